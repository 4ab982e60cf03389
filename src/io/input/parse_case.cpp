// SPDX-License-Identifier: GPL-3.0-or-later
// case.yaml -> config::Case: one function per block, each key checked for type, range and place.
#include "io/input/parse_case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <tuple>

#include "contact/conduction.hpp"
#include "contact/registry.hpp"
#include "core/error.hpp"
#include "core/names.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "coupling/cfd_dem/heat_transfer.hpp"
#include "coupling/cfd_dem/mapping.hpp"
#include "io/input/model_block.hpp"
#include "io/input/stl.hpp"
#include "io/input/validate.hpp"
#include "io/input/yaml_reader.hpp"
#include "particles/shapes.hpp"

namespace gf::input {

namespace fs = std::filesystem;

namespace {

std::string vec_text(const Vec3& v, int dimension = 3) {
  if (dimension == 2) return fmt::format("[{}, {}]", number_text(v.x), number_text(v.y));
  return fmt::format("[{}, {}, {}]", number_text(v.x), number_text(v.y), number_text(v.z));
}

/// The rotation taking e_z onto the unit vector `axis` (the shortest one; a half turn about x
/// when `axis` is -e_z).
Quat quat_from_z_to(const Vec3& axis) {
  const double w = 1 + axis.z;  // 1 + cos(angle)
  if (w < 1e-12) return Quat{0, 1, 0, 0};
  return normalized(Quat{w, -axis.y, axis.x, 0});  // (1 + e_z . a, e_z x a), halved angle
}

/// The rotation by `angle` (rad) about z.
Quat quat_about_z(double angle) {
  return quat_from_axis_angle(Vec3{0, 0, 1}, angle);
}

/// The rule a fixed group's initial velocities break, for the messages that refuse them.
std::string fixed_rule(const config::ParticleGroup& g) {
  return g.motion ? "the grains of a fixed group with a prescribed motion (fixed: {translate, "
                    "rotate}) take their velocities from the motion"
                  : "the grains of a fixed group (fixed: true) stay at rest";
}

const char* shape_name(config::Shape s) {
  switch (s) {
    case config::Shape::Sphere:
      return "sphere";
    case config::Shape::Spherocylinder:
      return "spherocylinder";
    case config::Shape::Disk:
      return "disk";
    case config::Shape::Polygon:
      return "polygon";
  }
  return "sphere";
}

/// State shared by the block readers.
struct Reader {
  fs::path case_dir;
  config::Case& c;
  /// Where each material was first referenced by a particle group / wall (for missing pairs).
  std::map<std::string, config::SourceLoc> particle_material_ref;
  std::vector<std::string> particle_materials;  ///< in order of first use
  std::vector<std::pair<std::string, config::SourceLoc>> wall_material_refs;
  std::vector<std::pair<std::string, config::SourceLoc>>
      servo_span_refs;  ///< wall names in servo spans
  struct SpanPair {
    std::string a, b;
    config::SourceLoc loc;
  };
  std::vector<SpanPair> servo_span_pairs;  ///< the pairs themselves

  std::vector<std::string> material_names() const {
    std::vector<std::string> out;
    for (const auto& m : c.materials) out.push_back(m.name);
    return out;
  }

  /// Reads a material reference and checks that it is defined.
  std::string material_ref(const YamlNode& n) const {
    const std::string name = n.as_string();
    for (const auto& m : c.materials)
      if (m.name == name) return name;
    const auto names = material_names();
    std::string hint;
    if (auto near = closest_match(name, names)) hint = fmt::format(" (did you mean '{}'?)", *near);
    n.fail(fmt::format("unknown material '{}'{}; defined materials: {}", name, hint, join(names)));
  }

  bool two_d() const { return c.dimension == 2; }
  /// A position, velocity or other vector: [x, y, z] in 3D, [x, y] in 2D (z = 0).
  Vec3 vec(const YamlNode& n) const { return n.as_vec(c.dimension); }
  Vec3 vec(const YamlMap& m, std::string_view key) const { return vec(m.at(key)); }
  Vec3 vec_or(const YamlMap& m, std::string_view key, const Vec3& fallback) const {
    auto n = m.find(key);
    return n ? vec(*n) : fallback;
  }
  Vec3 direction(const YamlNode& n) const { return n.as_direction(c.dimension); }
  std::string text(const Vec3& v) const { return vec_text(v, c.dimension); }
  const char* vec_form() const { return two_d() ? "[x, y]" : "[x, y, z]"; }

