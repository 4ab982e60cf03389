// SPDX-License-Identifier: GPL-3.0-or-later
// Building the DEM state from the case configuration, and one time step as timed stages.
#include "simulation/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

#include "analysis/measures.hpp"
#include "analysis/mixing.hpp"
#include "boundaries/fill.hpp"
#include "contact/conduction.hpp"
#include "contact/pair_forces.hpp"
#include "contact/registry.hpp"
#include "contact/shape_forces.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/log.hpp"
#include "core/names.hpp"
#include "integrators/gear5.hpp"
#include "integrators/rigid_bodies.hpp"
#include "integrators/velocity_verlet.hpp"
#include "io/csv/csv.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/validate.hpp"
#include "io/vtk/vtk.hpp"
#include "simulation/shape_builder.hpp"

namespace gf {

namespace {

std::string where(const config::SourceLoc& loc) {
  if (loc.line > 0)
    return fmt::format("{}:{}:{}: {}", loc.file, loc.line, loc.column, loc.key_path);
  return loc.key_path.empty() ? loc.file : fmt::format("{}: {}", loc.file, loc.key_path);
}

RadiusDistribution to_distribution(const config::SizeDistribution& s) {
  RadiusDistribution d;
  d.kind = static_cast<RadiusDistribution::Kind>(static_cast<int>(s.kind));
  d.value = s.value;
  d.min = s.min;
  d.max = s.max;
  d.mean = s.mean;
  d.std = s.std;
  return d;
}

/// The index of the entry of a named list (outlets, flow meters, regions) that the series
/// quantity `quantity` = prefix + name is about (the reader checked that it exists).
template <class List>
std::size_t named(const List& list, const std::string& quantity, std::string_view prefix) {
  const std::string_view name = std::string_view(quantity).substr(prefix.size());
  std::size_t k = 0;
  while (k < list.size() && list[k].name != name) ++k;
  REQUIRE(k < list.size(), "no {} in the case", quantity);
  return k;
}

FillRegion to_region(const config::Region& r) {
  FillRegion g;
  g.kind = r.kind == config::Region::Kind::Box ? FillRegion::Kind::Box : FillRegion::Kind::Cylinder;
  g.min = r.min;
  g.max = r.max;
  g.center = r.center;
  g.axis = r.axis;
  g.radius = r.radius;
  g.height = r.height;
  return g;
}

FillSpec to_fill(const config::Fill& f) {
  FillSpec s;
  s.region = to_region(f.region);
  s.lattice = static_cast<FillSpec::Lattice>(static_cast<int>(f.lattice));
  s.spacing = f.spacing;
  s.count = f.count;
  s.max_attempts = f.max_attempts;
  return s;
}

/// World axis (unit) of a spherocylinder with orientation q (body axis e_z).
Vec3 capsule_axis_of(const Quat& q) {
  return contact::capsule_axis(q);
}

/// Size of a grain for the skin and the default neighbour parameters: the sphere or disk radius,
/// the cap radius of a spherocylinder, the equal-area radius of a polygon.
double contact_radius(const ParticleStore& p, std::size_t i) {
  if (!p.has_shapes()) return p.radius()[i];
  switch (static_cast<ShapeCode>(p.shape()[i])) {
    case ShapeCode::Spherocylinder:
      return p.radius()[i] - p.half_length()[i];
    case ShapeCode::Polygon:
      return p.polygons()[static_cast<std::size_t>(p.polygon()[i])].equivalent_radius;
    default:
      return p.radius()[i];
  }
}

/// The largest grain an inlet of group g inserts: its bounding radius and its contact radius
/// (contact_radius), from one such grain built in a scratch store.
std::pair<double, double> inlet_grain_radii(const config::ParticleGroup& g, double density,
                                            double thickness) {
  ParticleStore scratch;
  if (g.kind != config::Shape::Sphere && g.kind != config::Shape::Disk) scratch.enable_shapes();
  ShapeBuilder(g, density, thickness, 1).add(scratch, 0, 0, g.radius.largest(), {}, {}, {}, {});
  return {scratch.radius()[0], contact_radius(scratch, 0)};
}

/// The force on all fixed grains but their weight, N: the sum over fixed grains of f - m g (their
/// contacts with free grains and, in CFD-DEM runs, the fluid's force), serial so that it does not
/// depend on the thread count. Zero without fixed grains.
Vec3 fixed_grain_load(const ParticleStore& p, const Vec3& gravity) {
  const std::int32_t* fixed = p.fixed();
  Vec3 sum{};
  if (fixed == nullptr) return sum;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (fixed[i] != 0) sum += p.f()[i] - p.mass()[i] * gravity;
  return sum;
}

/// The rigid motion of a case's motion block (walls[].motion, particles[].fixed): translation
/// and start; axis, centre and rate when it rotates (else the defaults: at rest, no turn).
RigidMotion rigid_motion(const config::Motion& m) {
  RigidMotion r;
  r.velocity = m.velocity;
  r.start = m.start;
  if (m.rotates) {
    r.axis = m.axis;
    r.center = m.center;
    r.rate = m.rate;
  }
  return r;
}

}  // namespace

Simulation::Simulation(const config::Case& cfg) : cfg_(cfg) {
  REQUIRE(cfg.dimension == 2 || cfg.dimension == 3, "dimension must be 2 or 3");
  two_d_ = cfg.dimension == 2;
  gear_ = cfg.integrator == Gear5Integrator::key;
  domain_.lo = cfg.domain.min;
  domain_.hi = cfg.domain.max;
  domain_.periodic = cfg.domain.periodic;
  if (cfg.shear && cfg.shear->boundary == config::Shear::Boundary::LeesEdwards) {
    domain_.shear_gradient = 2;
    domain_.shear_flow = 0;
    domain_.shear_velocity = cfg.shear->rate * (domain_.hi.z - domain_.lo.z);
  }
  // Velocity Verlet moves the list's references with the wraps (step()); Gear's predictor wraps
  // on its own (and is refused in Lees-Edwards boxes), and moving fixed grains are placed
  // without it (also refused there): the allowance for crossings stays.
  nlist_.set_follow_wraps(!gear_ && domain_.sheared());
  gravity_ = cfg.gravity;
  dt_ = cfg.time.step;
  std::uint64_t seed = 1;
  for (const auto& g : cfg.particles)
    if (g.fill) {
      seed = g.fill->seed;
      break;
    }
  rng_ = Rng(seed);
  if (cfg.heat) {
    // (the reader refuses these with the line; a case built in code is checked here too)
    if (cfg.dimension == 2)
      throw InputError(fmt::format("{}: heat conduction is for 3D cases", where(cfg.heat->loc)));
    heat_model_ = contact::conduction_index(cfg.heat->model);
    if (heat_model_ < 0)
      throw InputError(
          fmt::format("{}: unknown conduction model '{}'", where(cfg.heat->loc), cfg.heat->model));
    f_temperature_ =
        particles_.add_field("temperature", FieldType::Real, "K", kRestart | kOutput | kGhost);
    // The net heat flow into each grain at the last step (contacts, walls, source), W.
    f_heat_flow_ = particles_.add_field("heat_flow", FieldType::Real, "W", kRestart | kOutput);
    if (std::any_of(cfg.particles.begin(), cfg.particles.end(),
                    [](const config::ParticleGroup& g) { return g.heat_source.has_value(); }))
      f_heat_source_ =
          particles_.add_field("heat_source", FieldType::Real, "W", kRestart | kOutput);
  }
  build_particles();
  build_materials_and_pairs();
  build_walls();
  if (cfg.heat) {
    std::vector<double> conductivity;
    for (const auto& m : cfg.materials) {
      conductivity.push_back(m.thermal_conductivity.value_or(0.0));
      heat_capacity_.push_back(m.heat_capacity.value_or(0.0));
    }
    const int nm = static_cast<int>(conductivity.size());
    k_series_ = PairTable<double>(nm);
    for (int a = 0; a < nm; ++a)
      for (int b = 0; b < nm; ++b)
        if (conductivity[static_cast<std::size_t>(a)] > 0 &&
            conductivity[static_cast<std::size_t>(b)] > 0)
          k_series_(a, b) = contact::series_conductivity(conductivity[static_cast<std::size_t>(a)],
                                                         conductivity[static_cast<std::size_t>(b)]);
    std::vector<bool> used(materials_.size(), false);
    for (std::size_t i = 0; i < particles_.size(); ++i)
      used[static_cast<std::size_t>(particles_.material()[i])] = true;
    for (const auto& in : cfg.particles)
      for (std::size_t m = 0; m < materials_.size(); ++m)
        if (materials_[m].name == in.material) used[m] = true;
    for (std::size_t m = 0; m < materials_.size(); ++m)
      if (used[m] && !(conductivity[m] > 0 && heat_capacity_[m] > 0))
        throw InputError(fmt::format(
            "{}: material '{}' of particles needs thermal_conductivity and heat_capacity for heat "
            "conduction",
            where(cfg.materials[m].loc), cfg.materials[m].name));
    for (const auto& w : walls_)
      if (!std::isnan(w.temperature) && !(conductivity[static_cast<std::size_t>(w.material)] > 0))
        throw InputError(fmt::format(
            "{}: wall '{}' has a temperature but its material '{}' no "
            "thermal_conductivity",
            cfg.file.string(), w.name, materials_[static_cast<std::size_t>(w.material)].name));
  }
  for (const auto& o : cfg.outlets) {
    outlet_regions_.push_back(to_region(o.region));
    outlet_reinsert_.push_back(o.reinsert ? std::optional(to_region(*o.reinsert)) : std::nullopt);
  }
  outlet_tallies_.assign(outlet_regions_.size(), OutletTally{});
  meter_tallies_.assign(cfg.flow_meters.size(), FlowMeterTally{});
  for (std::size_t g = 0; g < cfg.particles.size(); ++g) {
    const auto& group = cfg.particles[g];
    if (!group.inlet) continue;
    InletState s;
    s.group = g;
    s.region = to_region(group.inlet->region);
    for (std::size_t m = 0; m < materials_.size(); ++m)
      if (materials_[m].name == group.material) s.material = static_cast<int>(m);
    s.rate = group.inlet->rate;
    s.mass_rate = group.inlet->mass_rate.value_or(0.0);
    s.start = group.inlet->start;
    s.stop = group.inlet->stop.value_or(std::numeric_limits<double>::infinity());
    s.every = group.inlet->every;
    s.velocity = group.inlet->velocity;
    inlets_.push_back(s);
  }

  double r_max = 0, r_contact = 0, r_contact_free = 0;
  const std::int32_t* fixed = particles_.fixed();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    r_max = std::max(r_max, particles_.radius()[i]);
    r_contact = std::max(r_contact, contact_radius(particles_, i));
    if (fixed == nullptr || fixed[i] == 0)
      r_contact_free = std::max(r_contact_free, contact_radius(particles_, i));
  }
  // Half the largest contact radius: for spheres the usual skin; elongated grains get a skin
  // sized by their thickness, not by their (rotation-invariant) bounding sphere. The skin
  // bounds how far grains move between list builds, so fixed grains (which never move) do not
  // count: a large fixed obstacle does not inflate the lists of small free grains.
  for (const auto& in : inlets_) {  // (the groups start empty: their largest grain)
    const auto [bounding, contact] = inlet_grain_radii(
        cfg.particles[in.group], materials_[static_cast<std::size_t>(in.material)].density,
        cfg.domain.thickness);
    r_max = std::max(r_max, bounding);
    r_contact = std::max(r_contact, contact);
    r_contact_free = std::max(r_contact_free, contact);
  }
  if (r_contact_free > 0) r_contact = r_contact_free;
  skin_ = cfg.neighbor.skin.value_or(0.5 * r_contact > 0 ? 0.5 * r_contact : 1e-3);
  if (two_d_) {
    // Grains lie in z = 0; the cell grid needs a (one-cell) extent along z.
    const double h = std::max(2 * r_max + skin_, 1e-3);
    domain_.lo.z = -h;
    domain_.hi.z = h;
    domain_.periodic[2] = false;
  }
  const Vec3 L = domain_.length();
  for (int k = 0; k < 3; ++k) {
    if (domain_.periodic[k] && L[k] <= 2 * (2 * r_max + skin_))
      throw InputError(fmt::format(
          "{}: the periodic length along {} ({} m) must exceed twice the neighbour cutoff "
          "2 (2 r_max + skin) = {} m",
          where(cfg.domain.loc), "xyz"[k], L[k], 2 * (2 * r_max + skin_)));
  }
  if (cfg.shear && cfg.shear->initial_profile) {
    // Start on the mean flow u_x = rate (z - z_mid) (added to the fill velocities): steady
    // shear is then reached in a few strain units instead of growing in from the walls.
    const double zmid = 0.5 * (domain_.lo.z + domain_.hi.z);
    for (std::size_t i = 0; i < particles_.size(); ++i)
      if (fixed == nullptr || fixed[i] == 0)  // fixed grains stay at rest
        particles_.v()[i].x += cfg.shear->rate * (particles_.x()[i].z - zmid);
  }
  if (cfg.analysis.rheology) {
    const auto& rc = *cfg.analysis.rheology;
    const double margin = rc.margin.value_or(walls_.empty() ? 0.0 : 2 * r_max);
    rheo_region_.z_lo = domain_.lo.z + margin;
    rheo_region_.z_hi = domain_.hi.z - margin;
    rheo_region_.bins = rc.bins;
    rheo_region_.area = L.x * L.y;
    if (!(rheo_region_.z_hi > rheo_region_.z_lo))
      throw InputError(fmt::format(
          "{}: the rheology layer is empty: the margin {} m (default: one grain length next to "
          "walls) leaves nothing of the box height {} m",
          where(rc.loc), margin, L.z));
  }
  const double t0 = 0.0;
  for (auto& w : walls_) w.update_geometry(t0);
  place_fixed_groups(t0);  // (moving fixed groups: their velocities at t = 0)
  RigidBodies::init_angular_momentum(particles_);
  if (gear_) Gear5Integrator::enable(particles_);
  if (cfg.fluid && cfg.coupling) {
    // The first fluid step (over the first `interval` DEM steps) from the initial grains; its
    // drag then acts from the first force evaluation on (docs/models/cfd_dem.md).
    cfd_ = std::make_unique<CfdDemCoupling>(cfg, particles_, dt_);
    cfd_->fluid_step(particles_);
  }
  update_neighbors(true);
  // The initial state's contacts, if a run writes them (written at step 0 with the others).
  collect_contacts_ = cfg.output.contacts_csv.every > 0 || cfg.output.contacts_vtk.every > 0;
  compute_forces();
  collect_contacts_ = false;
  if (gear_) Gear5Integrator::start(particles_);
}