  void read_time(const YamlMap& root);
  void read_domain(const YamlMap& root);
  void read_materials(const YamlMap& root);
  void read_contacts(const YamlMap& root);
  void read_particles(const YamlMap& root);
  /// A fixed group (at rest or with a prescribed motion): no grain of `ex` may have a non-zero
  /// velocity or angular velocity (InputError at its list entry, or its line of the CSV file).
  void check_fixed_at_rest(const YamlMap& gm, const config::ParticleGroup& g,
                           const config::Explicit& ex) const;
  /// `fixed:` true, false, or a prescribed motion (the keys of walls[].motion, read_motion).
  void read_fixed(const YamlNode& node, config::ParticleGroup& g);
  config::ParticleGroup read_group(const YamlNode& node);
  void read_shape(const YamlMap& gm, config::ParticleGroup& g) const;
  void read_size(const YamlMap& gm, config::ParticleGroup& g);
  void read_cylinder_length(const YamlMap& gm, config::ParticleGroup& g, bool from_diameter);
  config::PolygonSpec read_polygon(const YamlNode& node) const;
  config::SizeDistribution read_radius(const YamlNode& node);
  /// A region given by exactly one of the keys `box` {min, max} or `cylinder` (3D: {center,
  /// axis, radius, height}; 2D: the circle {center, radius}) of `m`.
  config::Region read_region(const YamlMap& m) const;
  config::Fill read_fill(const YamlNode& node, const config::ParticleGroup& g);
  config::Inlet read_inlet(const YamlNode& node) const;
  void read_positions(const YamlMap& gm, const config::ParticleGroup& g, config::Explicit& ex);
  std::vector<double> read_csv(const YamlNode& file_node, const config::ParticleGroup& g,
                               config::Explicit& ex);
  void read_walls(const YamlMap& root);
  void read_outlets(const YamlMap& root);
  void read_flow_meters(const YamlMap& root);
  void read_regions(const YamlMap& root);
  /// The `name` of an entry of a named list (outlets, flow meters, regions; `what` says which):
  /// a column-safe name, unique in the list (`names`: name -> line, updated).
  static std::string read_entry_name(const YamlMap& m, std::map<std::string, int>& names,
                                     std::string_view what);
  /// Fails at `key` of `m` when the region misses the domain (`who` would never see a grain).
  void require_region_meets_domain(const YamlMap& m, const config::Region& r,
                                   const std::string& who, std::string_view never) const;
  void read_mesh_wall(const YamlNode& node, config::Wall& w) const;
  /// Refuses a scaled mesh whose coordinates are not finite or absurd next to the domain.
  void check_mesh_size(const YamlMap& mm, const config::Wall& w) const;
  config::Motion read_motion(const YamlNode& node);
  void read_output(const YamlMap& root);
  std::optional<config::OutputEvery> read_interval(const YamlMap& m, bool off_allowed) const;
  void read_shear(const YamlMap& root);
  /// The series quantity fixed_torque[.x|.y|.z] (`item`): it needs a rotating fixed group, and
  /// all of them share one centre.
  void check_fixed_torque(const YamlNode& item, const std::string& name) const;
  void read_analysis(const YamlMap& root);
  void read_sweep(const YamlMap& root);
  void read_fluid(const YamlMap& root);
  void read_coupling(const YamlMap& root);
  /// coupling.heat_transfer and what it needs of the fluid block (heat capacity, conductivity,
  /// inflow temperatures) and of the case (the heat: block).
  void read_fluid_heat(const YamlMap& cm, config::Coupling& cp) const;
  void check_pairs() const;
  void read_heat(const YamlMap& root);
  /// A `temperature:` of a particle group or wall: needs the heat: block.
  std::optional<double> read_temperature(const YamlMap& m) const;
  void check_heat() const;
  /// time.end / time.step fits the step counters (InputError at `step` otherwise).
  void check_step_count(const YamlNode& step) const;
};

void Reader::read_time(const YamlMap& root) {
  YamlMap t(root.at("time"), {"step", "end"});
  c.time.step = t.number("step", Range::positive());
  c.time.loc = t.at("step").loc();
  // With shear.strain the end time follows from the strain (read_shear); otherwise it is needed.
  bool strain = false;
  if (auto sh = root.find("shear"); sh && sh->is_map()) strain = YamlMap(*sh).has("strain");
  if (strain) {
    if (auto e = t.find("end"))
      e->fail("give either time.end or shear.strain (the end time is shear.strain / shear.rate)");
    return;
  }
  c.time.end = t.number("end", Range::positive());
  if (c.time.end < c.time.step)
    t.at("end").fail_expected(fmt::format("a number >= time.step ({})", number_text(c.time.step)));
  check_step_count(t.at("step"));
}

void Reader::check_step_count(const YamlNode& step) const {
  // (step counts are 64-bit integers; 1e15 steps would take years on any machine)
  if (c.time.end / c.time.step > 1e15)
    step.fail_expected(
        fmt::format("a time step >= time.end / 1e15 = {} s (more than 1e15 steps "
                    "otherwise)",
                    number_text(c.time.end / 1e15)));
}

void Reader::read_shear(const YamlMap& root) {
  auto sn = root.find("shear");
  if (!sn) return;
  YamlMap sm(*sn, {"rate", "boundary", "wall_material", "strain", "initial_profile"});
  config::Shear sh;
  sh.loc = sn->loc();
  if (two_d())
    sn->fail("simple shear is available in 3D cases only (flow along x, gradient along z)");
  sh.rate = sm.number("rate", Range::positive());
  if (auto b = sm.find("boundary"))
    sh.boundary = b->as_choice({"walls", "lees_edwards"}) == "walls"
                      ? config::Shear::Boundary::Walls
                      : config::Shear::Boundary::LeesEdwards;
  sh.initial_profile = sm.boolean_or("initial_profile", true);
  if (auto st = sm.find("strain")) {
    sh.strain = st->as_number(Range::positive());
    c.time.end = *sh.strain / sh.rate;
    if (c.time.end < c.time.step)
      st->fail_expected(fmt::format("a strain >= shear.rate x time.step ({})",
                                    number_text(sh.rate * c.time.step)));
    check_step_count(YamlMap(root.at("time")).at("step"));
  }
  const auto& per = c.domain.periodic;
  if (sh.boundary == config::Shear::Boundary::Walls) {
    if (!per[0] || !per[1] || per[2])
      sn->fail(
          "shear between walls needs domain.periodic: [true, true, false] (periodic along the "
          "flow x and the vorticity y, walls at z = min and z = max)");
    const YamlNode mat = sm.at("wall_material");
    sh.wall_material = material_ref(mat);
    wall_material_refs.emplace_back(sh.wall_material, mat.loc());
    const double h = c.domain.max.z - c.domain.min.z;
    for (int side = 0; side < 2; ++side) {
      config::Wall w;
      w.name = side == 0 ? "shear_bottom" : "shear_top";
      for (const auto& other : c.walls)
        if (other.name == w.name)
          sn->fail(
              fmt::format("the shear walls are named shear_bottom and shear_top; rename the "
                          "wall '{}' declared under walls:",
                          w.name));
      w.kind = config::Wall::Kind::Plane;
      w.point = side == 0 ? c.domain.min : c.domain.max;
      w.normal = {0, 0, side == 0 ? 1.0 : -1.0};
      w.material = sh.wall_material;
      w.motion.velocity = {(side == 0 ? -0.5 : 0.5) * sh.rate * h, 0, 0};
      w.from_shear = true;
      w.loc = sh.loc;
      w.loc.key_path = sn->path();
      c.walls.push_back(std::move(w));
    }
  } else {
    if (!per[0] || !per[1] || !per[2])
      sn->fail(
          "Lees-Edwards shear needs domain.periodic: [true, true, true] (the images along z "
          "slide along x)");
    if (auto m = sm.find("wall_material"))
      m->fail("'wall_material' applies to boundary: walls only; a Lees-Edwards box has no walls");
    if (c.integrator == "gear5")
      sn->fail(
          "Lees-Edwards shear needs integrator: velocity_verlet (gear5 does not remap its "
          "derivatives across the sliding boundary)");
    for (const auto& w : c.walls)
      if (!w.from_shear)
        sn->fail(
            fmt::format("a Lees-Edwards shear box has no walls, but walls: declares '{}'", w.name));
    for (const auto& g : c.particles)
      if (g.motion)
        throw_input_error(
            g.fixed_loc,
            "a fixed group with a prescribed motion is not available in a Lees-Edwards shear box "
            "(its grains would cross the sliding boundary, which remaps velocities); expected "
            "fixed: true (grains at rest) or shear boundary: walls");
  }
  c.shear = std::move(sh);
}

void Reader::read_analysis(const YamlMap& root) {
  auto an = root.find("analysis");
  if (!an) return;
  YamlMap am(*an, {"rheology", "mixing"});
  if (auto mn = am.find("mixing")) {
    YamlMap mm(*mn, {"materials", "cell", "min_grains"});
    config::Mixing x;
    x.loc = mn->loc();
    const YamlNode mats = mm.at("materials");
    const auto list = mats.as_list();
    if (list.size() != 2) mats.fail_expected("two material names, [A, B]");
    for (const auto& m : list) {
      const std::string name = m.as_string();
      if (std::none_of(c.materials.begin(), c.materials.end(),
                       [&](const config::Material& d) { return d.name == name; }))
        m.fail_expected("a declared material");
      x.materials.push_back(name);
    }
    if (x.materials[0] == x.materials[1]) mats.fail_expected("two different materials");
    x.cell = mm.number("cell", Range::positive());
    if (auto g = mm.find("min_grains")) {
      const auto v = g->as_integer();
      if (v < 2) g->fail_expected("an integer >= 2");
      x.min_grains = static_cast<int>(v);
    }
    c.analysis.mixing = std::move(x);
  }
  if (auto rn = am.find("rheology")) {
    if (two_d()) rn->fail("rheology measurements are available in 3D cases only");
    YamlMap rm(*rn, {"every", "every_strain", "bins", "margin", "start"});
    config::Rheology r;
    r.loc = rn->loc();
    const auto interval = read_interval(rm, false);
    if (!interval) rm.exactly_one_of({"every", "every_strain"});  // throws: one is required
    r.every = interval->every;
    r.every_strain = interval->every_strain;
    const YamlNode every = rm.at(r.every_strain ? "every_strain" : "every");
    if (r.every > 0.5 * c.time.end)
      every.fail_expected(
          fmt::format("an interval that gives at least 2 samples before the end "
                      "({} s)",
                      number_text(c.time.end)));
    if (auto b = rm.find("bins")) r.bins = static_cast<int>(b->as_integer({1, 4096}));
    r.margin = rm.optional_number("margin", Range::non_negative());
    if (r.margin) {
      const double h = c.domain.max.z - c.domain.min.z;
      if (!(2 * *r.margin < h))
        rm.at("margin").fail_expected(
            fmt::format("a margin < half the box height ({} m)", number_text(0.5 * h)));
    }
    r.start = rm.optional_number("start", Range::non_negative());
    if (r.start && *r.start >= c.time.end)
      rm.at("start").fail_expected(
          fmt::format("a time before time.end ({} s)", number_text(c.time.end)));
    c.analysis.rheology = std::move(r);
  }
}

namespace {

/// A sweep's runs are named by their values printed with 6 significant digits (sweep.cpp:
/// phi_%g_rate_%g): the value just added (the list's last) must differ from the earlier ones in
/// that form, else two runs would share a folder.
void require_new_sweep_value(const YamlNode& item, const std::vector<double>& values) {
  const std::string name = fmt::format("{:g}", values.back());
  for (std::size_t k = 0; k + 1 < values.size(); ++k)
    if (fmt::format("{:g}", values[k]) == name)
      item.fail_expected(fmt::format(
          "a value not in the list before (item {} is {}; the runs are named by their values to "
          "6 digits)",
          k, number_text(values[k])));
}

}  // namespace

void Reader::read_sweep(const YamlMap& root) {
  auto sn = root.find("sweep");
  if (!sn) return;
  YamlMap sm(*sn, {"volume_fraction", "shear_rate", "processes"});
  config::Sweep sw;
  sw.loc = sn->loc();
  if (!c.shear)
    sn->fail("a sweep varies shear.rate and fill.volume_fraction: the case needs a shear: block");
  if (auto v = sm.find("volume_fraction")) {
    int fills = 0;
    for (const auto& g : c.particles)
      if (g.fill && g.fill->volume_fraction) ++fills;
    if (fills != 1)
      v->fail(
          fmt::format("a volume-fraction sweep needs exactly one fill with volume_fraction, "
                      "found {}",
                      fills));
    for (const auto& item : v->as_list(1)) {
      sw.volume_fractions.push_back(item.as_number(Range{0.0, 0.74, true, false}));
      require_new_sweep_value(item, sw.volume_fractions);
    }
  }
  if (auto v = sm.find("shear_rate"))
    for (const auto& item : v->as_list(1)) {
      sw.shear_rates.push_back(item.as_number(Range::positive()));
      require_new_sweep_value(item, sw.shear_rates);
    }
  if (sw.volume_fractions.empty() && sw.shear_rates.empty())
    sn->fail("a sweep needs a list volume_fraction: [...] or shear_rate: [...] (or both)");
  if (auto pn = sm.find("processes")) sw.processes = static_cast<int>(pn->as_integer({1, 1024}));
  c.sweep = std::move(sw);
}

void Reader::read_fluid(const YamlMap& root) {
  auto fn = root.find("fluid");
  if (!fn) return;
  YamlMap fm(*fn, {"density", "viscosity", "cells", "boundary", "initial_velocity", "convection",
                   "heat_capacity", "thermal_conductivity", "temperature", "temperature_convection",
                   "thermal_expansion", "reference_temperature"});
  config::Fluid f;
  f.loc = fn->key_loc();  // the `fluid:` line, for errors about the block as a whole
  // The coupling maps spheres and spherocylinders onto a 3D grid; 2D grains (disks, polygons)
  // have no solid volume per cell yet (docs/models/cfd_dem.md).
  if (two_d()) fn->fail("the CFD-DEM fluid is available in 3D cases only");
  f.density = fm.number("density", Range::positive());
  f.viscosity = fm.number("viscosity", Range::positive());
  const YamlNode cn = fm.at("cells");
  f.cells_loc = cn.loc();
  if (!cn.is_list() || cn.raw().size() != 3)
    cn.fail_expected("a list of 3 cell counts [nx, ny, nz]");
  const auto items = cn.as_list();
  for (int k = 0; k < 3; ++k) f.cells[k] = static_cast<int>(items[k].as_integer({1, 4096}));
  const double cells = static_cast<double>(f.cells[0]) * f.cells[1] * f.cells[2];
  if (cells > 2.0e7)
    cn.fail_expected(fmt::format("at most 2e7 cells in all, found {}", number_text(cells)));
  const auto& per = c.domain.periodic;
  const auto& faces = kBoxFaceNames;
  for (int face = 0; face < 6; ++face)
    if (per[face / 2]) f.boundary[face].kind = config::FluidBoundary::Kind::Periodic;
  if (auto bn = fm.find("boundary")) {
    std::vector<std::string> keys(faces.begin(), faces.end());
    keys.insert(keys.end(), kBoxFaceAliases.begin(), kBoxFaceAliases.end());
    YamlMap bm(*bn, keys);
    for (int face = 0; face < 6; ++face) {
      auto v = bm.find_either(faces[face], kBoxFaceAliases[face]);
      if (!v) continue;
      if (c.shear && c.shear->boundary == config::Shear::Boundary::Walls && face >= 4)
        v->fail(
            fmt::format("the fluid face {} is a shear wall (shear: boundary: walls) and "
                        "moves with it; leave it out of fluid.boundary",
                        faces[face]));
      config::FluidBoundary b;
      b.given = true;
      if (v->is_scalar()) {
        b.kind = v->as_choice({"periodic", "no_slip"}) == "periodic"
                     ? config::FluidBoundary::Kind::Periodic
                     : config::FluidBoundary::Kind::NoSlip;
      } else {
        if (!v->is_map())
          v->fail_expected(
              "periodic, no_slip, {moving_wall: [vx, vy, vz]}, {velocity_inlet: [vx, vy, vz]}, "
              "{pressure_outlet: p} or {no_slip: true}, each map with an optional temperature");
        YamlMap m(*v,
                  {"moving_wall", "velocity_inlet", "pressure_outlet", "no_slip", "temperature"});
        const std::string kind =
            m.exactly_one_of({"moving_wall", "velocity_inlet", "pressure_outlet", "no_slip"});
        b.temperature = read_temperature(m);
        if (kind == "no_slip") {
          if (!m.at("no_slip").as_bool()) m.at("no_slip").fail_expected("true");
          b.kind = config::FluidBoundary::Kind::NoSlip;
        } else if (kind == "pressure_outlet") {
          b.kind = config::FluidBoundary::Kind::PressureOutlet;
          b.pressure = m.number("pressure_outlet");
        } else {
          b.velocity = vec(m, kind);
          if (kind == "moving_wall") {
            b.kind = config::FluidBoundary::Kind::MovingWall;
            if (b.velocity[face / 2] != 0)
              m.at(kind).fail_expected(fmt::format(
                  "a wall velocity in the plane of the face (zero {} component)", "xyz"[face / 2]));
          } else {
            b.kind = config::FluidBoundary::Kind::VelocityInlet;
          }
        }
      }
      b.loc = v->loc();
      const bool periodic = b.kind == config::FluidBoundary::Kind::Periodic;
      if (periodic != per[face / 2])
        v->fail(periodic ? fmt::format("face {} is periodic but the domain is not periodic along "
                                       "{} (domain.periodic)",
                                       faces[face], "xyz"[face / 2])
                         : fmt::format("the domain is periodic along {} (domain.periodic), so "
                                       "the fluid face {} must be periodic too",
                                       "xyz"[face / 2], faces[face]));
      f.boundary[face] = b;
    }
    // Incompressible: without a pressure outlet, what the inlets push in has nowhere to go (the
    // pressure solve would stop at the first fluid step). Flux in through each inlet: its
    // velocity's component along the face's inward normal times the face's area.
    bool outlet = false;
    double net = 0.0, scale = 0.0;
    const Vec3 size = c.domain.max - c.domain.min;
    for (int face = 0; face < 6; ++face) {
      const auto& b = f.boundary[face];
      outlet = outlet || b.kind == config::FluidBoundary::Kind::PressureOutlet;
      if (b.kind != config::FluidBoundary::Kind::VelocityInlet) continue;
      const int a = face / 2;
      const double area = size[(a + 1) % 3] * size[(a + 2) % 3];
      const double flux = (face % 2 == 0 ? 1.0 : -1.0) * b.velocity[a] * area;
      net += flux;
      scale += std::abs(flux);
    }
    if (!outlet && std::abs(net) > 1e-12 * scale)
      bn->fail(fmt::format(
          "the fluid has no pressure_outlet face, so the velocity inlets must let in as much as "
          "they let out, but they give a net inflow of {:.4g} m^3/s: make a face "
          "{{pressure_outlet: p}}",
          net));
  }
  if (c.shear && c.shear->boundary == config::Shear::Boundary::LeesEdwards)
    fn->fail(
        "a fluid in a Lees-Edwards shear box is not supported (the fluid grid has no sliding "
        "images); shear it between walls (shear: {boundary: walls})");
  if (c.shear) {
    // The fluid's zmin and zmax are the shear walls: no-slip, moving with them.
    const double h = c.domain.max.z - c.domain.min.z;
    for (int side = 0; side < 2; ++side) {
      auto& b = f.boundary[4 + side];
      b.kind = config::FluidBoundary::Kind::MovingWall;
      b.velocity = {(side == 0 ? -0.5 : 0.5) * c.shear->rate * h, 0, 0};
    }
  }
  f.initial_velocity = vec_or(fm, "initial_velocity", Vec3{});
  if (auto cv = fm.find("convection"))
    f.convection = cv->as_choice({"van_leer", "central", "upwind"});
  f.heat_capacity = fm.number_or("heat_capacity", 0.0, Range::positive());
  f.thermal_conductivity = fm.number_or("thermal_conductivity", 0.0, Range::non_negative());
  f.temperature = read_temperature(fm);
  if (auto tc = fm.find("temperature_convection"))
    f.temperature_convection = tc->as_choice({"van_leer", "upwind"});
  f.thermal_expansion = fm.number_or("thermal_expansion", 0.0, Range::non_negative());
  f.reference_temperature = fm.optional_number("reference_temperature", Range::positive());
  if (auto rt = fm.find("reference_temperature"); rt && !(f.thermal_expansion > 0))
    rt->fail(
        "a reference temperature is the one of the Boussinesq buoyancy: it needs the fluid's "
        "thermal_expansion (1/K, e.g. 2.1e-4 for water, 1/T for a gas)");
  for (const char* key : {"heat_capacity", "thermal_conductivity", "temperature",
                          "temperature_convection", "thermal_expansion", "reference_temperature"})
    if (auto n = fm.find(key); n && !f.thermal_loc) f.thermal_loc = n->loc();
  c.fluid = std::move(f);
}

void Reader::read_coupling(const YamlMap& root) {
  auto cn = root.find("coupling");
  if (!cn) {
    if (c.fluid) {
      config::SourceLoc loc = c.fluid->loc;
      loc.key_path = "fluid";
      throw_input_error(loc,
                        "a fluid: block needs a coupling: block (e.g. 'coupling: {drag: "
                        "di_felice}'); the fluid only exists to act on the particles");
    }
    return;
  }
  if (!c.fluid)
    cn->fail("a coupling: block needs a fluid: block (density, viscosity, cells, boundary)");
  YamlMap cm(*cn, {"drag", "fluid_fraction", "interval", "min_fraction", "fluid_fraction_rate",
                   "rate_relaxation", "pressure_gradient_force", "interpolation", "torque",
                   "heat_transfer"});
  config::Coupling cp;
  cp.loc = cn->loc();
  {
    const YamlNode dn = cm.at("drag");
    std::tie(cp.drag, std::ignore, cp.drag_params) =
        read_model_block(dn, cfd_dem::drag_infos(), "drag law");
    try {
      cfd_dem::prepare_drag(cp.drag, cp.drag_params);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      dn.fail(e.what());
    }
  }
  if (auto ff = cm.find("fluid_fraction"))
    cp.fluid_fraction = ff->as_choice(cfd_dem::kDepositSchemeNames);
  if (auto in = cm.find("interval")) cp.interval = static_cast<int>(in->as_integer({1, 1e6}));
  cp.min_fraction = cm.number_or("min_fraction", 0.3, Range{0.0, 1.0, true, false});
  if (auto r = cm.find("fluid_fraction_rate")) {
    cp.fluid_fraction_rate = r->as_choice({"flux", "difference", "derivative"});
    if (cp.fluid_fraction_rate == "derivative" &&
        !cfd_dem::has_time_derivative(*cfd_dem::deposit_scheme(cp.fluid_fraction)))
      r->fail(fmt::format(
          "'derivative' needs 'fluid_fraction: smoothed' or 'trilinear' (the {} deposit moves in "
          "steps and has no time derivative); use 'flux' or 'difference' with it",
          cp.fluid_fraction));
  }
  cp.rate_relaxation = cm.number_or("rate_relaxation", 0.3, Range{0.0, 1.0, true, false});
  cp.pressure_gradient_force = cm.boolean_or("pressure_gradient_force", true);
  if (auto ip = cm.find("interpolation")) cp.interpolation = ip->as_choice({"trilinear", "cell"});
  if (auto tq = cm.find("torque")) cp.torque = tq->as_choice({"none", "rotational"});
  read_fluid_heat(cm, cp);
  c.coupling = std::move(cp);
}

void Reader::read_fluid_heat(const YamlMap& cm, config::Coupling& cp) const {
  const config::Fluid& f = *c.fluid;
  const auto fluid_loc = [&](const char* key) {
    config::SourceLoc loc = f.loc;
    loc.key_path = fmt::format("fluid.{}", key);
    return loc;
  };
  if (auto ht = cm.find("heat_transfer")) {
    const std::string key = ht->as_string();
    if (key != "none") {
      if (cfd_dem::heat_transfer_index(key) < 0) {
        std::vector<std::string> keys{"none"};
        for (const auto& info : cfd_dem::heat_transfer_infos()) keys.emplace_back(info.key);
        ht->fail_expected(fmt::format("a heat transfer correlation: {}", fmt::join(keys, ", ")));
      }
      if (!c.heat)
        ht->fail(
            "heat transfer between grains and fluid needs the grains' temperatures: add a "
            "top-level 'heat: {temperature: ...}' block (and thermal_conductivity, heat_capacity "
            "to the materials)");
      cp.heat_transfer = key;
    }
  }
  if (cp.heat_transfer.empty()) {
    // Thermal keys without the exchange would be silently ignored: say what they need.
    std::optional<config::SourceLoc> loc = f.thermal_loc;
    for (const auto& b : f.boundary)
      if (!loc && b.temperature) loc = b.loc;
    if (loc)
      throw_input_error(
          *loc,
          "the fluid's heat_capacity, thermal_conductivity, temperature, "
          "temperature_convection, thermal_expansion, reference_temperature and "
          "boundary temperatures are used only with a heat exchange between grains and "
          "fluid: set coupling.heat_transfer (e.g. gunn)");
    return;
  }
  if (!(f.heat_capacity > 0))
    throw_input_error(fluid_loc("heat_capacity"),
                      "coupling.heat_transfer needs the fluid's heat_capacity (J/(kg K), e.g. "
                      "1005 for air, 4182 for water)");
  if (!(f.thermal_conductivity > 0))
    throw_input_error(fluid_loc("thermal_conductivity"),
                      "coupling.heat_transfer needs the fluid's thermal_conductivity (W/(m K), "
                      "e.g. 0.026 for air, 0.6 for water)");
  const auto& faces = kBoxFaceNames;
  for (int face = 0; face < 6; ++face) {
    const auto& b = f.boundary[face];
    if (b.kind == config::FluidBoundary::Kind::VelocityInlet && !b.temperature)
      throw_input_error(b.loc, fmt::format("with coupling.heat_transfer the velocity inlet {} "
                                           "needs the temperature of its inflow: "
                                           "{{velocity_inlet: [vx, vy, vz], temperature: T}}",
                                           faces[face]));
  }
}

void Reader::read_domain(const YamlMap& root) {
  const YamlNode dn = root.at("domain");
  YamlMap d(dn, {"min", "max", "periodic", "thickness"});
  const int dim = c.dimension;
  c.domain.min = vec(d, "min");
  c.domain.max = vec(d, "max");
  for (int k = 0; k < dim; ++k) {
    if (!(c.domain.max[k] > c.domain.min[k]))
      d.at("max").fail_expected(
          fmt::format("every component greater than that of domain.min {}", text(c.domain.min)));
  }
  if (auto p = d.find("periodic")) {
    if (!p->is_list() || p->raw().size() != static_cast<std::size_t>(dim)) {
      if (two_d() && p->is_list() && p->raw().size() == 3)
        p->fail(fmt::format("expected 2 components in a 2D case ([x, y]), found {}", p->found()));
      p->fail_expected(two_d() ? "a list of 2 booleans [x, y]" : "a list of 3 booleans [x, y, z]");
    }
    const auto items = p->as_list();
    for (int k = 0; k < dim; ++k) c.domain.periodic[k] = items[k].as_bool();
  }
  if (auto t = d.find("thickness")) {
    if (!two_d())
      t->fail(
          "'thickness' applies to 2D cases only (dimension: 2), where it is the depth of the disks "
          "and polygons; a 3D case has none");
    c.domain.thickness = t->as_number(Range::positive());
  }
  c.domain.loc = dn.loc();
}

void Reader::read_materials(const YamlMap& root) {
  const YamlNode mn = root.at("materials");
  YamlMap m(mn);
  const auto entries = m.entries();
  if (entries.empty())
    mn.fail_expected("at least one material 'name: {density, youngs_modulus, poisson_ratio}'");
  for (const auto& [key, value] : entries) {
    config::Material mat;
    mat.name = key.as_string();
    if (mat.name.empty()) key.fail_expected("a material name");
    YamlMap mm(value, {"density", "youngs_modulus", "poisson_ratio", "thermal_conductivity",
                       "heat_capacity"});
    mat.density = mm.number("density", Range::positive());
    mat.youngs_modulus = mm.number("youngs_modulus", Range::positive());
    mat.poisson_ratio = mm.number("poisson_ratio", Range{-1.0, 0.5, true, true});
    mat.thermal_conductivity = mm.optional_number("thermal_conductivity", Range::positive());
    mat.heat_capacity = mm.optional_number("heat_capacity", Range::positive());
    mat.loc = value.loc();
    c.materials.push_back(mat);
  }
}

/// Models whose schema lists required parameters that may be replaced by others: each inner list
/// is one complete alternative.
std::vector<std::vector<std::string>> param_alternatives(std::string_view model) {
  if (model == "hooke") return {{"stiffness"}, {"max_overlap", "reference_velocity"}};
  return {};
}

void Reader::read_contacts(const YamlMap& root) {
  auto cn = root.find("contacts");
  if (!cn) return;
  std::map<std::pair<std::string, std::string>, int> seen;  // pair -> line
  for (const auto& item : cn->as_list()) {
    YamlMap cm(item);
    config::Contact ct;
    ct.loc = item.loc();
    const YamlNode between = cm.at("between");
    if (!between.is_list() || between.raw().size() != 2)
      between.fail_expected("a list of 2 material names [a, b]");
    const auto names = between.as_list();
    ct.between = {material_ref(names[0]), material_ref(names[1])};
    const auto key = std::minmax(ct.between[0], ct.between[1]);
    if (auto it = seen.find(key); it != seen.end())
      between.fail(fmt::format("the pair ({}, {}) already has a contacts entry (line {})",
                               key.first, key.second, it->second));
    seen.emplace(key, between.line());

    const YamlNode model = cm.at("model");
    ct.model = model.as_string();
    const contact::ModelInfo* info = contact::find_model(ct.model);
    if (!info) {
      std::vector<std::string> keys;
      for (const auto& mi : contact::model_infos()) keys.emplace_back(mi.key);
      std::string hint;
      if (auto near = closest_match(ct.model, keys))
        hint = fmt::format(" (did you mean '{}'?)", *near);
      model.fail(fmt::format("unknown contact model '{}'{}; registered models: {}", ct.model, hint,
                             join(keys)));
    }
    std::vector<std::string> param_names;
    for (const auto& p : info->params) param_names.emplace_back(p.name);
    std::vector<std::string> accepted{"between", "model"};
    accepted.insert(accepted.end(), param_names.begin(), param_names.end());
    for (const auto& [k, v] : cm.entries()) {
      const std::string name = k.as_string();
      if (std::find(accepted.begin(), accepted.end(), name) != accepted.end()) continue;
      std::string hint;
      if (auto near = closest_match(name, accepted))
        hint = fmt::format(" (did you mean '{}'?)", *near);
      k.fail(
          fmt::format("unknown parameter '{}'{} of contact model '{}'; its parameters: {} (besides "
                      "between, model)",
                      name, hint, ct.model, join(param_names)));
    }
    const auto alternatives = param_alternatives(ct.model);
    auto in_alternative = [&](std::string_view name) {
      for (const auto& alt : alternatives)
        if (std::find(alt.begin(), alt.end(), name) != alt.end()) return true;
      return false;
    };
    for (const auto& p : info->params) {
      if (auto v = cm.find(p.name)) {
        ct.params[std::string(p.name)] = v->as_number(Range{p.min, p.max, p.min_exclusive, false});
        ct.param_locs[std::string(p.name)] = v->loc();
        ct.param_found[std::string(p.name)] = v->found();
      } else if (p.default_value) {
        ct.params[std::string(p.name)] = *p.default_value;
      } else if (!in_alternative(p.name)) {
        config::SourceLoc loc = item.loc();
        loc.key_path = fmt::format("{}.{}", item.path(), p.name);
        throw_input_error(
            loc, fmt::format("missing required key '{}' of contact model '{}' ({}, {})", p.name,
                             ct.model, p.description, p.unit == "1" ? "dimensionless" : p.unit));
      }
    }
    if (!alternatives.empty()) {
      std::size_t n_complete = 0, n_touched = 0;  // alternatives given fully / at least in part
      for (const auto& alt : alternatives) {
        std::size_t n_given = 0;
        for (const auto& n : alt) n_given += cm.has(n) ? 1 : 0;
        n_complete += n_given == alt.size() ? 1 : 0;
        n_touched += n_given > 0 ? 1 : 0;
      }
      if (n_complete != 1 || n_touched != 1) {
        std::vector<std::string> forms, given;
        for (const auto& alt : alternatives) {
          std::vector<std::string> quoted;
          for (const auto& n : alt) {
            quoted.push_back(fmt::format("'{}'", n));
            if (cm.has(n)) given.push_back(n);
          }
          forms.push_back(join(quoted, " and "));
        }
        config::SourceLoc loc = item.loc();
        loc.key_path = fmt::format("{}.{}", item.path(), alternatives.front().front());
        throw_input_error(
            loc, fmt::format("contact model '{}' needs exactly one of: {}; found {}", ct.model,
                             join(forms, ", or "), given.empty() ? "none" : join(given)));
      }
    }
    c.contacts.push_back(std::move(ct));
  }
}

config::SizeDistribution Reader::read_radius(const YamlNode& node) {
  config::SizeDistribution d;
  if (node.is_scalar()) {
    d.kind = config::SizeDistribution::Kind::Fixed;
    d.value = node.as_number(Range::positive());
    return d;
  }
  if (!node.is_map())
    node.fail_expected(
        "a radius in m (a number > 0) or a map {distribution: uniform|normal|lognormal, ...}");
  YamlMap rm(node, {"distribution", "min", "max", "mean", "std"});
  const std::string kind = rm.at("distribution").as_choice({"uniform", "normal", "lognormal"});
  d.min = rm.number("min", Range::positive());
  d.max = rm.number("max", Range::positive());
  if (!(d.max > d.min))
    rm.at("max").fail_expected(fmt::format("a number > min ({})", number_text(d.min)));
  if (kind == "uniform") {
    d.kind = config::SizeDistribution::Kind::Uniform;
    for (const char* k : {"mean", "std"})
      if (auto n = rm.find(k))
        n->fail(fmt::format("'{}' does not apply to distribution: uniform (min, max only)", k));
    return d;
  }
  d.kind = kind == "normal" ? config::SizeDistribution::Kind::Normal
                            : config::SizeDistribution::Kind::Lognormal;
  d.mean = rm.number("mean", Range::positive());
  d.std = rm.number("std", Range::positive());
  if (!(d.mean > d.min && d.mean < d.max))
    rm.at("mean").fail_expected(fmt::format("a number between min ({}) and max ({})",
                                            number_text(d.min), number_text(d.max)));
  return d;
}

config::Region Reader::read_region(const YamlMap& m) const {
  config::Region r;
  const std::string region = m.exactly_one_of({"box", "cylinder"});
  if (region == "box") {
    YamlMap bm(m.at("box"), {"min", "max"});
    r.kind = config::Region::Kind::Box;
    r.min = vec(bm, "min");
    r.max = vec(bm, "max");
    for (int k = 0; k < c.dimension; ++k)
      if (!(r.max[k] > r.min[k]))
        bm.at("max").fail_expected(
            fmt::format("every component greater than that of min {}", text(r.min)));
  } else if (two_d()) {
    // In 2D a cylinder is a circle in the plane, as for walls: {center: [x, y], radius}.
    YamlMap cm(m.at("cylinder"), {"center", "radius"});
    r.kind = config::Region::Kind::Cylinder;
    r.center = vec(cm, "center");
    r.radius = cm.number("radius", Range::positive());
    r.height = 0;
  } else {
    YamlMap cm(m.at("cylinder"), {"center", "axis", "radius", "height"});
    r.kind = config::Region::Kind::Cylinder;
    r.center = cm.vec3("center");
    if (auto a = cm.find("axis")) r.axis = a->as_direction();
    r.radius = cm.number("radius", Range::positive());
    r.height = cm.number("height", Range::positive());
  }
  return r;
}

config::Inlet Reader::read_inlet(const YamlNode& node) const {
  YamlMap im(node, {"box", "cylinder", "rate", "mass_rate", "velocity", "start", "stop", "every"});
  config::Inlet in;
  in.loc = node.loc();
  in.region = read_region(im);
  const std::string which = im.exactly_one_of({"rate", "mass_rate"});
  const YamlNode rate = im.at(which);
  if (which == "rate")
    in.rate = rate.as_number(Range::positive());
  else
    in.mass_rate = rate.as_number(Range::positive());
  in.rate_loc = rate.loc();
  in.velocity = vec_or(im, "velocity", Vec3{});
  if (auto s = im.find("start")) in.start = s->as_number(Range::at_least(0.0));
  if (auto s = im.find("stop")) {
    in.stop = s->as_number(Range::positive());
    if (!(*in.stop > in.start))
      s->fail_expected(fmt::format("a time after start ({} s)", number_text(in.start)));
  }
  if (auto e = im.find("every")) {
    in.every = e->as_number(Range::positive());
    if (in.every < c.time.step)
      e->fail_expected(fmt::format("an interval >= time.step ({} s)", number_text(c.time.step)));
  }
  return in;
}

config::Fill Reader::read_fill(const YamlNode& node, const config::ParticleGroup& g) {
  config::Fill f;
  YamlMap fm(node, {"box", "cylinder", "lattice", "spacing", "count", "volume_fraction", "seed",
                    "velocity", "velocity_jitter", "max_attempts", "orientation"});
  f.loc = node.loc();
  f.region = read_region(fm);
  f.region_loc = fm.at(f.region.kind == config::Region::Kind::Box ? "box" : "cylinder").key_loc();
  if (auto l = fm.find("lattice")) {
    const std::string s = l->as_choice({"cubic", "hcp", "random"});
    f.lattice = s == "cubic" ? config::Fill::Lattice::Cubic
                : s == "hcp" ? config::Fill::Lattice::Hcp
                             : config::Fill::Lattice::Random;
  }
  const bool random = f.lattice == config::Fill::Lattice::Random;
  if (auto s = fm.find("spacing")) {
    if (random)
      s->fail("'spacing' applies to the cubic and hcp lattices only, not to lattice: random");
    const bool round = g.kind == config::Shape::Sphere || g.kind == config::Shape::Disk;
    const double min_spacing = 2 * bounding_radius(g, g.radius.largest());
    f.spacing = s->as_number(Range::positive());
    f.spacing_loc = s->loc();
    if (*f.spacing < min_spacing)
      s->fail_expected(
          round ? fmt::format("a spacing >= 2 x the largest radius ({} m) so that grains do not "
                              "overlap",
                              number_text(min_spacing))
                : fmt::format("a spacing >= 2 x the largest bounding radius of the {} grains ({} "
                              "m) so that grains do not overlap in any orientation",
                              g.shape, number_text(min_spacing)));
  }
  if (auto n = fm.find("count")) {
    if (fm.has("volume_fraction"))
      n->fail("give either 'count' or 'volume_fraction' (the count then follows from it)");
    f.count = n->as_integer(Range::at_least(1));
    f.count_loc = n->loc();
  } else if (auto vf = fm.find("volume_fraction")) {
    f.volume_fraction = vf->as_number(Range{0.0, 0.74, true, false});
    f.count_loc = vf->loc();
    if (g.radius.kind != config::SizeDistribution::Kind::Fixed)
      vf->fail(
          "'volume_fraction' needs grains of one size (a fixed radius); give 'count' for a "
          "size distribution");
    if (g.kind == config::Shape::Polygon && g.polygon.kind == config::PolygonSpec::Kind::Random)
      vf->fail("'volume_fraction' needs grains of one size; random polygons vary: give 'count'");
  } else if (random) {
    config::SourceLoc loc = node.key_loc();
    loc.key_path = node.path() + ".count";
    throw_input_error(
        loc,
        "missing required key 'count' or 'volume_fraction' (lattice: random needs the number of "
        "grains to insert)");
  }
  if (auto s = fm.find("seed"))
    f.seed = static_cast<std::uint64_t>(s->as_integer(Range::non_negative()));
  f.velocity = vec_or(fm, "velocity", Vec3{});
  f.velocity_jitter = fm.number_or("velocity_jitter", 0.0, Range::non_negative());
  if (g.fixed) {
    if (f.velocity != Vec3{})
      fm.at("velocity")
          .fail(fmt::format("{}; expected no initial velocity (or zero), found {}", fixed_rule(g),
                            text(f.velocity)));
    if (f.velocity_jitter > 0)
      fm.at("velocity_jitter")
          .fail(fmt::format("{}; expected no velocity jitter (or 0), found {}", fixed_rule(g),
                            number_text(f.velocity_jitter)));
  }
  if (auto m = fm.find("max_attempts")) {
    if (!random) m->fail("'max_attempts' applies to lattice: random only");
    f.max_attempts = m->as_integer(Range::at_least(1));
  }
  if (auto o = fm.find("orientation")) {
    if (g.kind == config::Shape::Sphere || g.kind == config::Shape::Disk)
      o->fail(fmt::format(
          "'orientation' applies to spherocylinder and polygon grains only, not to shape: {}",
          g.shape));
    const char* forms =
        two_d() ? "random or {angle: a} (rad, about z)" : "random or {axis: [x, y, z]}";
    if (o->is_scalar()) {
      if (o->as_string() != "random") o->fail_expected(forms);
      // random: f.orientation stays empty
    } else if (o->is_map()) {
      if (two_d()) {
        YamlMap om(*o, {"angle"});
        f.orientation = quat_about_z(om.number("angle"));
      } else {
        YamlMap om(*o, {"axis"});
        f.orientation = quat_from_z_to(om.at("axis").as_direction());
      }
    } else {
      o->fail_expected(forms);
    }
  }
  return f;
}

void Reader::read_positions(const YamlMap& gm, const config::ParticleGroup& g,
                            config::Explicit& ex) {
  const auto items = gm.at("positions").as_list(1);
  for (const auto& it : items) {
    ex.positions.push_back(vec(it));
    ex.lines.push_back(it.line());
  }
  // The list under `key` with one entry per position, or nothing when `key` is absent.
  auto same_length = [&](const char* key, const char* entry) -> std::vector<YamlNode> {
    auto n = gm.find(key);
    if (!n) return {};
    if (!n->is_list() || n->raw().size() != items.size())
      n->fail_expected(fmt::format("a list of {} {} (one per position)", items.size(), entry));
    return n->as_list();
  };
  const std::string vec_entries = fmt::format("{} entries", vec_form());
  for (const auto& it : same_length("velocities", vec_entries.c_str()))
    ex.velocities.push_back(vec(it));
  if (two_d()) {
    for (const auto& it : same_length("angular_velocities", "numbers (rad/s about z)")) {
      if (!it.is_scalar())
        it.fail_expected("a number (rad/s about z: angular velocities are scalars in a 2D case)");
      ex.angular_velocities.push_back(Vec3{0, 0, it.as_number()});
    }
  } else {
    for (const auto& it : same_length("angular_velocities", "[x, y, z] entries"))
      ex.angular_velocities.push_back(it.as_vec3());
  }
  if (g.kind == config::Shape::Spherocylinder)
    for (const auto& it : same_length("axes", "axis directions [x, y, z]"))
      ex.orientations.push_back(quat_from_z_to(it.as_direction()));
  if (g.kind == config::Shape::Polygon)
    for (const auto& it : same_length("angles", "angles (rad, about z)"))
      ex.orientations.push_back(quat_about_z(it.as_number()));
}

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

/// Fields of one CSV line with their 1-based start columns.
std::vector<std::pair<std::string_view, int>> split_csv(std::string_view line) {
  std::vector<std::pair<std::string_view, int>> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string_view raw =
        line.substr(start, comma == std::string_view::npos ? line.npos : comma - start);
    std::size_t lead = 0;
    while (lead < raw.size() && (raw[lead] == ' ' || raw[lead] == '\t')) ++lead;
    out.emplace_back(trim(raw), static_cast<int>(start + lead) + 1);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

std::vector<double> Reader::read_csv(const YamlNode& file_node, const config::ParticleGroup& g,
                                     config::Explicit& ex) {
  const std::string given = file_node.as_string();
  if (given.empty()) file_node.fail_expected("a CSV file name");
  fs::path path =
      fs::path(given).is_absolute() ? fs::path(given) : (case_dir / given).lexically_normal();
  ex.file = path;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    file_node.fail(fmt::format("cannot open the particle file '{}'{}", path.string(),
                               fs::exists(path) ? "" : " (no such file)"));
  const std::string key_path = file_node.path();
  auto fail_at = [&](int line, int column, const std::string& msg) {
    config::SourceLoc loc{path.string(), line, column, key_path};
    throw_input_error(loc, msg);
  };

  // Slots of a row: 0-2 position, 3-5 velocity, 6-8 angular velocity, 9 radius, 10-13
  // orientation quaternion (w, x, y, z; 3D), 14 orientation angle (rad about z; 2D).
  enum : int { kRadius = 9, kQuat = 10, kAngle = 14, kSlots = 15 };
  struct Column {
    std::string name;
    int slot;
  };
  const std::vector<Column> columns =
      two_d() ? std::vector<Column>{{"x", 0},  {"y", 1},      {"vx", 3},    {"vy", 4},
                                    {"wz", 8}, {"radius", 9}, {"angle", 14}}
              : std::vector<Column>{{"x", 0},   {"y", 1},   {"z", 2},   {"vx", 3}, {"vy", 4},
                                    {"vz", 5},  {"wx", 6},  {"wy", 7},  {"wz", 8}, {"radius", 9},
                                    {"qw", 10}, {"qx", 11}, {"qy", 12}, {"qz", 13}};
  // Columns that go together (all or none).
  const std::vector<std::vector<int>> together =
      two_d() ? std::vector<std::vector<int>>{{3, 4}}
              : std::vector<std::vector<int>>{{3, 4, 5}, {6, 7, 8}, {10, 11, 12, 13}};
  std::vector<std::string> names;
  for (const auto& col : columns) names.push_back(col.name);
  auto name_of = [&](int slot) {
    for (const auto& col : columns)
      if (col.slot == slot) return col.name;
    return std::string();
  };
  const bool oriented = g.kind == config::Shape::Spherocylinder || g.kind == config::Shape::Polygon;

  std::vector<int> slot_of;  // field index -> slot
  std::vector<double> radii;
  std::string line_text;
  int line_no = 0, header_line = 0;
  auto has = [&](int slot) {
    return std::find(slot_of.begin(), slot_of.end(), slot) != slot_of.end();
  };
  while (std::getline(in, line_text)) {
    ++line_no;
    const std::string_view line = trim(line_text);
    if (line.empty() || line.front() == '#') continue;
    const auto fields = split_csv(line_text);
    if (header_line == 0) {
      header_line = line_no;
      for (const auto& [name, col] : fields) {
        auto it = std::find_if(columns.begin(), columns.end(),
                               [&](const Column& c) { return c.name == name; });
        if (it == columns.end()) {
          static const std::vector<std::string> only_3d{"z",  "vz", "wx", "wy",
                                                        "qw", "qx", "qy", "qz"};
          if (two_d() && std::find(only_3d.begin(), only_3d.end(), name) != only_3d.end())
            fail_at(line_no, col,
                    fmt::format("column '{}' does not apply to a 2D case (dimension: 2); the "
                                "columns of a 2D particle file are: {}",
                                name, join(names)));
          if (!two_d() && name == "angle")
            fail_at(line_no, col,
                    "column 'angle' is for 2D cases; in 3D the orientation is given by the "
                    "columns qw, qx, qy, qz");
          fail_at(line_no, col,
                  fmt::format("unknown column '{}' in the header; accepted columns: {}", name,
                              join(names)));
        }
        if (has(it->slot))
          fail_at(line_no, col, fmt::format("column '{}' appears twice in the header", name));
        if (it->slot >= kQuat && !oriented)
          fail_at(line_no, col,
                  fmt::format("column '{}': orientations apply to spherocylinder and polygon "
                              "grains only, not to shape: {}",
                              name, g.shape));
        slot_of.push_back(it->slot);
      }
      for (int k = 0; k < c.dimension; ++k)
        if (!has(k))
          fail_at(
              line_no, 1,
              fmt::format("expected a header with columns {} (optionally {}), found no "
                          "column '{}'",
                          two_d() ? "x, y" : "x, y, z",
                          join(std::vector<std::string>(names.begin() + c.dimension, names.end())),
                          name_of(k)));
      for (const auto& set : together) {
        std::size_t n = 0;
        std::vector<std::string> set_names;
        for (int slot : set) {
          n += has(slot) ? 1 : 0;
          set_names.push_back(name_of(slot));
        }
        if (n != 0 && n != set.size())
          fail_at(line_no, 1,
                  fmt::format("columns {} go together; found only some of them", join(set_names)));
      }
      continue;
    }
    if (fields.size() != slot_of.size())
      fail_at(line_no, 1,
              fmt::format("expected {} comma-separated values (as in the header), found {}",
                          slot_of.size(), fields.size()));
    double v[kSlots] = {};
    for (std::size_t f = 0; f < fields.size(); ++f) {
      std::string_view text = fields[f].first;
      if (!text.empty() && text.front() == '+') text.remove_prefix(1);
      double x = 0;
      const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
      const int slot = slot_of[f];
      if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
          !std::isfinite(x))
        fail_at(line_no, fields[f].second,
                fmt::format("column '{}': expected a number, found '{}'", name_of(slot),
                            fields[f].first));
      if (slot == kRadius && !(x > 0))
        fail_at(line_no, fields[f].second,
                fmt::format("column 'radius': expected a number > 0, found '{}'", fields[f].first));
      v[slot] = x;
    }
    ex.positions.push_back({v[0], v[1], v[2]});
    ex.lines.push_back(line_no);
    if (has(3)) ex.velocities.push_back({v[3], v[4], v[5]});
    if (has(8)) ex.angular_velocities.push_back({v[6], v[7], v[8]});
    if (has(kRadius)) radii.push_back(v[kRadius]);
    if (has(kQuat)) {
      const Quat q{v[10], v[11], v[12], v[13]};
      if (!(norm2(q) > 0))
        fail_at(line_no, 1, "columns qw, qx, qy, qz: expected a non-zero quaternion, found 0");
      ex.orientations.push_back(normalized(q));
    }
    if (has(kAngle)) ex.orientations.push_back(quat_about_z(v[kAngle]));
  }
  if (header_line == 0)
    fail_at(0, 0,
            fmt::format("expected a header line '{}[,...]', found an empty file",
                        two_d() ? "x,y" : "x,y,z"));
  if (ex.positions.empty())
    fail_at(header_line, 1, "expected particle rows after the header, found none");
  return radii;
}

void Reader::read_shape(const YamlMap& gm, config::ParticleGroup& g) const {
  g.kind = two_d() ? config::Shape::Disk : config::Shape::Sphere;  // default: the round one
  if (auto s = gm.find("shape")) {
    const std::string name = s->as_choice({"sphere", "spherocylinder", "disk", "polygon"});
    g.kind = name == "sphere"           ? config::Shape::Sphere
             : name == "spherocylinder" ? config::Shape::Spherocylinder
             : name == "disk"           ? config::Shape::Disk
                                        : config::Shape::Polygon;
    const bool shape_2d = g.kind == config::Shape::Disk || g.kind == config::Shape::Polygon;
    if (shape_2d != two_d())
      s->fail(
          fmt::format("shape '{}' is a {}D shape, not available in a {}D case (dimension: {}); "
                      "the shapes of a {}D case are {}",
                      name, shape_2d ? 2 : 3, c.dimension, c.dimension, c.dimension,
                      two_d() ? "disk and polygon" : "sphere and spherocylinder"));
  }
  g.shape = shape_name(g.kind);
  // Keys that belong to other shapes.
  auto only_for = [&](const char* key, config::Shape shape, const char* what) {
    if (g.kind == shape) return;
    if (auto n = gm.find(key))
      n->fail(fmt::format("'{}'{} applies to shape: {} only; this group's shape is {}", key, what,
                          shape_name(shape), g.shape));
  };
  only_for("equivalent_diameter", config::Shape::Spherocylinder, "");
  only_for("length", config::Shape::Spherocylinder, "");
  only_for("aspect_ratio", config::Shape::Spherocylinder, "");
  only_for("axes", config::Shape::Spherocylinder, " (orientations of explicit particles)");
  only_for("polygon", config::Shape::Polygon, "");
  only_for("angles", config::Shape::Polygon, " (orientations of explicit particles)");
}

void Reader::read_cylinder_length(const YamlMap& gm, config::ParticleGroup& g, bool from_diameter) {
  if (from_diameter) {
    if (auto l = gm.find("length"))
      l->fail(
          "'length' does not go with 'equivalent_diameter'; give the elongation as "
          "'aspect_ratio' (or give 'radius' and 'length')");
    return;  // aspect_ratio was read with the diameter
  }
  const bool has_length = gm.has("length"), has_ratio = gm.has("aspect_ratio");
  if (has_length && has_ratio) gm.exactly_one_of({"length", "aspect_ratio"});  // throws
  if (!has_length && !has_ratio) {
    config::SourceLoc loc = gm.node().key_loc();
    loc.key_path = gm.node().path() + ".length";
    throw_input_error(loc,
                      "missing required key: a spherocylinder needs 'length' (m, the length L of "
                      "its cylindrical part, >= 0) or 'aspect_ratio' ((L + 2 r)/(2 r), >= 1)");
  }
  if (has_length)
    g.length = gm.number("length", Range::non_negative());
  else
    g.aspect_ratio = gm.number("aspect_ratio", Range::at_least(1));
}

void Reader::read_size(const YamlMap& gm, config::ParticleGroup& g) {
  if (g.kind == config::Shape::Polygon && g.polygon.kind == config::PolygonSpec::Kind::Vertices) {
    if (auto r = gm.find("radius"))
      r->fail(
          "a polygon given by its vertices takes its size from them; remove 'radius' (or use "
          "polygon: {regular: n} or {random: ...} with a radius)");
    g.radius.kind = config::SizeDistribution::Kind::Fixed;
    g.radius.value = std::sqrt(grain_measure(g, 0.0) / std::numbers::pi);  // equal-area radius
    return;
  }
  if (g.kind == config::Shape::Spherocylinder && gm.has("equivalent_diameter")) {
    if (gm.has("radius")) gm.exactly_one_of({"radius", "equivalent_diameter"});  // throws
    const double d = gm.number("equivalent_diameter", Range::positive());
    if (!gm.has("aspect_ratio")) {
      config::SourceLoc loc = gm.node().key_loc();
      loc.key_path = gm.node().path() + ".aspect_ratio";
      throw_input_error(loc,
                        "missing required key 'aspect_ratio': a spherocylinder given by "
                        "'equivalent_diameter' also needs its aspect ratio (L + 2 r)/(2 r) >= 1");
    }
    const double alpha = gm.number("aspect_ratio", Range::at_least(1));
    // Volume pi r^3 (2 alpha - 2/3) of the spherocylinder = pi d^3 / 6 of the sphere.
    g.radius.kind = config::SizeDistribution::Kind::Fixed;
    g.radius.value = d / std::cbrt(12 * alpha - 4);
    g.aspect_ratio = alpha;
    read_cylinder_length(gm, g, true);
    return;
  }
  g.radius = read_radius(gm.at("radius"));
  if (g.kind == config::Shape::Spherocylinder) read_cylinder_length(gm, g, false);
}

config::PolygonSpec Reader::read_polygon(const YamlNode& node) const {
  config::PolygonSpec p;
  YamlMap pm(node, {"vertices", "regular", "random"});
  const std::string form = pm.exactly_one_of({"vertices", "regular", "random"});
  const Range vertex_count{3, static_cast<double>(kMaxPolygonVertices), false, false};
  if (form == "vertices") {
    p.kind = config::PolygonSpec::Kind::Vertices;
    const YamlNode vn = pm.at("vertices");
    const auto items = vn.as_list(3);
    if (items.size() > static_cast<std::size_t>(kMaxPolygonVertices))
      vn.fail_expected(
          fmt::format("a list of 3 to {} vertices [[x, y], ...]", kMaxPolygonVertices));
    for (const auto& it : items) p.vertices.push_back(it.as_vec(2));
    // Strictly convex and counter-clockwise: every turn is to the left (positive cross product
    // of consecutive edges), and the turns add up to one full turn (no star polygon).
    const std::size_t n = p.vertices.size();
    double turning = 0;
    std::size_t n_right = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 a = p.vertices[(i + n - 1) % n], b = p.vertices[i], cc = p.vertices[(i + 1) % n];
      const Vec3 e1 = b - a, e2 = cc - b;
      const double cr = e1.x * e2.y - e1.y * e2.x;
      n_right += cr < 0 ? 1 : 0;
      turning += std::atan2(cr, dot(e1, e2));
    }
    if (n_right == n)
      vn.fail(
          "the vertices are listed clockwise; list them counter-clockwise (a strictly convex "
          "polygon turns left at every vertex)");
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 a = p.vertices[(i + n - 1) % n], b = p.vertices[i], cc = p.vertices[(i + 1) % n];
      const Vec3 e1 = b - a, e2 = cc - b;
      const double cr = e1.x * e2.y - e1.y * e2.x;
      if (!(norm(e1) > 0) || !(norm(e2) > 0))
        items[i].fail(
            fmt::format("vertex {} {} repeats its neighbour; expected distinct "
                        "vertices of a strictly convex polygon",
                        i, vec_text(b, 2)));
      if (!(cr > 1e-12 * norm(e1) * norm(e2)))
        items[i].fail(fmt::format(
            "the polygon is not strictly convex and counter-clockwise at vertex {} {}: the "
            "cross product of the edges from vertex {} and to vertex {} is {} m^2 (expected > "
            "0: {})",
            i, vec_text(b, 2), (i + n - 1) % n, (i + 1) % n, number_text(cr),
            cr < 0 ? "the boundary turns right there" : "the three vertices are in a line"));
    }
    if (turning > 3 * std::numbers::pi)
      vn.fail(fmt::format(
          "the vertices wind {:.0f} times around the polygon; expected a simple convex polygon, "
          "each vertex listed once, counter-clockwise",
          turning / (2 * std::numbers::pi)));
  } else if (form == "regular") {
    p.kind = config::PolygonSpec::Kind::Regular;
    p.sides = static_cast<int>(pm.at("regular").as_integer(vertex_count));
  } else {
    p.kind = config::PolygonSpec::Kind::Random;
    YamlMap rm(pm.at("random"), {"vertices", "elongation"});
    const YamlNode vn = rm.at("vertices");
    if (!vn.is_list() || vn.raw().size() != 2)
      vn.fail_expected(
          fmt::format("a list of 2 integers [min, max] in [3, {}]", kMaxPolygonVertices));
    const auto vi = vn.as_list();
    p.min_vertices = static_cast<int>(vi[0].as_integer(vertex_count));
    p.max_vertices = static_cast<int>(vi[1].as_integer(vertex_count));
    if (p.max_vertices < p.min_vertices)
      vi[1].fail_expected(fmt::format("an integer >= the minimum ({})", p.min_vertices));
    if (auto en = rm.find("elongation")) {
      if (!en->is_list() || en->raw().size() != 2)
        en->fail_expected("a list of 2 numbers [min, max], each >= 1");
      const auto ei = en->as_list();
      p.min_elongation = ei[0].as_number(Range::at_least(1));
      p.max_elongation = ei[1].as_number(Range::at_least(1));
      if (p.max_elongation < p.min_elongation)
        ei[1].fail_expected(
            fmt::format("a number >= the minimum ({})", number_text(p.min_elongation)));
    }
  }
  return p;
}

config::ParticleGroup Reader::read_group(const YamlNode& node) {
  YamlMap gm(node, {"shape", "radius", "equivalent_diameter", "length", "aspect_ratio", "polygon",
                    "material", "fill", "positions", "velocities", "angular_velocities", "axes",
                    "angles", "file", "fixed", "inlet", "temperature", "heat_source"});
  config::ParticleGroup g;
  g.loc = node.loc();
  g.temperature = read_temperature(gm);
  if (auto hs = gm.find("heat_source")) {
    if (!c.heat)
      hs->fail(
          "a heat source needs heat conduction: add a top-level 'heat: {temperature: ...}' block "
          "(and thermal_conductivity, heat_capacity to the materials)");
    g.heat_source = hs->as_number();
  }
  if (auto fx = gm.find("fixed")) read_fixed(*fx, g);
  read_shape(gm, g);
  if (g.kind == config::Shape::Polygon) g.polygon = read_polygon(gm.at("polygon"));
  const YamlNode mat = gm.at("material");
  g.material = material_ref(mat);
  if (!particle_material_ref.count(g.material)) {
    particle_material_ref[g.material] = mat.loc();
    particle_materials.push_back(g.material);
  }
  const std::string source = gm.exactly_one_of({"fill", "positions", "file", "inlet"});
  if (source != "positions") {
    for (const char* k : {"velocities", "angular_velocities", "axes", "angles"}) {
      if (auto n = gm.find(k))
        n->fail(fmt::format(
            "'{}' go with 'positions:'{}", k,
            source == "file"
                ? (two_d()
                       ? " (a CSV file gives them as columns vx,vy / wz / angle)"
                       : " (a CSV file gives them as columns vx,vy,vz / wx,wy,wz / qw,qx,qy,qz)")
            : source == "inlet" ? " (an inlet gives 'velocity' inside 'inlet:')"
                                : " (a fill gives 'velocity' and 'orientation' inside 'fill:')"));
    }
  }
  if (source == "file") {
    config::Explicit ex;
    const YamlNode fn = gm.at("file");
    const auto radii = read_csv(fn, g, ex);
    if (!radii.empty()) {
      for (const char* k : {"radius", "equivalent_diameter"})
        if (auto r = gm.find(k))
          r->fail(fmt::format(
              "the particle file '{}' has a radius column; give the size in one place only",
              ex.file.string()));
      if (g.kind == config::Shape::Polygon && g.polygon.kind == config::PolygonSpec::Kind::Vertices)
        fn.fail(fmt::format(
            "the particle file '{}' has a radius column, but a polygon given by its vertices "
            "takes its size from them",
            ex.file.string()));
      const auto [lo, hi] = std::minmax_element(radii.begin(), radii.end());
      if (*lo == *hi) {
        g.radius.kind = config::SizeDistribution::Kind::Fixed;
        g.radius.value = *lo;
      } else {
        g.radius.kind = config::SizeDistribution::Kind::Uniform;  // bounds of the radii read
        g.radius.min = *lo;
        g.radius.max = *hi;
      }
      ex.radii = radii;
      if (g.kind == config::Shape::Spherocylinder) read_cylinder_length(gm, g, false);
    } else {
      read_size(gm, g);
    }
    if (g.fixed) check_fixed_at_rest(gm, g, ex);
    g.explicit_particles = std::move(ex);
    return g;
  }
  read_size(gm, g);
  if (source == "inlet") {
    const YamlNode in = gm.at("inlet");
    if (g.fixed)
      in.fail("a fixed group cannot have an inlet (inserted grains fall, fixed ones stay put)");
    if (c.integrator == "gear5")
      in.fail(
          "an inlet is not available with integrator: gear5 (a new grain has no higher time "
          "derivatives); use velocity_verlet");
    g.inlet = read_inlet(in);
  } else if (source == "fill") {
    g.fill = read_fill(gm.at("fill"), g);
  } else {
    config::Explicit ex;
    read_positions(gm, g, ex);
    if (g.fixed) check_fixed_at_rest(gm, g, ex);
    g.explicit_particles = std::move(ex);
  }
  return g;
}