void Simulation::build_particles() {
  std::map<std::string, int> mat_index;
  for (std::size_t m = 0; m < cfg_.materials.size(); ++m)
    mat_index[cfg_.materials[m].name] = static_cast<int>(m);
  bool polygons = false, capsules = false;
  for (const auto& g : cfg_.particles) {
    polygons |= g.kind == config::Shape::Polygon;
    capsules |= g.kind == config::Shape::Spherocylinder;
  }
  if (gear_ && capsules)
    throw InputError(fmt::format(
        "{}: integrator 'gear5' is not available with spherocylinders (their rotation needs the "
        "rigid-body step of velocity_verlet); use integrator: velocity_verlet",
        cfg_.file.string()));
  if (polygons || capsules) particles_.enable_shapes();
  // Fixed groups: the store carries the flag (checkpoints, ghosts, outputs) only when some
  // group has it, so that other runs' memory and files stay as they were.
  const bool any_fixed = std::any_of(cfg_.particles.begin(), cfg_.particles.end(),
                                     [](const config::ParticleGroup& g) { return g.fixed; });
  if (any_fixed) particles_.enable_fixed();
  // Moving fixed groups: their grains' reference state (position, orientation at t = 0), which
  // their motions carry analytically (place_fixed_groups); only in runs that have one.
  const bool any_moving = std::any_of(cfg_.particles.begin(), cfg_.particles.end(),
                                      [](const config::ParticleGroup& g) { return g.motion; });
  if (any_moving) {
    if (cfg_.shear && cfg_.shear->boundary == config::Shear::Boundary::LeesEdwards)
      throw InputError(fmt::format(
          "{}: a fixed group with a prescribed motion is not available in a Lees-Edwards shear "
          "box; expected fixed: true (grains at rest) or shear boundary: walls",
          cfg_.file.string()));
    particles_.enable_fixed_motion();
  }
  // Spherocylinders: one contact per end with planes and cylinders, up to eight per triangle of
  // a mesh wall (boundaries/triangle_mesh.hpp).
  const bool mesh_walls = std::any_of(cfg_.walls.begin(), cfg_.walls.end(), [](const auto& w) {
    return w.kind == config::Wall::Kind::Mesh;
  });
  if (capsules) wlist_.set_slots(mesh_walls ? TriangleMesh::capsule_slots : 2);
  has_mesh_walls_ = mesh_walls;
  has_capsules_ = capsules;

  std::vector<FilledSphere> placed;
  std::int64_t next_id = 1;
  for (std::size_t gi = 0; gi < cfg_.particles.size(); ++gi) {
    const auto& g = cfg_.particles[gi];
    auto it = mat_index.find(g.material);
    if (it == mat_index.end())
      throw InputError(fmt::format("{}: unknown material '{}'", where(g.loc), g.material));
    const int mat = it->second;
    const double rho = cfg_.materials[static_cast<std::size_t>(mat)].density;
    const RadiusDistribution dist = to_distribution(g.radius);
    const std::uint64_t seed = g.fill ? g.fill->seed : 1 + gi;
    ShapeBuilder builder(g, rho, cfg_.domain.thickness, seed);
    if (cfg_.heat) {
      builder.set_temperature(g.temperature.value_or(cfg_.heat->temperature));
      builder.set_heat_source(g.heat_source.value_or(0.0));
    }
    const bool round = g.kind == config::Shape::Sphere || g.kind == config::Shape::Disk;
    if (g.motion && !g.fixed)
      throw InputError(
          fmt::format("{}: a prescribed motion is for fixed groups (fixed: {{translate, rotate}})",
                      where(g.loc)));
    if (g.fixed) {
      // The reader refuses these (with the line); a case built in code is checked here too.
      const bool moving_fill =
          g.fill && (!(g.fill->velocity == Vec3{}) || g.fill->velocity_jitter > 0);
      bool moving_explicit = false;
      if (g.explicit_particles) {
        for (const auto& v : g.explicit_particles->velocities) moving_explicit |= !(v == Vec3{});
        for (const auto& w : g.explicit_particles->angular_velocities)
          moving_explicit |= !(w == Vec3{});
      }
      if (moving_fill || moving_explicit)
        throw InputError(fmt::format(
            "{}: the grains of a fixed group {}; expected no initial velocities", where(g.loc),
            g.motion ? "take their velocities from its prescribed motion" : "stay at rest"));
    }
    const std::size_t first = particles_.size();
    if (g.fill) {
      Rng rng(g.fill->seed);
      FillSpec spec = to_fill(*g.fill);
      spec.two_d = two_d_;
      if (g.fill->volume_fraction) {
        spec.count = input::volume_fraction_count(*g.fill, g, cfg_.dimension);
        spec.pick_random = true;
      }
      if (!round && g.fill->lattice == config::Fill::Lattice::Cubic)
        spec.extent = input::grain_extent(*g.fill, g, g.radius.largest());
      // Round grains are placed with their own radii; other shapes by a sphere that holds any
      // orientation of the largest grain, and their size is drawn afterwards.
      RadiusDistribution place = dist;
      if (!round) {
        place.kind = RadiusDistribution::Kind::Fixed;
        place.value = builder.placement_radius();
      }
      const auto spheres = [&] {
        try {
          return generate_fill(spec, place, rng, placed);
        } catch (const InputError& e) {  // (the fill's own message, at the fill's place)
          throw InputError(fmt::format("{}: {}", where(g.fill->loc), e.what()));
        }
      }();
      if (spheres.empty())
        throw InputError(fmt::format("{}: the fill region holds no grain of bounding radius {} m",
                                     where(g.loc), place.largest()));
      if (g.fill->volume_fraction && static_cast<std::int64_t>(spheres.size()) < *spec.count)
        throw InputError(fmt::format(
            "{}: the lattice has {} sites, fewer than the {} grains volume_fraction {} asks for",
            where(g.fill->loc), spheres.size(), *spec.count, *g.fill->volume_fraction));
      particles_.reserve(particles_.size() + spheres.size());  // exact size, no growth slack
      for (const auto& s : spheres) {
        Vec3 v = g.fill->velocity;
        if (g.fill->velocity_jitter > 0)
          for (int k = 0; k < (two_d_ ? 2 : 3); ++k)
            v[k] += rng.uniform(-g.fill->velocity_jitter, g.fill->velocity_jitter);
        const double size = round ? s.r : dist.sample(rng);
        Quat q;
        if (!round)
          q = g.fill->orientation ? *g.fill->orientation
                                  : ShapeBuilder::random_orientation(rng, two_d_);
        const std::size_t i = builder.add(particles_, next_id++, mat, size, s.x, v, {}, q);
        placed.push_back({s.x, particles_.radius()[i]});
      }
    }
    if (g.explicit_particles) {
      const auto& e = *g.explicit_particles;
      particles_.reserve(particles_.size() + e.positions.size());
      for (std::size_t k = 0; k < e.positions.size(); ++k) {
        const double r = e.radii.empty() ? dist.largest() : e.radii[k];
        const Vec3 v = e.velocities.empty() ? Vec3{} : e.velocities[k];
        const Vec3 w = e.angular_velocities.empty() ? Vec3{} : e.angular_velocities[k];
        const Quat q = e.orientations.empty() ? Quat{} : e.orientations[k];
        const std::size_t i = builder.add(particles_, next_id++, mat, r, e.positions[k], v, w, q);
        placed.push_back({e.positions[k], particles_.radius()[i]});
      }
    }
    if (g.fixed) {
      std::int32_t flag = ParticleStore::kFixedAtRest;
      if (g.motion) {
        flag = ParticleStore::kFixedMoving + static_cast<std::int32_t>(fixed_motions_.size());
        fixed_motions_.push_back({rigid_motion(*g.motion), g.motion->rotates});
      }
      for (std::size_t i = first; i < particles_.size(); ++i) {
        particles_.fixed()[i] = flag;
        if (!g.motion) continue;
        particles_.fixed_x0()[i] = particles_.x()[i];
        if (particles_.has_shapes()) particles_.fixed_q0()[i] = particles_.orientation()[i];
      }
    }
  }
  next_id_ = next_id;
  log::info("{} particles", particles_.size());
}