void Reader::read_fixed(const YamlNode& node, config::ParticleGroup& g) {
  g.fixed_loc = node.loc();
  constexpr std::string_view forms =
      "true, false or a prescribed motion with the keys of walls[].motion: {translate: "
      "{velocity: V, start: T}, rotate: {axis: A, center: C, rpm: N (or rate: W)}}";
  if (!node.is_map()) {
    try {
      g.fixed = node.as_bool();
    } catch (const InputError&) {
      node.fail_expected(forms);
    }
    return;
  }
  if (node.raw().size() == 0)
    node.fail_expected(fmt::format(
        "{} (an empty map names no motion; give 'translate' and/or 'rotate', or fixed: true for "
        "grains at rest)",
        forms));
  // The same reader as the walls' motions: one syntax, one meaning (boundaries/motion.hpp).
  const config::Motion m = read_motion(node);
  g.fixed = true;
  // A translation at zero velocity without rotation is rest: the group is fixed at rest.
  if (m.rotates || !(m.velocity == Vec3{})) g.motion = m;
}

void Reader::check_fixed_at_rest(const YamlMap& gm, const config::ParticleGroup& g,
                                 const config::Explicit& ex) const {
  // The first grain given a velocity or an angular velocity, at its list entry or CSV line.
  for (const auto& [key, values, what] :
       {std::tuple{"velocities", &ex.velocities, "velocity"},
        std::tuple{"angular_velocities", &ex.angular_velocities, "angular velocity"}}) {
    for (std::size_t k = 0; k < values->size(); ++k) {
      const Vec3& v = (*values)[k];
      if (v == Vec3{}) continue;
      const std::string found =
          two_d() && values == &ex.angular_velocities ? number_text(v.z) : text(v);
      const std::string msg =
          fmt::format("{}; expected no initial {} (or zero), found {} for particle {}",
                      fixed_rule(g), what, found, k);
      if (!ex.file.empty()) {
        const YamlNode fn = gm.at("file");
        throw_input_error({ex.file.string(), ex.lines[k], 1, fn.path()},
                          fmt::format("columns {}: {}",
                                      values == &ex.velocities ? (two_d() ? "vx, vy" : "vx, vy, vz")
                                                               : (two_d() ? "wz" : "wx, wy, wz"),
                                      msg));
      }
      gm.at(key).as_list()[k].fail(msg);
    }
  }
}