void Simulation::build_materials_and_pairs() {
  const int nm = static_cast<int>(cfg_.materials.size());
  std::map<std::string, int> mat_index;
  for (int m = 0; m < nm; ++m) {
    const auto& c = cfg_.materials[static_cast<std::size_t>(m)];
    materials_.push_back({c.name, c.density, c.youngs_modulus, c.poisson_ratio});
    mat_index[c.name] = m;
  }
  // Largest grain radius of each material: the reference size of derived stiffnesses.
  std::vector<double> r_ref(static_cast<std::size_t>(nm), 0.0);
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    auto& rr = r_ref[static_cast<std::size_t>(particles_.material()[i])];
    rr = std::max(rr, particles_.radius()[i]);
  }
  for (const auto& g : cfg_.particles)  // (an inlet's group starts empty: its largest grain)
    if (g.inlet) {
      const int m = mat_index.at(g.material);
      auto& rr = r_ref[static_cast<std::size_t>(m)];
      rr = std::max(rr, inlet_grain_radii(g, materials_[static_cast<std::size_t>(m)].density,
                                          cfg_.domain.thickness)
                            .first);
    }
  pairs_ = PairTable<contact::PairCoeffs>(nm);
  for (const auto& c : cfg_.contacts) {
    const auto a = mat_index.find(c.between[0]), b = mat_index.find(c.between[1]);
    if (a == mat_index.end() || b == mat_index.end())
      throw InputError(fmt::format("{}: unknown material in 'between'", where(c.loc)));
    contact::PairContext ctx{&materials_[static_cast<std::size_t>(a->second)],
                             &materials_[static_cast<std::size_t>(b->second)],
                             std::max(r_ref[static_cast<std::size_t>(a->second)],
                                      r_ref[static_cast<std::size_t>(b->second)])};
    try {
      contact::PairCoeffs pc = contact::prepare_pair(c.model, ctx, c.params);
      pairs_.set(a->second, b->second, pc);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw InputError(fmt::format("{}: {}", where(c.loc), e.what()));
    }
  }
  // Every pair of materials that can meet needs a law.
  std::vector<bool> used(static_cast<std::size_t>(nm), false);
  for (std::size_t i = 0; i < particles_.size(); ++i)
    used[static_cast<std::size_t>(particles_.material()[i])] = true;
  for (const auto& g : cfg_.particles)
    if (g.inlet) used[static_cast<std::size_t>(mat_index.at(g.material))] = true;
  for (int a = 0; a < nm; ++a)
    for (int b = a; b < nm; ++b)
      if (used[static_cast<std::size_t>(a)] && used[static_cast<std::size_t>(b)] &&
          pairs_(a, b).model < 0)
        throw InputError(fmt::format("{}: no entry in 'contacts' for the material pair [{}, {}]",
                                     cfg_.file.string(),
                                     materials_[static_cast<std::size_t>(a)].name,
                                     materials_[static_cast<std::size_t>(b)].name));
  // Cohesion has no area for a polygon contact (the reader refuses it at the key; a case built in
  // code is checked here too).
  for (const auto& c : cfg_.contacts) {
    const auto it = c.params.find("cohesion_energy_density");
    if (it == c.params.end() || !(it->second > 0)) continue;
    for (const auto& g : cfg_.particles)
      if (g.kind == config::Shape::Polygon &&
          (g.material == c.between[0] || g.material == c.between[1]))
        throw InputError(fmt::format(
            "{}: cohesion_energy_density > 0 for [{}, {}], a material of polygon grains: cohesion "
            "is available for spheres, spherocylinders and disks only",
            where(c.loc), c.between[0], c.between[1]));
  }
}

void Simulation::build_walls() {
  std::map<std::string, int> mat_index;
  for (std::size_t m = 0; m < materials_.size(); ++m)
    mat_index[materials_[m].name] = static_cast<int>(m);
  std::vector<bool> used(materials_.size(), false);
  for (std::size_t i = 0; i < particles_.size(); ++i)
    used[static_cast<std::size_t>(particles_.material()[i])] = true;
  for (const auto& wc : cfg_.walls) {
    auto it = mat_index.find(wc.material);
    if (it == mat_index.end())
      throw InputError(fmt::format("{}: unknown material '{}'", where(wc.loc), wc.material));
    for (std::size_t m = 0; m < materials_.size(); ++m)
      if (used[m] && pairs_(static_cast<int>(m), it->second).model < 0)
        throw InputError(fmt::format("{}: no entry in 'contacts' for the material pair [{}, {}]",
                                     where(wc.loc), materials_[m].name, wc.material));
    Wall w;
    w.name = wc.name;
    w.group = wc.name;
    w.material = it->second;
    w.motion = rigid_motion(wc.motion);
    if (wc.temperature) w.temperature = *wc.temperature;
    if (wc.servo) {
      w.servo = true;
      w.servo_max_velocity = wc.servo->max_velocity;
      w.servo_until = wc.servo->until.value_or(1e300);
      w.servo_gain = wc.servo->gain;
      w.servo_pressure = wc.servo->pressure;  // spans resolved once all walls exist (below)
    }
    if (wc.motion.rotates) {
      // (axis, centre and rate: rigid_motion)
    } else if (wc.kind == config::Wall::Kind::Mesh) {  // torques about the box centre of the mesh
      Vec3 lo = wc.mesh_points[0], hi = wc.mesh_points[0];
      for (const auto& q : wc.mesh_points)
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], q[k]);
          hi[k] = std::max(hi[k], q[k]);
        }
      w.motion.center = 0.5 * (lo + hi);
    } else {
      w.motion.center = wc.kind == config::Wall::Kind::Cylinder ? wc.center : wc.point;
    }
    switch (wc.kind) {
      case config::Wall::Kind::Plane:
        w.kind = WallKind::Plane;
        w.point0 = wc.point;
        w.dir0 = wc.normal;
        walls_.push_back(w);
        break;
      case config::Wall::Kind::Cylinder:
        w.kind = WallKind::Cylinder;
        w.point0 = wc.center;
        w.dir0 = wc.axis;
        w.radius = wc.radius;
        w.inside = wc.inside;
        walls_.push_back(w);
        break;
      case config::Wall::Kind::Mesh: {
        // (the reader refuses these; a case built in code is checked here too)
        if (two_d_)
          throw InputError(fmt::format(
              "{}: mesh walls are 3D surfaces, not available in 2D; use plane or box walls",
              where(wc.loc)));
        w.kind = WallKind::Mesh;
        w.mesh = TriangleMesh(wc.mesh_points, wc.mesh_triangles);
        // The reference point is the motion centre (torques are about it); dir0 normal to the
        // rotation axis, so that |dir - dir_b| measures the rotation (Wall::moved_since).
        w.point0 = w.motion.center;
        const Vec3 ax = w.motion.axis;
        w.dir0 = std::abs(ax.x) < 0.9 ? normalized(cross(ax, Vec3{1, 0, 0}))
                                      : normalized(cross(ax, Vec3{0, 1, 0}));
        w.radius = w.mesh.radius_about(w.point0);
        walls_.push_back(std::move(w));
        break;
      }
      case config::Wall::Kind::Box: {
        const auto& faces = kBoxFaceNames;
        for (int f = 0; f < 6; ++f) {
          if (std::find(wc.open.begin(), wc.open.end(), faces[f]) != wc.open.end()) continue;
          if (two_d_ && f >= 4) continue;  // 2D: the grains lie in z = 0, no z faces
          Wall p = w;
          p.kind = WallKind::Plane;
          p.name = wc.name + "." + std::string(faces[f]);
          const int axis = f / 2;
          const bool lo = (f % 2) == 0;
          p.point0 = lo ? wc.min : wc.max;
          p.dir0 = {};
          p.dir0[axis] = lo ? 1.0 : -1.0;
          if (!wc.motion.rotates) p.motion.center = p.point0;
          walls_.push_back(p);
        }
        break;
      }
    }
  }
  // Servo spans by index (the parser checked that they name plane walls of the case).
  for (const auto& wc : cfg_.walls) {
    if (!wc.servo) continue;
    auto index_of = [&](const std::string& name) {
      for (std::size_t k = 0; k < walls_.size(); ++k)
        if (walls_[k].name == name) return static_cast<std::int32_t>(k);
      throw InputError(fmt::format("{}: servo span names no wall '{}'", where(wc.loc), name));
    };
    const std::int32_t self = index_of(wc.name);
    for (const auto& pr : wc.servo->spans)
      walls_[static_cast<std::size_t>(self)].servo_spans.push_back(
          {index_of(pr[0]), index_of(pr[1])});
  }
}

double Simulation::servo_target_force(std::size_t w) const {
  const Wall& wall = walls_[w];
  double area = two_d_ ? cfg_.domain.thickness : 1.0;
  for (const auto& [ia, ib] : wall.servo_spans) {
    const Wall& a = walls_[static_cast<std::size_t>(ia)];
    area *= std::abs(dot(a.point - walls_[static_cast<std::size_t>(ib)].point, a.dir));
  }
  return wall.servo_pressure * area;
}

void Simulation::update_servos() {
  for (std::size_t w = 0; w < walls_.size(); ++w)
    if (walls_[w].servo) walls_[w].servo_step(time(), dt_, servo_target_force(w));
}

void Simulation::place_fixed_groups(double t) {
  if (fixed_motions_.empty()) return;
  ParticleStore& p = particles_;
  const std::int32_t* fixed = p.fixed();
  const Vec3* x0 = p.fixed_x0();
  const Quat* q0 = p.fixed_q0();  // null without shapes
  Vec3* x = p.x();
  Vec3* v = p.v();
  Vec3* w = p.omega();
  Quat* q = p.has_shapes() ? p.orientation() : nullptr;
  Vec3* L = p.has_shapes() ? p.angular_momentum() : nullptr;
  const std::int32_t* shape = p.has_shapes() ? p.shape() : nullptr;
  const Vec3* inertia = p.has_shapes() ? p.inertia_body() : nullptr;
  const FixedMotion* motions = fixed_motions_.data();
  const bool periodic = domain_.any_periodic();
  // The displacements since the list build join the drift's rebuild test (a moving fixed grain
  // must trigger a rebuild as a free one does); without the drift's measure (Gear, shapes) the
  // test reads the positions themselves.
  const auto ref = nlist_.reference_positions();
  const bool track = drift_max_d2_ >= 0 && ref.size() == p.size();
  const double max_d2 =
      exec::parallel_max(static_cast<exec::index_t>(p.size()), 0.0, [&](exec::index_t i) {
        const std::int32_t k = fixed[i] - ParticleStore::kFixedMoving;
        if (k < 0) return 0.0;
        const RigidMotion& m = motions[k].motion;
        const Vec3 at = m.carry(x0[i], t);  // not wrapped: the rigid body's own point
        x[i] = at;
        if (periodic) domain_.wrap(x[i]);
        v[i] = m.velocity_at(at, t);
        w[i] = m.omega();
        if (q != nullptr) {
          q[i] = m.turn(q0[i], t);
          if (static_cast<ShapeCode>(shape[i]) == ShapeCode::Spherocylinder) {
            // L = R I_body R^T omega, as RigidBodies keeps it for free rods.
            const Vec3 wb = rotate_inverse(q[i], w[i]);
            const Vec3& I = inertia[i];
            L[i] = rotate(q[i], Vec3{I.x * wb.x, I.y * wb.y, I.z * wb.z});
          }
        }
        return track ? norm2(domain_.delta(x[i], ref[static_cast<std::size_t>(i)])) : 0.0;
      });
  if (track) drift_max_d2_ = std::max(drift_max_d2_, max_d2);
}

Vec3 Simulation::fixed_group_torque() const {
  // Serial, so that it does not depend on the thread count (as fixed_grain_load).
  const ParticleStore& p = particles_;
  Vec3 sum{};
  if (fixed_motions_.empty()) return sum;
  const double t = time();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::int32_t k = p.fixed()[i] - ParticleStore::kFixedMoving;
    if (k < 0 || !fixed_motions_[static_cast<std::size_t>(k)].rotates) continue;
    const RigidMotion& m = fixed_motions_[static_cast<std::size_t>(k)].motion;
    const Vec3 arm = m.carry(p.fixed_x0()[i], t) - m.center_at(t);
    sum += cross(arm, p.f()[i] - p.mass()[i] * gravity_) + p.torque()[i];
  }
  return sum;
}

void Simulation::build_pair_gaps() {
  // Between Lees-Edwards images a pair's image slides until the next build: the force loop takes
  // the slide since this offset off the gaps (PairSkip::slide).
  pair_gap_.clear();
  end_moved_.clear();
  gap_offset_ = domain_.shear_offset;
  const auto& p = particles_;
  const auto off = nlist_.offsets();
  const auto nb = nlist_.neighbors();
  pair_gap_.resize(nb.size());
  end_moved_.assign(p.size(), 0.0);
  exec::parallel_for(static_cast<exec::index_t>(nlist_.n_particles()), [&](exec::index_t i) {
    const Vec3 xi = p.x()[i];
    const Vec3 ai = axis_ref_[static_cast<std::size_t>(i)];
    const double ri = p.radius()[i] - p.half_length()[i];
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const std::int32_t j = nb[k];
      const Vec3 xj = xi - domain_.delta(xi, p.x()[j]);  // as the force loop's image
      const Vec3 aj = axis_ref_[static_cast<std::size_t>(j)];
      const auto sc = contact::closest_points_segments(xi - ai, xi + ai, xj - aj, xj + aj);
      // Less a margin of round-off (the force loop's own segment test rounds differently).
      pair_gap_[static_cast<std::size_t>(k)] = std::sqrt(sc.dist2) - ri -
                                               (p.radius()[j] - p.half_length()[j]) -
                                               1e-9 * (ri + p.radius()[j]);
    }
  });
}

const Vec3* Simulation::wall_half_axes() {
  if (!has_capsules_ || !has_mesh_walls_) return nullptr;
  const auto& p = particles_;
  half_axes_.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    half_axes_[i] = p.half_length()[i] * capsule_axis_of(p.orientation()[i]);
  return half_axes_.data();
}

bool Simulation::capsule_ends_moved() const {
  // A point of a capsule's axis moves by a convex combination of the moves of its two ends, so
  // if both ends moved less than skin/2, no pair left out of the list can have come into
  // contact (see update_neighbors).
  const auto& p = particles_;
  const auto x_ref = nlist_.reference_positions();
  if (axis_ref_.size() != p.size() || x_ref.size() != p.size()) return true;
  const double lim = nlist_.displacement_limit(domain_);
  if (lim <= 0) return true;
  const double lim2 = lim * lim;
  // Every grain's largest end move (spheres: the centre's) is kept for the force loop's skip
  // (contact::PairSkip), so the pass does not stop at the first grain beyond the limit.
  end_moved_.resize(p.size());
  return exec::parallel_sum(static_cast<exec::index_t>(p.size()), std::int64_t{0},
                            [&](exec::index_t i) -> std::int64_t {
                              const auto k = static_cast<std::size_t>(i);
                              const Vec3 d = domain_.delta(p.x()[i], x_ref[k]);
                              const Vec3 da =
                                  p.half_length()[i] * capsule_axis_of(p.orientation()[i]) -
                                  axis_ref_[k];
                              const double m2 = std::max(norm2(d + da), norm2(d - da));
                              end_moved_[k] = std::sqrt(m2);
                              return m2 > lim2 ? 1 : 0;
                            }) > 0;
}