void Reader::read_particles(const YamlMap& root) {
  for (const auto& item : root.at("particles").as_list(1)) c.particles.push_back(read_group(item));
}

config::Motion Reader::read_motion(const YamlNode& node) {
  config::Motion m;
  YamlMap mm(node, {"translate", "rotate"});
  if (auto t = mm.find("translate")) {
    YamlMap tm(*t, {"velocity", "start"});
    m.velocity = vec(tm, "velocity");
    m.start = tm.number_or("start", 0.0, Range::non_negative());
  }
  if (auto r = mm.find("rotate")) {
    YamlMap rm(*r, {"axis", "center", "rpm", "rate"});
    m.rotates = true;
    double sign = 1;
    if (!two_d()) {
      m.axis = rm.at("axis").as_direction();
    } else if (auto a = rm.find("axis")) {
      // 2D: the rotation is about z; an axis, if given, is [0, 0, 1] or [0, 0, -1].
      const Vec3 axis = a->raw().IsSequence() && a->raw().size() == 3 ? a->as_direction() : Vec3{};
      if (!(std::abs(axis.z) == 1.0 && axis.x == 0 && axis.y == 0))
        a->fail_expected(
            "[0, 0, 1] or [0, 0, -1] (in a 2D case the rotation is about z; 'axis' may be left "
            "out)");
      sign = axis.z;  // stored as a rotation about +z at rate sign * rate
    }
    m.center = vec_or(rm, "center", Vec3{});
    const std::string which = rm.exactly_one_of({"rpm", "rate"});
    const double v = rm.number(which);
    m.rate = sign * (which == "rpm" ? v * 2 * std::numbers::pi / 60.0 : v);
  }
  return m;
}