void Simulation::count_meter_crossings() {
  StageTimers::Scope timer(timers_, Stage::Integrate);
  const std::size_t n = particles_.size();
  const Vec3* x = particles_.x();
  if (meter_x_.size() != n) {  // (never after a build or restart; a start without one)
    meter_x_.assign(x, x + n);
    return;
  }
  const std::int32_t* fixed = particles_.fixed();
  const double* mass = particles_.mass();
  // In a box without periodic images the sides are plain signed distances, a short loop with
  // one rarely taken branch (most grains cross nothing in a step).
  const bool images = domain_.any_periodic() || domain_.sheared();
  for (std::size_t k = 0; k < meter_tallies_.size(); ++k) {
    const config::FlowMeter& f = cfg_.flow_meters[k];
    const Vec3 p = f.point, nrm = f.normal;
    const double r2 = f.radius ? *f.radius * *f.radius : std::numeric_limits<double>::infinity();
    FlowMeterTally& t = meter_tallies_[k];
    const auto crossed = [&](std::size_t i, const Vec3& rel, const Vec3& d, double s0, double s1) {
      if (fixed != nullptr && fixed[i] != 0) return;
      const Vec3 c = rel + (s0 / (s0 - s1)) * d;  // where the centre crossed, from the point
      if (norm2(c - dot(c, nrm) * nrm) > r2) return;
      const bool forward = s0 < 0;
      t.count += forward ? 1 : -1;
      t.mass += forward ? mass[i] : -mass[i];
    };
    if (!images) {
      const double c0 = dot(p, nrm);
      for (std::size_t i = 0; i < n; ++i) {
        const double s0 = dot(meter_x_[i], nrm) - c0, s1 = dot(x[i], nrm) - c0;
        if ((s0 < 0) != (s1 < 0)) crossed(i, meter_x_[i] - p, x[i] - meter_x_[i], s0, s1);
      }
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) {
      // The side of the plane's nearest image before, and the displacement (minimum image: a
      // wrap through a periodic boundary is the short step it is) after.
      const Vec3 rel = domain_.delta(meter_x_[i], p);
      const Vec3 d = domain_.delta(x[i], meter_x_[i]);
      const double s0 = dot(rel, nrm), s1 = s0 + dot(d, nrm);
      if ((s0 < 0) != (s1 < 0)) crossed(i, rel, d, s0, s1);
    }
  }
  std::copy(x, x + n, meter_x_.begin());
}

analysis::LaceyIndex Simulation::lacey_index() const {
  REQUIRE(cfg_.analysis.mixing.has_value(), "lacey_index needs analysis.mixing");
  const config::Mixing& m = *cfg_.analysis.mixing;
  // The kind of each grain: 0 and 1 for the two materials, -1 for others and fixed grains.
  int mat[2] = {-1, -1};
  for (std::size_t k = 0; k < materials_.size(); ++k)
    for (int s = 0; s < 2; ++s)
      if (materials_[k].name == m.materials[static_cast<std::size_t>(s)])
        mat[s] = static_cast<int>(k);
  const std::size_t n = particles_.size();
  mixing_kind_.resize(n);
  const std::int32_t* fixed = particles_.fixed();
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t mi = particles_.material()[i];
    mixing_kind_[i] = (fixed != nullptr && fixed[i] != 0) ? -1
                      : mi == mat[0]                      ? 0
                      : mi == mat[1]                      ? 1
                                                          : -1;
  }
  return analysis::lacey_index(particles_.x(), mixing_kind_.data(), n, domain_.lo, domain_.hi,
                               m.cell, two_d_ ? 2 : 3, m.min_grains);
}

void Simulation::series_row_written() {
  reset_wall_means(WallMeans::Series);
  for (auto& t : meter_tallies_) {
    t.rate_at_row = t.rate(time());
    t.mass_at_row = t.mass;
    t.time_at_row = time();
  }
}

void Simulation::compact_polygon_table() {
  if (!particles_.has_shapes()) return;
  auto& table = particles_.polygons();
  // Only once most of the table is garbage (outlines of grains an outlet took): each entry is
  // then moved a bounded number of times on average, and short runs keep their indices.
  if (table.size() < 256) return;
  std::int32_t* poly = particles_.polygon();
  const std::size_t n = particles_.size();
  std::vector<std::int32_t> remap(table.size(), -1);
  for (std::size_t i = 0; i < n; ++i)
    if (poly[i] >= 0) remap[static_cast<std::size_t>(poly[i])] = 0;
  std::size_t used = 0;
  for (auto& r : remap)
    if (r == 0) r = static_cast<std::int32_t>(used++);
  if (2 * used > table.size()) return;
  std::vector<PolygonShape> kept;
  kept.reserve(used);
  for (std::size_t k = 0; k < table.size(); ++k)
    if (remap[k] >= 0) kept.push_back(table[k]);
  table = std::move(kept);
  for (std::size_t i = 0; i < n; ++i)
    if (poly[i] >= 0) poly[i] = remap[static_cast<std::size_t>(poly[i])];
}

std::vector<std::int64_t> Simulation::take_outlet_grains() {
  if (outlet_regions_.empty()) return {};
  const std::size_t n = particles_.size();
  const Vec3* x = particles_.x();
  const std::int32_t* fixed = particles_.fixed();
  // The grains left first, in their order, then those taken: one permutation and a shrink.
  std::vector<std::int64_t> order, taken;
  std::vector<std::vector<std::int64_t>> back(outlet_regions_.size());  // to reinsert
  order.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t k = 0;
    if (fixed == nullptr || fixed[i] == 0)
      while (k < outlet_regions_.size() && !outlet_regions_[k].contains(x[i], 0.0, two_d_)) ++k;
    else
      k = outlet_regions_.size();  // fixed grains stay
    if (k == outlet_regions_.size() || outlet_reinsert_[k]) {
      order.push_back(static_cast<std::int64_t>(i));
      if (k == outlet_regions_.size()) continue;
      back[k].push_back(static_cast<std::int64_t>(i));
    } else {
      taken.push_back(static_cast<std::int64_t>(i));
    }
    ++outlet_tallies_[k].count;
    outlet_tallies_[k].mass += particles_.mass()[i];
  }
  // A grain put back elsewhere is a new grain to the list build: it keeps its place in the store
  // but gets no index at the last build (-1), so that neither a pair history (two grains that
  // touched in the outlet and land side by side) nor a wall history (a grain that slid along a
  // wall into the outlet and lands against it again) of its old contacts is carried.
  std::vector<char> moved;
  for (std::size_t k = 0; k < back.size(); ++k) {
    if (back[k].empty()) continue;
    reinsert_grains(back[k], *outlet_reinsert_[k], cfg_.outlets[k].name);
    moved.resize(n, 0);
    for (const auto i : back[k]) moved[static_cast<std::size_t>(i)] = 1;
  }
  if (taken.empty() && moved.empty()) return {};
  const std::size_t left = order.size();
  if (!taken.empty()) {
    order.insert(order.end(), taken.begin(), taken.end());
    particles_.permute(order);
    particles_.resize(left);
    order.resize(left);
  }
  if (!moved.empty())
    for (auto& o : order)
      if (moved[static_cast<std::size_t>(o)]) o = -1;
  return order;
}

std::vector<std::size_t> Simulation::grains_near(const FillRegion& region, double reach) const {
  Vec3 lo, hi;
  region.bounds(lo, hi);
  std::vector<std::size_t> near;
  const Vec3* x = particles_.x();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    bool in = true;
    for (int k = 0; k < (two_d_ ? 2 : 3); ++k)
      in = in && x[i][k] > lo[k] - reach && x[i][k] < hi[k] + reach;
    if (in) near.push_back(i);
  }
  return near;
}

std::optional<Vec3> Simulation::free_place(const FillRegion& region, double r,
                                           const std::vector<std::size_t>& near, std::size_t self) {
  Vec3 lo, hi;
  region.bounds(lo, hi);
  const Vec3* x = particles_.x();
  const double* radius = particles_.radius();
  for (int attempt = 0; attempt < 1000; ++attempt) {
    Vec3 y;
    for (int k = 0; k < 3; ++k) y[k] = two_d_ && k == 2 ? 0.0 : rng_.uniform(lo[k], hi[k]);
    if (!region.contains(y, r, two_d_)) continue;
    const bool free = std::none_of(near.begin(), near.end(), [&](std::size_t j) {
      const double reach = r + radius[j];
      return j != self && norm2(domain_.delta(y, x[j])) < reach * reach;
    });
    if (free) return y;
  }
  return std::nullopt;
}

void Simulation::reinsert_grains(std::span<const std::int64_t> grains, const FillRegion& region,
                                 const std::string& outlet) {
  auto& p = particles_;
  double r_max = 0;
  for (std::size_t i = 0; i < p.size(); ++i) r_max = std::max(r_max, p.radius()[i]);
  // The grains that a grain placed in the region could touch (the moved ones join as they land).
  std::vector<std::size_t> near = grains_near(region, 2 * r_max);
  for (const std::int64_t g : grains) {
    const auto i = static_cast<std::size_t>(g);
    const auto y = free_place(region, p.radius()[i], near, i);
    if (!y)
      throw Error(fmt::format(
          "at t = {:.6g} s: outlet '{}' found no free place for a grain (r = {:g} m) in its "
          "reinsert region after 1000 tries: make the region larger",
          time(), outlet, p.radius()[i]));
    p.x()[i] = *y;
    p.v()[i] = {};
    p.omega()[i] = {};
    if (p.has_shapes()) p.angular_momentum()[i] = {};
    near.push_back(i);
  }
}

std::int64_t Simulation::inserted_grains() const {
  std::int64_t n = 0;
  for (const auto& in : inlets_) n += in.inserted;
  return n;
}

bool Simulation::InletState::due(double t) const {
  return t < stop && t >= start + static_cast<double>(batches) * every - 1e-9 * every;
}

bool Simulation::inlets_due() const {
  return std::any_of(inlets_.begin(), inlets_.end(),
                     [t = time()](const InletState& in) { return in.due(t); });
}

std::size_t Simulation::insert_inlet_grains() {
  const double t = time();
  const std::size_t before = particles_.size();
  for (auto& in : inlets_) {
    if (!in.due(t)) continue;
    in.batches = static_cast<std::int64_t>(std::floor((t - in.start) / in.every + 1e-9)) + 1;
    // The grains (or the mass) due by the end of this batch's interval (never past the stop).
    // By mass, grains come until the mass inserted reaches the mass due: each batch's last
    // grain overshoots by part of a grain, which the next batch owes less.
    const double until = std::min(t - in.start + in.every, in.stop - in.start);
    const auto due = static_cast<std::int64_t>(std::floor(in.rate * until + 1e-9));
    const double due_mass = in.mass_rate * until;
    const auto owed = [&] {
      return in.mass_rate > 0 ? in.inserted_mass < due_mass * (1 - 1e-12) : in.inserted < due;
    };
    const auto& g = cfg_.particles[in.group];
    const double rho = materials_[static_cast<std::size_t>(in.material)].density;
    // Random polygon outlines come from a generator seeded by the group and the batch: new
    // outlines every batch, the same ones in a run continued from a checkpoint (which keeps the
    // batch count and the outlines made so far). A batch's grains of one outline (given
    // vertices, regular polygons of one size) share one new entry of the outline table.
    ShapeBuilder builder(
        g, rho, cfg_.domain.thickness,
        (1 + in.group) * 0x9e3779b97f4a7c15ull + static_cast<std::uint64_t>(in.batches));
    if (cfg_.heat) {
      builder.set_temperature(g.temperature.value_or(cfg_.heat->temperature));
      builder.set_heat_source(g.heat_source.value_or(0.0));
    }
    const RadiusDistribution dist = to_distribution(g.radius);
    const bool round = g.kind == config::Shape::Sphere || g.kind == config::Shape::Disk;
    // Spherocylinders are placed by a sphere that holds any of them, as a fill places them.
    const double place = builder.placement_radius();
    double r_max = place;
    for (std::size_t i = 0; i < particles_.size(); ++i)
      r_max = std::max(r_max, particles_.radius()[i]);
    std::vector<std::size_t> near = grains_near(in.region, 2 * r_max);
    while (owed()) {
      const double r = dist.sample(rng_);
      const Quat q = round ? Quat{} : ShapeBuilder::random_orientation(rng_, two_d_);
      const auto y = free_place(in.region, round ? r : place, near, particles_.size());
      if (!y) {
        // The region is full: the rest waits for the next batch (the grains below move on).
        if (!inlet_short_warned_)
          log::warn(
              "at t = {:.6g} s: the inlet of particles[{}] found no free place for {} of its "
              "grains; they wait for its next batch (a larger region or a shorter 'every' keeps "
              "the rate)",
              t, in.group,
              in.mass_rate > 0 ? fmt::format("{:.4g} kg", due_mass - in.inserted_mass)
                               : fmt::format("{}", due - in.inserted));
        inlet_short_warned_ = true;
        break;
      }
      near.push_back(
          builder.add(particles_, next_id_++, in.material, r, *y, in.velocity, Vec3{}, q));
      ++in.inserted;
      in.inserted_mass += particles_.mass()[near.back()];
    }
  }
  return particles_.size() - before;
}

void Simulation::update_neighbors(bool force) {
  StageTimers::Scope timer(timers_, Stage::Neighbor);
  std::size_t n = particles_.size();
  const double max_d2 = drift_max_d2_;
  drift_max_d2_ = -1;  // measured for this step only
  bool rebuild = force || (max_d2 >= 0 ? nlist_.needs_rebuild(domain_, max_d2, n)
                                       : nlist_.needs_rebuild(domain_, particles_.x(), n));
  // A list built without re-ordering (a device run's checkpoint, docs/gpu.md) has no slabs, and
  // the force loop would run on one thread until the next build: build it sorted now.
  if (!rebuild && n > 0 && nlist_.n_slabs() == 0) rebuild = true;
  if (!rebuild && has_capsules_) rebuild = capsule_ends_moved();
  if (!rebuild && !inlets_.empty()) rebuild = inlets_due();  // new grains need a new list
  bool walls_moved = false;
  if (!rebuild && !walls_.empty()) {
    const double diag = norm(domain_.length());
    for (std::size_t w = 0; w < walls_.size() && !walls_moved; ++w) {
      const double moved =
          walls_[w].moved_since(wall_point_at_build_[w], wall_dir_at_build_[w], diag);
      walls_moved = moved > 0.5 * skin_;
    }
  }
  if (!rebuild && walls_moved) {
    // Only walls moved (e.g. a gate pulled away, a servo plate): rebuild the wall list alone.
    // Since the last full build every particle moved less than skin/2, so until the next one it
    // moves less than skin relative to now; with the walls' skin/2, a pair further apart than
    // 1.5 skin now cannot touch before the next rebuild.
    wlist_.build(walls_, particles_.x(), particles_.radius(), n, 1.5 * skin_, {}, wall_half_axes(),
                 particles_.fixed());
    for (std::size_t w = 0; w < walls_.size(); ++w) {
      wall_point_at_build_[w] = walls_[w].point;
      wall_dir_at_build_[w] = walls_[w].dir;
    }
    return;
  }
  if (!rebuild) return;
  // Grains reach the outlets between builds; they are taken at the next build (within the
  // skin's travel of any grain), where the lists are made anew anyway.
  auto previous = take_outlet_grains();
  if (!previous.empty()) compact_polygon_table();
  const std::size_t kept = particles_.size();
  if (const std::size_t added = insert_inlet_grains(); added > 0) {
    // The new grains had no index at the last build.
    if (previous.empty()) {
      previous.resize(kept);
      std::iota(previous.begin(), previous.end(), std::int64_t{0});
    }
    previous.resize(kept + added, -1);
  }
  n = particles_.size();
  // Re-ordering the particles by cell at every rebuild keeps neighbours close in memory and
  // gives the slabs the threaded force loop needs.
  // Spherocylinders: the bounding spheres of elongated grains overlap far more often than the
  // grains (aspect ratio 4: ~18 candidates per rod, ~2 contacts), so the list keeps only pairs
  // whose axes come closer than r_i + r_j + skin; the rebuild criterion then also watches the
  // ends of every capsule (capsule_ends_moved).
  // Two fixed grains never interact (parts of one immobile base: the force between them would
  // move nothing, and would count in the contacts, the elastic energy and the stresses), so the
  // list leaves their pairs out.
  PairFilter filter;
  if (has_capsules_)
    filter = [this](std::int32_t i, std::int32_t j) {
      const auto& p = particles_;
      const double hi = p.half_length()[i], hj = p.half_length()[j];
      if (hi == 0 && hj == 0) return true;  // two spheres: the bounding test was exact
      const Vec3 xi = p.x()[i];
      const Vec3 xj = xi - domain_.delta(xi, p.x()[j]);
      const Vec3 ai = hi * capsule_axis_of(p.orientation()[i]);
      const Vec3 aj = hj * capsule_axis_of(p.orientation()[j]);
      const auto sc = contact::closest_points_segments(xi - ai, xi + ai, xj - aj, xj + aj);
      const double reach = p.radius()[i] - hi + p.radius()[j] - hj + skin_;
      return sc.dist2 < reach * reach;
    };
  if (particles_.has_fixed())
    filter = [this, shapes = std::move(filter)](std::int32_t i, std::int32_t j) {
      const std::int32_t* fixed = particles_.fixed();  // (re-ordered by the build: read now)
      if (fixed[i] != 0 && fixed[j] != 0) return false;
      return !shapes || shapes(i, j);
    };
  const auto perm = nlist_.sort_and_build(particles_, domain_, skin_, filter, previous);
  if (has_capsules_) {
    axis_ref_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      axis_ref_[i] = particles_.half_length()[i] * capsule_axis_of(particles_.orientation()[i]);
    build_pair_gaps();
  }
  wlist_.build(walls_, particles_.x(), particles_.radius(), n, skin_, perm, wall_half_axes(),
               particles_.fixed());
  if (!meter_tallies_.empty()) meter_x_.assign(particles_.x(), particles_.x() + n);
  wall_point_at_build_.resize(walls_.size());
  wall_dir_at_build_.resize(walls_.size());
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    wall_point_at_build_[w] = walls_[w].point;
    wall_dir_at_build_[w] = walls_[w].dir;
  }
}

void Simulation::compute_forces() {
  {
    StageTimers::Scope timer(timers_, Stage::Force);
    if (!forces_reset_) reset_forces(particles_, gravity_);
    forces_reset_ = false;
    contact::ContactSink sink;
    const contact::ContactSink* report = nullptr;
    if (collect_virial_) {
      virial_rows_.assign(particles_.size(), Mat3{});
      normal_rows_.assign(particles_.size(), Mat3{});
      sink.rows = virial_rows_.data();
      sink.normals = normal_rows_.data();
      // Pairs across a periodic z boundary have their midpoint outside the box: a layer that
      // spans the whole periodic box takes every pair.
      if (!domain_.periodic[2]) {
        sink.lo = rheo_region_.z_lo;
        sink.hi = rheo_region_.z_hi;
      }
      report = &sink;
    }
    if (heat_model_ >= 0 && !particles_.has_shapes()) {
      // The contacts' overlaps for conduct_heat: the force loop finds the touching pairs anyway.
      heat_overlap_.assign(nlist_.neighbors().size(), 0.0);
      sink.overlaps = heat_overlap_.data();
      report = &sink;
    }
    if (collect_contacts_) {
      contact_records_.assign(nlist_.neighbors().size(), contact::ContactRecord{});
      sink.contacts = contact_records_.data();
      contacts_step_ = step_;
      report = &sink;
    }
    // (Entries of a list restored from a checkpoint have no gaps until the next build.)
    const contact::PairSkip skip{pair_gap_.data(), end_moved_.data(),
                                 domain_.offset_change(gap_offset_)};
    const bool can_skip = pair_skip_active() && pair_gap_.size() == nlist_.neighbors().size() &&
                          end_moved_.size() == particles_.size();
    n_contacts_ =
        particles_.has_shapes()
            ? contact::compute_shape_pair_forces(particles_, domain_, nlist_, pairs_, dt_, report,
                                                 can_skip ? &skip : nullptr)
            : contact::compute_pair_forces(particles_, domain_, nlist_, pairs_, dt_, report);
    if (collect_virial_) {
      contact_sums_ = {};
      for (std::size_t i = 0; i < virial_rows_.size(); ++i) {
        contact_sums_.virial = contact_sums_.virial + virial_rows_[i];
        contact_sums_.normals = contact_sums_.normals + normal_rows_[i];
      }
    }
  }
  {
    StageTimers::Scope timer(timers_, Stage::Walls);
    contact::ContactRecord* records = nullptr;
    if (collect_contacts_) {
      wall_records_.assign(wlist_.entries().size() * static_cast<std::size_t>(wlist_.slots()),
                           contact::ContactRecord{});
      records = wall_records_.data();
    }
    n_wall_contacts_ =
        compute_wall_forces(particles_, walls_, wlist_, pairs_, time(), dt_, records);
  }
  // Drag with the grains' current velocities and the pressure-gradient force (timed by the
  // coupling: its "fluid" time).
  if (cfd_) cfd_->add_forces(particles_);
}