// `mesh: {file, scale, offset}`: an STL surface, read now so that `check` reports a bad file.
void Reader::read_mesh_wall(const YamlNode& node, config::Wall& w) const {
  if (two_d())
    node.fail("mesh walls are 3D surfaces, not available in 2D (dimension: 2); use plane or box");
  YamlMap mm(node, {"file", "scale", "offset"});
  const YamlNode file = mm.at("file");
  const std::string given = file.as_string();
  if (given.empty()) file.fail_expected("an STL file name");
  w.kind = config::Wall::Kind::Mesh;
  w.mesh_file =
      fs::path(given).is_absolute() ? fs::path(given) : (case_dir / given).lexically_normal();
  w.mesh_scale = mm.number_or("scale", 1.0, Range::positive());
  w.mesh_offset = vec_or(mm, "offset", Vec3{});
  io::StlSurface stl;
  try {
    stl = io::read_stl(w.mesh_file);
  } catch (const std::exception& e) {
    file.fail(fmt::format("cannot read the STL file '{}': {}", w.mesh_file.string(), e.what()));
  }
  w.mesh_points.reserve(stl.points.size());
  for (const auto& p : stl.points) w.mesh_points.push_back(w.mesh_scale * p + w.mesh_offset);
  check_mesh_size(mm, w);
  w.mesh_triangles = std::move(stl.triangles);
  w.mesh_dropped = stl.dropped;
}

// A scaled mesh far larger or smaller than the domain, or far away from it, is a scale or an
// offset meant for other units (or a typo): its coordinates overflow, or the distances the
// contact search takes between them lose every digit (1e200 m squared is inf). Refused at
// `scale` (the size) or `offset` (the place) when beyond 1e6 times the domain's diagonal, or
// under 1e-6 of it.
void Reader::check_mesh_size(const YamlMap& mm, const config::Wall& w) const {
  const double size = norm(c.domain.max - c.domain.min);
  const YamlNode scale = mm.find("scale") ? mm.at("scale") : mm.at("file");
  const YamlNode place = mm.find("offset") ? mm.at("offset") : scale;
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (const auto& p : w.mesh_points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      (mm.find("scale") ? scale : place)
          .fail(fmt::format("expected a scale and offset that keep the mesh's coordinates finite, "
                            "found a vertex at {} m (scale {})",
                            text(p), number_text(w.mesh_scale)));
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  // (the largest extent and distance along an axis: a norm of 1e200 m would overflow)
  const Vec3 centre = 0.5 * (c.domain.min + c.domain.max);
  double span = 0, away = 0;
  for (int k = 0; k < 3; ++k) {
    span = std::max(span, hi[k] - lo[k]);
    away = std::max({away, std::abs(lo[k] - centre[k]), std::abs(hi[k] - centre[k])});
  }
  if (!(span <= 1e6 * size) || !(span >= 1e-6 * size))
    scale.fail(fmt::format(
        "expected a scale that gives a mesh of about the domain's size ({:.3g} m across), found "
        "one {:.3g} m across (scale {}; a file in millimetres needs scale: 0.001)",
        size, span, number_text(w.mesh_scale)));
  if (!(away <= 1e6 * size))
    place.fail(fmt::format(
        "expected a mesh near the domain ({:.3g} m across), found it {:.3g} m from the domain's "
        "centre (bounds {} - {})",
        size, away, text(lo), text(hi)));
}

void Reader::read_outlets(const YamlMap& root) {
  auto on = root.find("outlets");
  if (!on) return;
  std::map<std::string, int> names;  // name -> line
  for (const auto& item : on->as_list()) {
    YamlMap om(item, {"name", "box", "cylinder", "reinsert"});
    config::Outlet o;
    o.loc = item.loc();
    o.name = read_entry_name(om, names, "outlet");
    o.region = read_region(om);
    const auto key = [](const config::Region& r) {
      return r.kind == config::Region::Kind::Box ? "box" : "cylinder";
    };
    const auto [lo, hi] = region_bounds(o.region);
    require_region_meets_domain(om, o.region, fmt::format("outlet '{}'", o.name), "take");
    if (auto rn = om.find("reinsert")) {
      if (c.integrator == "gear5")
        rn->fail(
            "'reinsert' is not available with integrator: gear5 (a reinserted grain would keep "
            "its higher time derivatives); use velocity_verlet");
      const YamlMap rm(*rn, {"box", "cylinder"});
      o.reinsert = read_region(rm);
      o.reinsert_loc = rn->loc();
      const auto [rlo, rhi] = region_bounds(*o.reinsert);
      bool inside = true, apart = false;
      for (int k = 0; k < c.dimension; ++k) {
        inside = inside && rlo[k] >= c.domain.min[k] && rhi[k] <= c.domain.max[k];
        apart = apart || rlo[k] >= hi[k] || rhi[k] <= lo[k];
      }
      if (!inside)
        rm.at(key(*o.reinsert))
            .fail_expected(fmt::format("a region inside the domain {} - {}", text(c.domain.min),
                                       text(c.domain.max)));
      if (!apart)
        rm.at(key(*o.reinsert))
            .fail(fmt::format("the reinsert region meets outlet '{}' itself: grains put back "
                              "there would be taken again",
                              o.name));
    }
    c.outlets.push_back(std::move(o));
  }
}

void Reader::read_flow_meters(const YamlMap& root) {
  auto fn = root.find("flow_meters");
  if (!fn) return;
  std::map<std::string, int> names;  // name -> line
  for (const auto& item : fn->as_list()) {
    YamlMap fm(item, {"name", "point", "normal", "radius"});
    config::FlowMeter f;
    f.loc = item.loc();
    f.name = read_entry_name(fm, names, "flow meter");
    f.point = vec(fm, "point");
    f.normal = direction(fm.at("normal"));
    f.radius = fm.optional_number("radius", Range::positive());
    // A plane that misses the domain would never count a grain: surely a typo. It meets the
    // box when the box's corners are not all on one side of it.
    double lo = 1e300, hi = -1e300;
    for (int corner = 0; corner < (1 << c.dimension); ++corner) {
      Vec3 q;
      for (int k = 0; k < c.dimension; ++k)
        q[k] = (corner >> k & 1) != 0 ? c.domain.max[k] : c.domain.min[k];
      const double s = dot(q - f.point, f.normal);
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    if (!(lo < 0 && hi > 0))
      fm.at("point").fail(fmt::format(
          "flow meter '{}': its plane (through {}, normal {}) misses the domain {} - {}: it would "
          "never count a grain",
          f.name, text(f.point), text(f.normal), text(c.domain.min), text(c.domain.max)));
    c.flow_meters.push_back(std::move(f));
  }
}

std::string Reader::read_entry_name(const YamlMap& m, std::map<std::string, int>& names,
                                    std::string_view what) {
  const YamlNode name = m.at("name");
  std::string text = name.as_string();
  if (!is_column_name(text))
    name.fail_expected(
        fmt::format("a{} {} name of letters, digits, '_' and '-', starting with a letter or '_'",
                    what.front() == 'o' ? "n" : "", what));
  if (auto it = names.find(text); it != names.end())
    name.fail(
        fmt::format("duplicate {} name '{}' (first used at line {})", what, text, it->second));
  names.emplace(text, name.line());
  return text;
}

void Reader::require_region_meets_domain(const YamlMap& m, const config::Region& r,
                                         const std::string& who, std::string_view never) const {
  // A region that misses the domain would never see a grain: surely a typo.
  const auto [lo, hi] = region_bounds(r);
  for (int k = 0; k < c.dimension; ++k)
    if (!(hi[k] > c.domain.min[k] && lo[k] < c.domain.max[k]))
      m.at(r.kind == config::Region::Kind::Box ? "box" : "cylinder")
          .fail(fmt::format("{} lies outside the domain {} - {}: it would never {} a grain", who,
                            text(c.domain.min), text(c.domain.max), never));
}

void Reader::read_regions(const YamlMap& root) {
  auto rn = root.find("regions");
  if (!rn) return;
  std::map<std::string, int> names;  // name -> line
  for (const auto& item : rn->as_list()) {
    YamlMap rm(item, {"name", "box", "cylinder"});
    config::NamedRegion r;
    r.loc = item.loc();
    r.name = read_entry_name(rm, names, "region");
    r.region = read_region(rm);
    require_region_meets_domain(rm, r.region, fmt::format("region '{}'", r.name), "hold");
    c.regions.push_back(std::move(r));
  }
}

void Reader::read_walls(const YamlMap& root) {
  auto wn = root.find("walls");
  if (!wn) return;
  std::map<std::string, int> names;  // name -> line
  for (const auto& item : wn->as_list()) {
    YamlMap wm(item, {"name", "plane", "box", "cylinder", "mesh", "material", "motion", "servo",
                      "temperature"});
    config::Wall w;
    w.loc = item.loc();
    w.temperature = read_temperature(wm);
    const YamlNode name = wm.at("name");
    w.name = name.as_string();
    if (!is_column_name(w.name))
      name.fail_expected(
          "a wall name of letters, digits, '_' and '-', starting with a letter or '_'");
    if (auto it = names.find(w.name); it != names.end())
      name.fail(
          fmt::format("duplicate wall name '{}' (first used at line {})", w.name, it->second));
    names.emplace(w.name, name.line());

    const std::string kind = wm.exactly_one_of({"plane", "box", "cylinder", "mesh"});
    if (kind == "mesh") {
      read_mesh_wall(wm.at("mesh"), w);
    } else if (kind == "plane") {
      YamlMap pm(wm.at("plane"), {"point", "normal"});
      w.kind = config::Wall::Kind::Plane;
      w.point = vec(pm, "point");
      w.normal = direction(pm.at("normal"));
    } else if (kind == "box") {
      YamlMap bm(wm.at("box"), {"min", "max", "open"});
      w.kind = config::Wall::Kind::Box;
      w.min = vec(bm, "min");
      w.max = vec(bm, "max");
      for (int k = 0; k < c.dimension; ++k)
        if (!(w.max[k] > w.min[k]))
          bm.at("max").fail_expected(
              fmt::format("every component greater than that of min {}", text(w.min)));
      if (auto o = bm.find("open")) {
        const std::size_t n_faces = two_d() ? 4 : 6;
        for (const auto& face : o->as_list()) {
          // x_min ... z_max (the two-fluid block's spelling) name the same faces.
          const int k = face.is_scalar() ? box_face_index(face.raw().Scalar()) : -1;
          if (two_d() && k >= 4)
            face.fail(fmt::format(
                "a box in a 2D case (dimension: 2) has no face '{}'; its faces are xmin, xmax, "
                "ymin, ymax",
                face.raw().Scalar()));
          const std::string f = k >= 0 ? std::string(kBoxFaceNames[static_cast<std::size_t>(k)])
                                       : face.as_choice(std::span<const std::string_view>(
                                             kBoxFaceNames.data(), n_faces));
          if (std::find(w.open.begin(), w.open.end(), f) != w.open.end())
            face.fail(fmt::format("face '{}' is listed twice", f));
          w.open.push_back(f);
        }
      }
      // A 2D box has no z faces: they are recorded as open, so that no plane is built there.
      if (two_d()) w.open.insert(w.open.end(), {"zmin", "zmax"});
    } else {
      // In 2D a cylinder is a circle in the plane (its axis is z): an obstacle (inside: false)
      // or a vessel (inside: true) for disks and polygons.
      YamlMap cm(wm.at("cylinder"),
                 two_d() ? std::vector<std::string>{"center", "radius", "inside"}
                         : std::vector<std::string>{"center", "axis", "radius", "inside"});
      w.kind = config::Wall::Kind::Cylinder;
      w.center = vec(cm, "center");
      if (auto a = cm.find("axis")) w.axis = a->as_direction();
      w.radius = cm.number("radius", Range::positive());
      w.inside = cm.boolean_or("inside", true);
    }
    const YamlNode mat = wm.at("material");
    w.material = material_ref(mat);
    wall_material_refs.emplace_back(w.material, mat.loc());
    if (auto mo = wm.find("motion")) w.motion = read_motion(*mo);
    if (auto sv = wm.find("servo")) {
      if (w.kind != config::Wall::Kind::Plane)
        sv->fail(
            "a servo (stress-controlled wall) needs a plane wall; give the faces of a box as "
            "separate planes");
      if (w.motion.rotates) sv->fail("a servo wall cannot also rotate; give it no 'rotate' motion");
      YamlMap sm(*sv, {"pressure", "max_velocity", "span", "until", "gain"});
      config::Servo servo;
      servo.loc = sv->loc();
      servo.pressure = sm.number("pressure", Range::positive());
      servo.max_velocity = sm.number("max_velocity", Range::positive());
      if (auto u = sm.find("until")) servo.until = u->as_number(Range::non_negative());
      servo.gain = sm.number_or("gain", 0.01, Range{0.0, 1.0, true, false});
      const YamlNode span = sm.at("span");
      const auto pairs = span.as_list(1);
      const std::size_t want = two_d() ? 1 : 2;
      if (pairs.size() != want)
        span.fail_expected(fmt::format(
            "{} pair(s) of wall names [a, b] whose distance is the extent of this wall's face "
            "({})",
            want,
            two_d() ? "2D: one pair; the area is that distance times domain.thickness"
                    : "3D: two pairs; the area is the product of the two distances"));
      for (const auto& pr : pairs) {
        const auto pair = pr.as_list(2);
        if (pair.size() != 2) pr.fail_expected("a pair of wall names [a, b]");
        if (pair[0].as_string() == pair[1].as_string())
          pr.fail_expected("two different walls [a, b] (the span is the distance between them)");
        servo_span_pairs.push_back({pair[0].as_string(), pair[1].as_string(), pr.loc()});
        servo.spans.push_back({pair[0].as_string(), pair[1].as_string()});
        servo_span_refs.push_back({pair[0].as_string(), pair[0].loc()});
        servo_span_refs.push_back({pair[1].as_string(), pair[1].loc()});
      }
      w.servo = std::move(servo);
    }
    c.walls.push_back(std::move(w));
  }
  // Spans must name plane walls of this case.
  for (const auto& [name, loc] : servo_span_refs) {
    const auto it = std::find_if(c.walls.begin(), c.walls.end(),
                                 [&](const config::Wall& w) { return w.name == name; });
    if (it == c.walls.end() || it->kind != config::Wall::Kind::Plane)
      throw_input_error(loc, fmt::format("expected the name of a plane wall of this case, found "
                                         "'{}'",
                                         name));
  }
  // ... and parallel ones: the span is the distance between two parallel planes.
  for (const auto& [a, b, loc] : servo_span_pairs) {
    auto normal = [&](const std::string& name) {
      return std::find_if(c.walls.begin(), c.walls.end(),
                          [&](const config::Wall& w) { return w.name == name; })
          ->normal;
    };
    const Vec3 na = normal(a), nb = normal(b);
    if (norm(cross(na, nb)) > 1e-9 * norm(na) * norm(nb))
      throw_input_error(loc, fmt::format("expected two parallel plane walls, found '{}' (normal "
                                         "[{}, {}, {}]) and '{}' (normal [{}, {}, {}])",
                                         a, na.x, na.y, na.z, b, nb.x, nb.y, nb.z));
  }
}

// The interval of an output or of the rheology sampling: `every` (s) or, in a shear case,
// `every_strain` (strain: the same number per unit strain at every rate of a sweep).
std::optional<config::OutputEvery> Reader::read_interval(const YamlMap& m, bool off_allowed) const {
  if (!m.find("every") && !m.find("every_strain")) return std::nullopt;
  const std::string how = m.exactly_one_of({"every", "every_strain"});
  const YamlNode n = m.at(how);
  const double v = n.as_number(off_allowed ? Range::non_negative() : Range::positive());
  config::OutputEvery out;
  if (how == "every_strain") {
    if (!c.shear)
      n.fail(
          "'every_strain' needs a shear: block (its rate turns strain into time); use 'every' "
          "(s)");
    out.every_strain = v;
  }
  out.every = out.every_strain ? v / c.shear->rate : v;
  // (with a tolerance: a strain interval converted to seconds may round below one step)
  if ((!off_allowed || out.every > 0) && out.every < c.time.step * (1 - 1e-12)) {
    std::string hint;
    if (out.every_strain) {  // the smallest strain, rounded up to 3 digits
      const double strain = c.time.step * c.shear->rate;
      const double unit = std::pow(10.0, std::floor(std::log10(strain)) - 2);
      hint = fmt::format(": a strain >= {:.3g} at shear.rate {}",
                         std::ceil(strain / unit * (1 - 1e-12)) * unit, number_text(c.shear->rate));
    }
    n.fail_expected(fmt::format("{}an interval >= time.step ({} s){}",
                                off_allowed ? "0 (off) or " : "", number_text(c.time.step), hint));
  }
  return out;
}

void Reader::read_output(const YamlMap& root) {
  auto on = root.find("output");
  if (!on) return;
  YamlMap om(*on, {"directory", "vtk", "particles_csv", "contacts_csv", "contacts_vtk", "series",
                   "checkpoint"});
  if (auto d = om.find("directory")) {
    const std::string dir = d->as_string();
    if (dir.empty()) d->fail_expected("a folder name");
    c.output.directory = dir;
  }
  // The interval in seconds (`every`) or, in a shear case, in strain (`every_strain`, so that
  // one case gives as many outputs per strain at every shear rate of a sweep).
  auto every = [&](const YamlMap& m, config::OutputEvery& target) {
    if (auto e = read_interval(m, true)) target = *e;
  };
  for (auto [key, target] :
       {std::pair{"vtk", &c.output.vtk}, std::pair{"particles_csv", &c.output.particles_csv},
        std::pair{"contacts_csv", &c.output.contacts_csv},
        std::pair{"contacts_vtk", &c.output.contacts_vtk},
        std::pair{"checkpoint", &c.output.checkpoint}}) {
    if (auto n = om.find(key)) every(YamlMap(*n, {"every", "every_strain"}), *target);
  }
  if (auto s = om.find("series")) {
    YamlMap sm(*s, {"every", "every_strain", "quantities"});
    every(sm, c.output.series);
    std::vector<std::string> walls;
    for (const auto& w : c.walls) {
      walls.push_back(w.name);
      // The faces of a box report on their own too: NAME.xmin ... NAME.zmax.
      if (w.kind == config::Wall::Kind::Box)
        for (const std::string_view face : kBoxFaceNames)
          if (std::find(w.open.begin(), w.open.end(), face) == w.open.end())
            walls.push_back(w.name + "." + std::string(face));
    }
    if (auto q = sm.find("quantities")) {
      for (const auto& item : q->as_list()) {
        const std::string name = item.as_string();
        // A quantity of a named outlet or flow meter: the name must be declared.
        const auto named = [&](std::string_view prefix, const auto& list, const char* what) {
          const std::string object = name.substr(prefix.size());
          std::vector<std::string> names;
          for (const auto& o : list) names.push_back(o.name);
          if (std::find(names.begin(), names.end(), object) == names.end())
            item.fail(fmt::format("unknown {} '{}' in '{}'; {}", what, object, name,
                                  names.empty()
                                      ? fmt::format("no {}s are declared", what)
                                      : fmt::format("declared {}s: {}", what, join(names))));
        };
        if (const auto outlet_prefix = outlet_series_prefix(name); !outlet_prefix.empty()) {
          named(outlet_prefix, c.outlets, "outlet");
        } else if (const auto meter_prefix = flow_meter_series_prefix(name);
                   !meter_prefix.empty()) {
          named(meter_prefix, c.flow_meters, "flow meter");
        } else if (const auto region_prefix = region_series_prefix(name); !region_prefix.empty()) {
          named(region_prefix, c.regions, "region");
        } else if (name.starts_with("wall_heat_flow.")) {
          const std::string wall = name.substr(15);
          if (std::find(walls.begin(), walls.end(), wall) == walls.end())
            item.fail(fmt::format("unknown wall '{}' in '{}'; {}", wall, name,
                                  walls.empty() ? std::string("no walls are declared")
                                                : fmt::format("declared walls: {}", join(walls))));
        } else if (name.starts_with("fluid_boundary_heat_flow.")) {
          static const std::vector<std::string> faces(kBoxFaceNames.begin(), kBoxFaceNames.end());
          const std::string face = name.substr(25);
          if (std::find(faces.begin(), faces.end(), face) == faces.end())
            item.fail(fmt::format("unknown box face '{}' in '{}'; expected one of {}", face, name,
                                  join(faces)));
        } else if (!is_series_quantity(name, walls)) {
          for (std::string_view prefix : wall_series_prefixes()) {
            if (name.starts_with(prefix)) {
              std::string wall = name.substr(prefix.size());
              for (const char* comp : {".x", ".y", ".z"})
                if (wall.size() > 2 && wall.substr(wall.size() - 2) == comp)
                  wall.resize(wall.size() - 2);
              item.fail(fmt::format("unknown wall '{}' in '{}'; {}", wall, name,
                                    walls.empty()
                                        ? std::string("no walls are declared")
                                        : fmt::format("declared walls: {}", join(walls))));
            }
          }
          std::string hint;
          if (auto near = closest_match(name, series_quantity_names()))
            hint = fmt::format(" (did you mean '{}'?)", *near);
          item.fail(fmt::format(
              "unknown series quantity '{}'{}; accepted: {}, wall_force.WALL, wall_torque.WALL, "
              "wall_force_mean.WALL, wall_torque_mean.WALL, wall_position.WALL (these, "
              "fixed_force and fixed_torque optionally with .x, .y or .z), outlet_mass.OUTLET, "
              "outlet_count.OUTLET, flow_mass.METER, flow_count.METER, flow_rate.METER, "
              "region_count.REGION, region_mass.REGION, region_temperature.REGION, "
              "wall_heat_flow.WALL, fluid_boundary_heat_flow.FACE",
              name, hint, join(series_quantity_names())));
        }
        if (!c.heat &&
            (name.starts_with("temperature_") || name == "thermal_energy" ||
             name.starts_with("wall_heat_flow.") || name.starts_with("region_temperature.")))
          item.fail(fmt::format(
              "series quantity '{}' needs heat conduction: a top-level heat: block", name));
        if (!c.fluid && (name.rfind("fluid_", 0) == 0 || name == "superficial_velocity" ||
                         name == "min_fluid_fraction"))
          item.fail(fmt::format("series quantity '{}' needs a fluid: block", name));
        if (c.fluid &&
            (name == "fluid_temperature_mean" || name == "fluid_thermal_energy" ||
             name == "fluid_heat_from_grains" || name.starts_with("fluid_boundary_heat_flow") ||
             name == "fluid_heat_in_transit") &&
            (!c.coupling || c.coupling->heat_transfer.empty()))
          item.fail(
              fmt::format("series quantity '{}' needs the fluid's temperature: "
                          "coupling.heat_transfer (e.g. gunn)",
                          name));
        // (the analysis block is read after the output: its rheology intervals are checked
        // against the series')
        bool mixing = false;
        if (auto an = root.find("analysis"); an && an->is_map())
          mixing = YamlMap(*an).has("mixing");
        if (name == "lacey_index" && !mixing)
          item.fail(
              "series quantity 'lacey_index' needs analysis.mixing: {materials: [A, B], cell: "
              "side of the cells in m}");
        if (name.starts_with("fixed_force") &&
            std::none_of(c.particles.begin(), c.particles.end(),
                         [](const config::ParticleGroup& g) { return g.fixed; }))
          item.fail(fmt::format(
              "series quantity '{}' is the load on fixed grains; it needs a particle group with "
              "fixed: true",
              name));
        if (name.starts_with("fixed_torque")) check_fixed_torque(item, name);
        if (std::find(c.output.quantities.begin(), c.output.quantities.end(), name) !=
            c.output.quantities.end())
          item.fail(fmt::format("quantity '{}' is listed twice", name));
        c.output.quantities.push_back(name);
      }
    }
    if (c.output.series.every > 0 && c.output.quantities.empty()) {
      config::SourceLoc loc = s->key_loc();
      loc.key_path = s->path() + ".quantities";
      throw_input_error(
          loc, "missing required key 'quantities' (the series to write, e.g. [kinetic_energy])");
    }
  }
}

void Reader::check_fixed_torque(const YamlNode& item, const std::string& name) const {
  // The torque is taken about one centre: the rotating fixed groups must share it (its place at
  // t = 0 and its translation), so that one point is the centre at every time.
  const config::ParticleGroup* first = nullptr;
  for (const auto& g : c.particles) {
    if (!g.motion || !g.motion->rotates) continue;
    if (!first) {
      first = &g;
      continue;
    }
    const config::Motion& a = *first->motion;
    const config::Motion& b = *g.motion;
    if (!(a.center == b.center) || !(a.velocity == b.velocity) ||
        (!(a.velocity == Vec3{}) && a.start != b.start))
      item.fail(fmt::format(
          "series quantity '{}' is the torque on the rotating fixed groups about their rotation "
          "centre; expected one centre, but the groups at {}:{} and {}:{} turn about different "
          "ones (center {} and {}, translation {} and {})",
          name, first->fixed_loc.file, first->fixed_loc.line, g.fixed_loc.file, g.fixed_loc.line,
          text(a.center), text(b.center), text(a.velocity), text(b.velocity)));
  }
  if (!first)
    item.fail(fmt::format(
        "series quantity '{}' is the torque on the rotating fixed groups about their rotation "
        "centre; it needs a particle group with fixed: {{rotate: {{...}}}}",
        name));
}

void Reader::check_pairs() const {
  std::set<std::pair<std::string, std::string>> given;
  for (const auto& ct : c.contacts) given.insert(std::minmax(ct.between[0], ct.between[1]));
  auto require = [&](const std::string& a, const std::string& b, const config::SourceLoc& where) {
    const auto key = std::minmax(a, b);
    if (given.count(key)) return;
    throw_input_error(
        where,
        fmt::format("no contacts entry for the material pair ({}, {}); add one under contacts:, "
                    "e.g. '- {{between: [{}, {}], model: hertz_mindlin, restitution: 0.5}}'",
                    key.first, key.second, key.first, key.second));
  };
  for (std::size_t i = 0; i < particle_materials.size(); ++i)
    for (std::size_t j = 0; j <= i; ++j)
      require(particle_materials[j], particle_materials[i],
              particle_material_ref.at(particle_materials[i]));
  if (particle_materials.empty()) return;
  for (const auto& [wm, loc] : wall_material_refs)
    for (const auto& pm : particle_materials) require(pm, wm, loc);
}

void Reader::read_heat(const YamlMap& root) {
  auto hn = root.find("heat");
  if (!hn) return;
  YamlMap hm(*hn, {"model", "temperature"});
  config::Heat h;
  h.loc = hn->loc();
  if (two_d())
    hn->fail(
        "heat conduction is for 3D cases (spheres and spherocylinders); a 2D contact's "
        "conductance per unit depth has no finite constriction resistance");
  if (auto m = hm.find("model")) {
    h.model = m->as_string();
    if (contact::conduction_index(h.model) < 0) {
      std::vector<std::string> keys;
      for (const auto& info : contact::conduction_infos()) keys.emplace_back(info.key);
      m->fail_expected(fmt::format("a conduction model: {}", fmt::join(keys, ", ")));
    }
  }
  h.temperature = hm.number("temperature", Range::positive());
  c.heat = h;
}

std::optional<double> Reader::read_temperature(const YamlMap& m) const {
  auto t = m.find("temperature");
  if (!t) return std::nullopt;
  if (!c.heat)
    t->fail(
        "a temperature needs heat conduction: add a top-level 'heat: {temperature: ...}' block "
        "(and thermal_conductivity, heat_capacity to the materials)");
  return t->as_number(Range::positive());
}

void Reader::check_heat() const {
  if (!c.heat) return;
  auto material = [&](const std::string& name) -> const config::Material& {
    for (const auto& m : c.materials)
      if (m.name == name) return m;
    throw Error(fmt::format("unknown material '{}'", name));  // (material_ref checked it)
  };
  for (const auto& name : particle_materials) {
    const config::Material& m = material(name);
    if (!m.thermal_conductivity || !m.heat_capacity)
      throw_input_error(
          m.loc, fmt::format("material '{}' of particles needs thermal_conductivity (W/(m K)) and "
                             "heat_capacity (J/(kg K)) for the heat: block",
                             name));
  }
  for (const auto& w : c.walls)
    if (w.temperature && !material(w.material).thermal_conductivity)
      throw_input_error(material(w.material).loc,
                        fmt::format("material '{}' of wall '{}', which has a temperature, needs "
                                    "thermal_conductivity (W/(m K))",
                                    w.material, w.name));
}

config::Case parse(const YamlNode& root, const fs::path& file) {
  config::Case c;
  c.file = file;
  Reader r{file.parent_path(), c, {}, {}, {}, {}, {}};
  YamlMap rm(root, {"name",      "dimension", "time",      "domain", "gravity",  "integrator",
                    "materials", "contacts",  "particles", "walls",  "outlets",  "flow_meters",
                    "regions",   "output",    "neighbor",  "shear",  "analysis", "sweep",
                    "fluid",     "coupling",  "heat"});
  if (auto n = rm.find("name")) {
    c.name = n->as_string();
    if (c.name.empty()) n->fail_expected("a case name");
  } else {
    c.name = fs::absolute(file).parent_path().filename().string();
    if (c.name.empty()) c.name = file.stem().string();
  }
  if (auto d = rm.find("dimension")) {
    const auto dim = d->as_integer();
    if (dim != 2 && dim != 3) d->fail_expected("2 or 3");
    c.dimension = static_cast<int>(dim);
  }
  r.read_time(rm);
  r.read_domain(rm);
  c.gravity = r.vec_or(rm, "gravity", c.dimension == 2 ? Vec3{0, -9.81, 0} : Vec3{0, 0, -9.81});
  if (auto i = rm.find("integrator")) c.integrator = i->as_choice({"velocity_verlet", "gear5"});
  r.read_materials(rm);
  r.read_heat(rm);
  r.read_contacts(rm);
  r.read_particles(rm);
  r.read_walls(rm);
  r.read_outlets(rm);
  r.read_flow_meters(rm);
  r.read_regions(rm);
  r.read_shear(rm);
  r.read_fluid(rm);
  r.read_coupling(rm);
  r.read_output(rm);
  r.read_analysis(rm);
  r.read_sweep(rm);
  if (auto n = rm.find("neighbor")) {
    YamlMap nm(*n, {"skin"});
    c.neighbor.skin = nm.optional_number("skin", Range::positive());
  }
  r.check_pairs();
  r.check_heat();
  return c;
}

}  // namespace

const std::vector<std::string>& series_quantity_names() {
  static const std::vector<std::string> names{"kinetic_energy",
                                              "translational_kinetic_energy",
                                              "rotational_kinetic_energy",
                                              "potential_energy",
                                              "elastic_energy",
                                              "total_energy",
                                              "max_z",
                                              "mean_z",
                                              "contact_count",
                                              "wall_contact_count",
                                              "coordination_number",
                                              "particle_count",
                                              "fixed_force",
                                              "fixed_torque",
                                              "fluid_pressure_drop",
                                              "superficial_velocity",
                                              "fluid_kinetic_energy",
                                              "min_fluid_fraction",
                                              "fluid_temperature_mean",
                                              "fluid_thermal_energy",
                                              "fluid_heat_from_grains",
                                              "fluid_boundary_heat_flow",
                                              "fluid_heat_in_transit",
                                              "lacey_index",
                                              "temperature_mean",
                                              "temperature_min",
                                              "temperature_max",
                                              "thermal_energy"};
  return names;
}

std::span<const std::string_view> vector_series_quantities() {
  static constexpr std::string_view names[] = {"fixed_force", "fixed_torque"};
  return names;
}

std::span<const std::string_view> wall_series_prefixes() {
  static constexpr std::string_view prefixes[] = {"wall_force.", "wall_torque.", "wall_force_mean.",
                                                  "wall_torque_mean.", "wall_position."};
  return prefixes;
}

std::string_view outlet_series_prefix(std::string_view quantity) {
  for (std::string_view prefix : {"outlet_mass.", "outlet_count."})
    if (quantity.starts_with(prefix)) return prefix;
  return {};
}

std::string_view region_series_prefix(std::string_view quantity) {
  for (std::string_view prefix : {"region_count.", "region_mass.", "region_temperature."})
    if (quantity.starts_with(prefix)) return prefix;
  return {};
}

std::string_view flow_meter_series_prefix(std::string_view quantity) {
  for (std::string_view prefix : {"flow_mass.", "flow_count.", "flow_rate."})
    if (quantity.starts_with(prefix)) return prefix;
  return {};
}

bool is_series_quantity(std::string_view quantity, const std::vector<std::string>& wall_names) {
  const auto& names = series_quantity_names();
  if (std::find(names.begin(), names.end(), quantity) != names.end()) return true;
  for (std::string_view vector : vector_series_quantities())
    if (quantity.size() == vector.size() + 2 && quantity.starts_with(vector) &&
        quantity[vector.size()] == '.' &&
        (quantity.back() == 'x' || quantity.back() == 'y' || quantity.back() == 'z'))
      return true;
  for (std::string_view prefix : wall_series_prefixes()) {
    if (quantity.substr(0, prefix.size()) != prefix) continue;
    std::string_view wall = quantity.substr(prefix.size());
    if (std::find(wall_names.begin(), wall_names.end(), wall) != wall_names.end()) return true;
    if (wall.size() > 2 && wall[wall.size() - 2] == '.' &&
        (wall.back() == 'x' || wall.back() == 'y' || wall.back() == 'z')) {
      wall.remove_suffix(2);
      if (std::find(wall_names.begin(), wall_names.end(), wall) != wall_names.end()) return true;
    }
  }
  return false;
}

config::Case load_case(const fs::path& file) {
  return parse(YamlNode::parse_file(file), file);
}

Override parse_override(std::string_view text) {
  const auto eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0)
    throw InputError(fmt::format("--set '{}': expected KEY.PATH=VALUE, e.g. shear.rate=100", text));
  return {std::string(text.substr(0, eq)), std::string(text.substr(eq + 1))};
}