template <class In>
Vec3 Simulation::heat_sums(In&& in) const {
  const auto& t = particles_.get<double>(f_temperature_);
  const double* m = particles_.mass();
  const std::int32_t* mat = particles_.material();
  const Vec3* x = particles_.x();
  Vec3 s{};
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (!in(x[i])) continue;
    const double cap = m[i] * heat_capacity_[static_cast<std::size_t>(mat[i])];
    s.x += cap;
    s.y += cap * t[i];
  }
  return s;
}

void Simulation::conduct_heat() {
  StageTimers::Scope timer(timers_, Stage::Force);
  const std::size_t n = particles_.size();
  const std::span<double> q = particles_.get<double>(f_heat_flow_);
  if (f_heat_source_ >= 0) {
    const std::span<double> source = particles_.get<double>(f_heat_source_);
    std::copy(source.begin(), source.end(), q.begin());
  } else {
    std::fill(q.begin(), q.end(), 0.0);
  }
  heat_h_.assign(n, 0.0);
  double* temp = particles_.get<double>(f_temperature_).data();
  if (!particles_.has_shapes() && heat_overlap_.size() == nlist_.neighbors().size())
    contact::pair_heat_flows_from_overlaps(particles_, nlist_, heat_model_, k_series_, temp,
                                           heat_overlap_.data(), q.data(), heat_h_.data());
  else
    contact::pair_heat_flows(particles_, domain_, nlist_, heat_model_, k_series_, temp, q.data(),
                             heat_h_.data(), heat_entry_h_);
  if (!walls_.empty())
    wall_heat_flows(particles_, walls_, wlist_, heat_model_, k_series_, temp, q.data(),
                    heat_h_.data());
  if (cfd_) cfd_->add_heat(particles_, temp, q.data(), heat_h_.data(), dt_);
  // Explicit Euler, m c dT/dt = Q: stable while dt sum(H) / (m c) <= 1 for every grain (the
  // rows of the conduction matrix by Gershgorin's discs), which a DEM step keeps by orders of
  // magnitude for real materials; a step that breaks it stops the run with the numbers.
  const double* m = particles_.mass();
  const std::int32_t* mat = particles_.material();
  for (std::size_t i = 0; i < n; ++i) {
    const double cap = m[i] * heat_capacity_[static_cast<std::size_t>(mat[i])];
    if (dt_ * heat_h_[i] > cap)
      throw Error(fmt::format(
          "heat conduction is unstable at t = {} s: grain {} has dt sum(H) / (m c) = {:.3g} > 1 "
          "(conductances to contacts, walls and fluid {:.3g} W/K, heat capacity {:.3g} J/K); "
          "reduce time.step or "
          "check thermal_conductivity / heat_capacity",
          time(), particles_.id()[i], dt_ * heat_h_[i] / cap, heat_h_[i], cap));
    temp[i] += dt_ * q[i] / cap;
  }
}

void Simulation::complete_step() {
  if (!kick_pending_) return;
  StageTimers::Scope timer(timers_, Stage::Integrate);
  VelocityVerlet::post_force(particles_, dt_);
  kick_pending_ = false;
}

void Simulation::step(bool defer_kick) {
  // Lees-Edwards: the images' offset at the end of this step, where the drift puts the grains.
  domain_.set_shear_time(static_cast<double>(step_ + 1) * dt_);
  {
    StageTimers::Scope timer(timers_, Stage::Integrate);
    if (gear_) {
      Gear5Integrator::predict(particles_, domain_, dt_);
    } else {
      // Grains without shapes: the drift also resets the forces and measures the displacements
      // for the list's rebuild test (two passes fewer). Rigid bodies read the torque after it.
      // In a Lees-Edwards box the list's reference positions follow the wraps (see
      // VerletList::set_follow_wraps).
      const auto follow = nlist_.follow_wraps();
      Vec3* wrap_refs =
          domain_.sheared() && follow.size() == particles_.size() ? follow.data() : nullptr;
      if (!particles_.has_shapes()) {
        DriftExtras extras;
        extras.gravity = &gravity_;
        extras.pending_kick = kick_pending_;
        kick_pending_ = false;
        const auto ref = nlist_.reference_positions();
        if (ref.size() == particles_.size()) extras.x_ref = ref.data();
        extras.wrap_refs = wrap_refs;
        VelocityVerlet::pre_force(particles_, domain_, dt_, &extras);
        forces_reset_ = true;
        drift_max_d2_ = extras.x_ref ? extras.max_d2 : -1;
      } else {
        complete_step();  // (never deferred with shapes; kept for safety)
        DriftExtras extras;
        extras.wrap_refs = wrap_refs;
        VelocityVerlet::pre_force(particles_, domain_, dt_, &extras);
      }
      RigidBodies::pre_force(particles_, dt_);
    }
  }
  ++step_;
  for (auto& w : walls_) w.update_geometry(time());
  place_fixed_groups(time());
  if (!meter_tallies_.empty()) count_meter_crossings();
  update_neighbors(false);
  compute_forces();
  update_servos();
  if (heat_model_ >= 0) conduct_heat();
  if (!walls_.empty()) {
    for (auto& s : wall_sums_) {
      s.force.resize(walls_.size());
      s.torque.resize(walls_.size());
      for (std::size_t k = 0; k < walls_.size(); ++k) {
        s.force[k] += walls_[k].force;
        s.torque[k] += walls_[k].torque;
      }
      ++s.steps;
    }
  }
  {
    StageTimers::Scope timer(timers_, Stage::Integrate);
    if (gear_) {
      Gear5Integrator::correct(particles_, domain_, dt_);
    } else {
      // The fluid step below reads the grains' velocities: no deferral when it is due.
      const bool fluid_due = cfd_ && cfd_->due(step_);
      if (defer_kick && !particles_.has_shapes() && !fluid_due)
        kick_pending_ = true;  // the next drift does it (DriftExtras::pending_kick)
      else
        VelocityVerlet::post_force(particles_, dt_);
      RigidBodies::post_force(particles_, dt_);
    }
  }
  // The next fluid step, from the grains at the end of this step (the fluid leads the DEM by
  // one interval: explicit sub-cycling, docs/models/cfd_dem.md).
  if (cfd_ && cfd_->due(step_)) {
    try {
      cfd_->fluid_step(particles_);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw Error(fmt::format("at t = {:.6g} s (step {}): {}", time(), step_, e.what()));
    }
  }
}

bool Simulation::write_contacts_csv(const std::filesystem::path& dir) const {
  if (contacts_step_ != step_) return false;
  io::write_contacts_csv(dir / fmt::format("contacts_{:09d}.csv", step_), contact_records_,
                         particles_);
  if (!walls_.empty()) {
    std::vector<std::string> names;
    for (const auto& w : walls_) names.push_back(w.name);
    io::write_wall_contacts_csv(dir / fmt::format("wall_contacts_{:09d}.csv", step_), wall_records_,
                                particles_, names);
  }
  return true;
}

bool Simulation::write_contacts_vtp(const std::filesystem::path& dir, std::string& file) const {
  if (contacts_step_ != step_) return false;
  file = fmt::format("contacts_{:09d}.vtp", step_);
  io::write_contacts_vtp(dir / file, contact_records_, wall_records_, particles_);
  return true;
}

analysis::RheologySample Simulation::rheology_sample() const {
  std::vector<double> density;
  for (const auto& m : materials_) density.push_back(m.density);
  return analysis::measure_rheology(particles_, rheo_region_, contact_sums_, density);
}

double Simulation::total_energy() const {
  return quantity("total_energy");
}

std::vector<std::string> Simulation::series_columns() const {
  // Per-wall quantities PREFIX.NAME are vectors (three columns); NAME.x/.y/.z one component.
  std::vector<std::string> cols;
  for (const auto& q : cfg_.output.quantities) {
    bool wall = false;
    for (std::string_view prefix : input::wall_series_prefixes()) wall |= q.starts_with(prefix);
    const bool component =
        q.size() > 2 && q[q.size() - 2] == '.' && (q.back() >= 'x' && q.back() <= 'z');
    const auto vectors = input::vector_series_quantities();
    const bool vector = std::find(vectors.begin(), vectors.end(), q) != vectors.end();
    if ((wall && !component) || vector) {
      for (const char* c : {".x", ".y", ".z"}) cols.push_back(q + c);
    } else {
      cols.push_back(q);
    }
  }
  return cols;
}

Vec3 Simulation::wall_mean_force(WallMeans who, std::size_t k) const {
  const WallSums& s = wall_sums_[static_cast<int>(who)];
  if (s.steps > 0) return (1.0 / static_cast<double>(s.steps)) * s.force[k];
  return k < s.closed_force.size() ? s.closed_force[k] : walls_[k].force;
}

Vec3 Simulation::wall_mean_torque(WallMeans who, std::size_t k) const {
  const WallSums& s = wall_sums_[static_cast<int>(who)];
  if (s.steps > 0) return (1.0 / static_cast<double>(s.steps)) * s.torque[k];
  return k < s.closed_torque.size() ? s.closed_torque[k] : walls_[k].torque;
}