namespace {

/// The value of an override as YAML (so that lists work: sweep.shear_rate=[50, 100]).
YAML::Node value_node(const Override& o) {
  try {
    return YAML::Load(o.value);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("--set {}={}: not a YAML value ({})", o.path, o.value, e.msg));
  }
}

}  // namespace

namespace {
/// Keys of one map of which a case gives at most one, where switching from the command line is
/// expected (an output or sampling interval in seconds or in strain; a fill by count or by
/// volume fraction): --set of one removes the other. Other one-of choices stay errors.
const std::vector<std::vector<const char*>> kAlternativeKeys = {{"every", "every_strain"},
                                                                {"count", "volume_fraction"}};
}  // namespace

void apply_overrides(const YAML::Node& root, const std::vector<Override>& overrides,
                     const fs::path& file) {
  for (const auto& o : overrides) {
    YAML::Node node = root;
    std::string_view rest = o.path;
    std::string done;
    while (!rest.empty()) {
      // Next step: "key", "key[i]" or "[i]".
      const auto dot = rest.find('.');
      std::string_view step = rest.substr(0, dot);
      rest = dot == std::string_view::npos ? std::string_view{} : rest.substr(dot + 1);
      const auto br = step.find('[');
      const std::string key(step.substr(0, br));
      auto fail = [&](std::string_view why) -> void {
        throw InputError(fmt::format("{}: --set {}={}: {}", file.string(), o.path, o.value, why));
      };
      if (key.empty() && br != 0) fail("empty key");
      const bool last_step = rest.empty() && br == std::string_view::npos;
      if (!key.empty()) {
        if (!node.IsMap() && !node.IsNull())
          fail(fmt::format("'{}' is not a map", done.empty() ? "the case" : done));
        done += (done.empty() ? "" : ".") + key;
        if (last_step) {
          // A key given instead of an alternative replaces it (--set output.vtk.every=0 on a
          // case with output.vtk.every_strain).
          for (const auto& group : kAlternativeKeys)
            if (std::find(group.begin(), group.end(), key) != group.end())
              for (const char* other : group)
                if (other != key && node[other]) node.remove(other);
          node[key] = value_node(o);
          note_override(o.path, fmt::format("{}={}", o.path, o.value));
          break;
        }
        if (!node[key]) node[key] = YAML::Node(YAML::NodeType::Map);
        YAML::Node child = node[key];
        node.reset(child);
      }
      std::string_view idx = br == std::string_view::npos ? std::string_view{} : step.substr(br);
      while (!idx.empty()) {
        const auto close = idx.find(']');
        if (idx.front() != '[' || close == std::string_view::npos) fail("malformed [index]");
        const std::string num(idx.substr(1, close - 1));
        idx = idx.substr(close + 1);
        std::size_t pos = 0;
        long i = -1;
        try {
          i = std::stol(num, &pos);
        } catch (const std::exception&) {
        }
        if (pos != num.size() || i < 0) fail(fmt::format("'[{}]' is not a list index", num));
        if (!node.IsSequence() || static_cast<std::size_t>(i) >= node.size())
          fail(fmt::format("'{}' has no item [{}]", done, i));
        done += fmt::format("[{}]", i);
        if (rest.empty() && idx.empty()) {
          node[static_cast<std::size_t>(i)] = value_node(o);
          note_override(o.path, fmt::format("{}={}", o.path, o.value));
          break;
        }
        YAML::Node child = node[static_cast<std::size_t>(i)];
        node.reset(child);
      }
    }
  }
}

config::Case load_case(const fs::path& file, const std::vector<Override>& overrides) {
  const YamlNode root = YamlNode::parse_file(file);
  apply_overrides(root.raw(), overrides, file);
  return parse(root, file);
}

config::Case load_case_text(const std::string& yaml_text, const fs::path& file) {
  return parse(YamlNode::parse_text(yaml_text, file.string()), file);
}

}  // namespace gf::input