double Simulation::quantity(const std::string& name) const {
  return series_row({name})[0];
}

std::vector<double> Simulation::series_row(const std::vector<std::string>& columns) const {
  // The O(N) reductions run at most once per row, whatever the number of columns using them.
  std::optional<analysis::EnergyHeights> e;
  std::optional<double> elastic;
  auto energies = [&]() -> const analysis::EnergyHeights& {
    if (!e) e = analysis::energy_and_heights(particles_, gravity_, two_d_ ? 1 : 2);
    return *e;
  };
  auto elastic_energy = [&] {
    if (!elastic)
      elastic = contact::shape_pair_elastic_energy(particles_, domain_, nlist_, pairs_) +
                wall_elastic_energy(particles_, walls_, wlist_, pairs_);
    return *elastic;
  };
  std::optional<Vec3> fixed_load;
  auto fixed_force = [&]() -> const Vec3& {
    if (!fixed_load) fixed_load = fixed_grain_load(particles_, gravity_);
    return *fixed_load;
  };
  std::optional<Vec3> fixed_turn;
  auto fixed_torque = [&]() -> const Vec3& {
    if (!fixed_turn) fixed_turn = fixed_group_torque();
    return *fixed_turn;
  };
  std::vector<double> row;
  row.reserve(columns.size());
  for (const auto& name : columns) {
    if (name.starts_with("wall_position.")) {
      // The current point of a plane wall (for a box: of its face NAME.xmin ...), m.
      std::string rest = name.substr(14);
      int comp = -1;
      if (rest.size() > 2 && rest[rest.size() - 2] == '.' && rest.back() >= 'x' &&
          rest.back() <= 'z') {
        comp = rest.back() - 'x';
        rest.resize(rest.size() - 2);
      }
      const Wall* found = nullptr;
      for (const auto& w : walls_)
        if (w.name == rest) found = &w;
      REQUIRE(found, "no wall named '{}'", rest);
      REQUIRE(comp >= 0, "wall_position needs a component");
      row.push_back(found->point[comp]);
    } else if (name.starts_with("wall_force") || name.starts_with("wall_torque")) {
      // wall_force.W, wall_torque.W: this step's; wall_force_mean.W, wall_torque_mean.W: the
      // mean over the steps since the previous row (this step's at a row with none before).
      const bool force = name.starts_with("wall_force");
      const bool mean = name.starts_with(force ? "wall_force_mean." : "wall_torque_mean.");
      std::string rest = name.substr(name.find('.') + 1);
      int comp = 2;
      if (rest.size() > 2 && rest[rest.size() - 2] == '.' && rest.back() >= 'x' &&
          rest.back() <= 'z') {
        comp = rest.back() - 'x';
        rest.resize(rest.size() - 2);
      }
      Vec3 sum{};
      bool found = false;
      for (std::size_t k = 0; k < walls_.size(); ++k) {
        const Wall& w = walls_[k];
        if (w.group != rest && w.name != rest) continue;
        found = true;
        if (mean)
          sum += force ? wall_mean_force(WallMeans::Series, k)
                       : wall_mean_torque(WallMeans::Series, k);
        else
          sum += force ? w.force : w.torque;
      }
      REQUIRE(found, "no wall named '{}'", rest);
      row.push_back(sum[comp]);
    } else if (name == "fixed_force" || name.starts_with("fixed_force.")) {
      // fixed_force.x|y|z (fixed_force alone, as quantity() may ask: z, as wall_force.W).
      const int comp = name.size() == 13 ? name.back() - 'x' : 2;
      REQUIRE(comp >= 0 && comp <= 2, "series quantity '{}': expected a component .x, .y or .z",
              name);
      row.push_back(fixed_force()[comp]);
    } else if (name == "fixed_torque" || name.starts_with("fixed_torque.")) {
      // fixed_torque.x|y|z (alone: z), about the rotating fixed groups' centre.
      const int comp = name.size() == 14 ? name.back() - 'x' : 2;
      REQUIRE(comp >= 0 && comp <= 2, "series quantity '{}': expected a component .x, .y or .z",
              name);
      row.push_back(fixed_torque()[comp]);
    } else if (name == "kinetic_energy") {
      row.push_back(energies().kinetic_translational + energies().kinetic_rotational);
    } else if (name == "translational_kinetic_energy") {
      row.push_back(energies().kinetic_translational);
    } else if (name == "rotational_kinetic_energy") {
      row.push_back(energies().kinetic_rotational);
    } else if (name == "potential_energy") {
      row.push_back(energies().potential);
    } else if (name == "elastic_energy") {
      row.push_back(elastic_energy());
    } else if (name == "total_energy") {
      const auto& en = energies();
      row.push_back(en.kinetic_translational + en.kinetic_rotational + en.potential +
                    elastic_energy());
    } else if (name == "max_z") {
      row.push_back(energies().max_z);
    } else if (name == "mean_z") {
      row.push_back(energies().mean_z);
    } else if (name == "contact_count") {
      row.push_back(static_cast<double>(n_contacts_));
    } else if (name == "wall_contact_count") {
      row.push_back(static_cast<double>(n_wall_contacts_));
    } else if (name == "particle_count") {
      row.push_back(static_cast<double>(particles_.size()));
    } else if (name == "lacey_index") {
      row.push_back(lacey_index().index);
    } else if (name == "temperature_mean" || name == "thermal_energy") {
      // The heat-capacity weighted mean: the temperature the grains would share if isolated.
      const Vec3 h = heat_sums([](const Vec3&) { return true; });
      row.push_back(name == "thermal_energy" ? h.y : h.y / h.x);
    } else if (name == "temperature_min" || name == "temperature_max") {
      const auto& t = particles_.get<double>(f_temperature_);
      const bool lo = name == "temperature_min";
      double v =
          lo ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
      for (const double ti : t) v = lo ? std::min(v, ti) : std::max(v, ti);
      row.push_back(t.empty() ? std::numeric_limits<double>::quiet_NaN() : v);
    } else if (name.starts_with("wall_heat_flow.")) {
      const std::string_view wall = std::string_view(name).substr(15);
      double q = 0;
      for (const auto& w : walls_)
        if (w.group == wall || w.name == wall) q += w.heat_flow;
      row.push_back(q);
    } else if (const auto meter_prefix = input::flow_meter_series_prefix(name);
               !meter_prefix.empty()) {
      const FlowMeterTally& t = meter_tallies_[named(cfg_.flow_meters, name, meter_prefix)];
      row.push_back(meter_prefix == "flow_mass."    ? t.mass
                    : meter_prefix == "flow_count." ? static_cast<double>(t.count)
                                                    : t.rate(time()));
    } else if (const auto region_prefix = input::region_series_prefix(name);
               !region_prefix.empty()) {
      // The free grains whose centres lie in it (serial: the same sum at any thread count).
      const FillRegion where =
          to_region(cfg_.regions[named(cfg_.regions, name, region_prefix)].region);
      if (region_prefix == "region_temperature.") {
        const Vec3 h = heat_sums([&](const Vec3& x) { return where.contains(x, 0, two_d_); });
        row.push_back(h.x > 0 ? h.y / h.x : std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      const std::int32_t* fixed = particles_.fixed();
      double count = 0, mass = 0;
      for (std::size_t i = 0; i < particles_.size(); ++i) {
        if ((fixed != nullptr && fixed[i] != 0) || !where.contains(particles_.x()[i], 0, two_d_))
          continue;
        count += 1;
        mass += particles_.mass()[i];
      }
      row.push_back(region_prefix == "region_count." ? count : mass);
    } else if (const auto prefix = input::outlet_series_prefix(name); !prefix.empty()) {
      const std::size_t k = named(cfg_.outlets, name, prefix);
      row.push_back(prefix == "outlet_mass." ? outlet_tallies_[k].mass
                                             : static_cast<double>(outlet_tallies_[k].count));
    } else if (name == "coordination_number") {
      row.push_back(analysis::coordination_number(n_contacts_, particles_.size()));
    } else if (cfd_ && name == "fluid_pressure_drop") {
      row.push_back(cfd_->pressure_drop());
    } else if (cfd_ && name == "superficial_velocity") {
      row.push_back(cfd_->superficial_velocity());
    } else if (cfd_ && name == "fluid_kinetic_energy") {
      row.push_back(cfd_->fluid().kinetic_energy());
    } else if (cfd_ && name == "min_fluid_fraction") {
      row.push_back(cfd_->min_fluid_fraction());
    } else if (cfd_ && cfd_->has_heat() && name == "fluid_temperature_mean") {
      row.push_back(cfd_->heat()->mean_temperature(cfd_->fluid()));
    } else if (cfd_ && cfd_->has_heat() && name == "fluid_thermal_energy") {
      row.push_back(cfd_->heat()->energy(cfd_->fluid()));
    } else if (cfd_ && cfd_->has_heat() && name == "fluid_heat_from_grains") {
      row.push_back(cfd_->grain_heat_to_fluid());
    } else if (cfd_ && cfd_->has_heat() && name == "fluid_boundary_heat_flow") {
      row.push_back(cfd_->boundary_heat_to_fluid());
    } else if (cfd_ && cfd_->has_heat() && name.starts_with("fluid_boundary_heat_flow.")) {
      const auto& faces = kBoxFaceNames;
      const auto it = std::find(faces.begin(), faces.end(), std::string_view(name).substr(25));
      REQUIRE(it != faces.end(), "unknown box face in series quantity '{}'", name);
      row.push_back(cfd_->boundary_heat_to_fluid(static_cast<int>(it - faces.begin())));
    } else if (cfd_ && cfd_->has_heat() && name == "fluid_heat_in_transit") {
      row.push_back(cfd_->heat_in_transit(particles_));
    } else {
      throw InputError(fmt::format("unknown series quantity '{}'", name));
    }
  }
  return row;
}

}  // namespace gf
