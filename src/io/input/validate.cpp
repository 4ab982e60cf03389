// SPDX-License-Identifier: GPL-3.0-or-later
// Whole-case checks: materials and pairs, particles in the domain, overlaps, time step limits.
#include "io/input/validate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string_view>

#include "contact/geometry/capsule.hpp"
#include "contact/geometry/polygon2d.hpp"
#include "contact/registry.hpp"
#include "core/error.hpp"
#include "coupling/cfd_dem/heat_transfer.hpp"
#include "io/input/memory_budget.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double pi = std::numbers::pi;

/// The given vertices of a polygon, recentred on their centroid (as the simulation does).
ConvexPolygon centred_vertices(const config::PolygonSpec& p) {
  ConvexPolygon poly;
  poly.n = static_cast<int>(std::min<std::size_t>(p.vertices.size(), kMaxPolygonVertices));
  for (int k = 0; k < poly.n; ++k) poly.v[k] = {p.vertices[k].x, p.vertices[k].y};
  const auto pr = contact::polygon_properties(poly);
  for (int k = 0; k < poly.n; ++k) poly.v[k] = poly.v[k] - pr.centroid;
  return poly;
}

double circumradius(const ConvexPolygon& poly) {
  double r = 0;
  for (int k = 0; k < poly.n; ++k) r = std::max(r, norm(poly.v[k]));
  return r;
}

/// Circumradius of a regular n-gon of equal-area radius 1: pi R^2 = (n/2) R_c^2 sin(2 pi / n).
double regular_reach_factor(int n) {
  return std::sqrt(2 * pi / (n * std::sin(2 * pi / n)));
}

}  // namespace

double cylinder_length(const config::ParticleGroup& g, double r) {
  if (g.kind != config::Shape::Spherocylinder) return 0;
  if (g.length) return *g.length;
  if (g.aspect_ratio) return 2 * r * (*g.aspect_ratio - 1);
  return 0;
}

double polygon_reach_factor(const config::PolygonSpec& p) {
  switch (p.kind) {
    case config::PolygonSpec::Kind::Vertices: {
      const ConvexPolygon poly = centred_vertices(p);
      const double r_eq = contact::polygon_properties(poly).equivalent_radius;
      return r_eq > 0 ? circumradius(poly) / r_eq : 1.0;
    }
    case config::PolygonSpec::Kind::Regular:
      return regular_reach_factor(p.sides);
    case config::PolygonSpec::Kind::Random:
      break;
  }
  // Random polygons are drawn at run time: sample the generator the simulation uses (fixed seed,
  // so the estimate is reproducible) at the two ends and the middle of the elongation range.
  std::mt19937_64 rng(20240611);
  double factor = 0;
  const int lo = std::clamp(p.min_vertices, 3, kMaxPolygonVertices);
  const int hi = std::clamp(p.max_vertices, lo, kMaxPolygonVertices);
  for (int n = lo; n <= hi; ++n)
    for (double e :
         {p.min_elongation, 0.5 * (p.min_elongation + p.max_elongation), p.max_elongation})
      for (int draw = 0; draw < 2000 / (hi - lo + 1) + 100; ++draw)
        factor = std::max(
            factor, circumradius(contact::random_convex_polygon(rng, n, 1.0, std::max(1.0, e))));
  // 5 % above the sample's largest: the simulation (simulation/shape_builder.cpp) uses this
  // same bound and redraws the rare outline beyond it, so no grain ever exceeds it.
  return 1.05 * factor;
}

double bounding_radius(const config::ParticleGroup& g, double r) {
  switch (g.kind) {
    case config::Shape::Sphere:
    case config::Shape::Disk:
      return r;
    case config::Shape::Spherocylinder:
      return r + 0.5 * cylinder_length(g, r);
    case config::Shape::Polygon:
      if (g.polygon.kind == config::PolygonSpec::Kind::Vertices)
        return circumradius(centred_vertices(g.polygon));
      return r * polygon_reach_factor(g.polygon);
  }
  return r;
}

double grain_measure(const config::ParticleGroup& g, double r) {
  switch (g.kind) {
    case config::Shape::Sphere:
      return 4.0 / 3.0 * pi * r * r * r;
    case config::Shape::Spherocylinder:
      return pi * r * r * cylinder_length(g, r) + 4.0 / 3.0 * pi * r * r * r;
    case config::Shape::Disk:
      return pi * r * r;
    case config::Shape::Polygon:
      if (g.polygon.kind == config::PolygonSpec::Kind::Vertices)
        return contact::polygon_properties(centred_vertices(g.polygon)).area;
      return pi * r * r;
  }
  return 0;
}

Vec3 grain_extent(const config::Fill& f, const config::ParticleGroup& g, double r) {
  const double reach = bounding_radius(g, r);
  if (g.kind != config::Shape::Spherocylinder || !f.orientation) return {reach, reach, reach};
  const double h = 0.5 * cylinder_length(g, r);
  const Vec3 u = rotate(*f.orientation, Vec3{0, 0, 1});
  return {r + h * std::fabs(u.x), r + h * std::fabs(u.y), r + h * std::fabs(u.z)};
}

std::pair<Vec3, Vec3> region_bounds(const config::Region& r) {
  if (r.kind == config::Region::Kind::Box) return {r.min, r.max};
  Vec3 lo, hi;
  const Vec3 a = r.axis, top = r.center + r.height * a;
  for (int k = 0; k < 3; ++k) {
    const double across = r.radius * std::sqrt(std::max(0.0, 1.0 - a[k] * a[k]));
    lo[k] = std::min(r.center[k], top[k]) - across;
    hi[k] = std::max(r.center[k], top[k]) + across;
  }
  return {lo, hi};
}

double region_measure(const config::Region& region, int dimension) {
  if (region.kind == config::Region::Kind::Cylinder)
    return pi * region.radius * region.radius * (dimension == 2 ? 1.0 : region.height);
  const Vec3 len = region.max - region.min;
  return dimension == 2 ? len.x * len.y : len.x * len.y * len.z;
}

std::int64_t volume_fraction_count(const config::Fill& f, const config::ParticleGroup& g,
                                   int dimension) {
  if (!f.volume_fraction) return f.count.value_or(0);
  const double n = *f.volume_fraction * region_measure(f.region, dimension) /
                   grain_measure(g, g.radius.largest());
  // (capped where llround would overflow; memory_budget refuses far fewer grains)
  return std::max<std::int64_t>(1, std::llround(std::min(n, 1e18)));
}

namespace {

std::string vec_text(const Vec3& v, int dimension) {
  if (dimension == 2) return fmt::format("[{}, {}]", number_text(v.x), number_text(v.y));
  return fmt::format("[{}, {}, {}]", number_text(v.x), number_text(v.y), number_text(v.z));
}

std::string seconds(double t) {
  return fmt::format("{:.4g} s", t);
}

/// How check's counts name a fixed group: ", fixed" (at rest), ", fixed, moving", or nothing.
const char* fixed_tag(const config::ParticleGroup& g) {
  if (g.motion) return ", fixed, moving";
  return g.fixed ? ", fixed" : "";
}

/// The smallest grain of one particle group: radius for the contact laws (sphere, disk: r;
/// spherocylinder: the cap radius; polygon: the equal-area radius) and mass.
struct SmallGrain {
  double r = 0;        ///< m
  double m = 0;        ///< kg
  bool fixed = false;  ///< of a group with fixed: true (immobile: see check_time_step)
};

/// Sizes of the grains of one material.
struct GrainSizes {
  double r_min = inf;                ///< smallest contact radius, m
  double r_min_free = inf;           ///< the same over groups that are not fixed, m
  double r_max = 0;                  ///< largest contact radius, m
  double r_max_free = 0;             ///< the same over groups that are not fixed, m
  double reach_max = 0;              ///< largest bounding radius, m
  std::vector<SmallGrain> smallest;  ///< one per group of this material
};

/// One explicit particle, for the domain and overlap checks. Spheres, disks and spherocylinders
/// (a segment c +- half_axis swept by r) and polygons of known outline are checked exactly;
/// random polygons (drawn at run time) only by their inscribed and bounding radii.
struct Placed {
  Vec3 x;
  double r = 0;      ///< contact radius (sphere, disk, spherocylinder caps), m
  double reach = 0;  ///< bounding radius about x, m
  double inner = 0;  ///< radius of a sphere or disk about x inside the grain, m
  Vec3 half_axis;    ///< spherocylinder: half its segment, world frame, m
  int poly = -1;     ///< index of the outline (relative to x, world frame) in `outlines_`
  bool exact = true;
  config::Shape shape = config::Shape::Sphere;
  std::size_t group = 0;
  std::size_t index = 0;
};

class Validator {
 public:
  explicit Validator(const config::Case& c) : c_(c), dim_(c.dimension == 2 ? 2 : 3) {}
  CheckReport run();

 private:
  config::SourceLoc at(config::SourceLoc loc, const std::string& fallback_path) const {
    if (loc.file.empty()) loc.file = c_.file.string();
    if (loc.key_path.empty()) loc.key_path = fallback_path;
    return loc;
  }
  config::SourceLoc group_loc(std::size_t g) const {
    return at(c_.particles[g].loc, fmt::format("particles[{}]", g));
  }
  config::SourceLoc particle_loc(std::size_t g, std::size_t i) const;
  std::string text(const Vec3& v) const { return vec_text(v, dim_); }
  /// Bytes of one grain of the group at a run's peak (memory_budget.hpp), heat conduction's too,
  /// and the shape columns a round grain carries in a store with shaped grains.
  double grain_bytes(const config::ParticleGroup& group) const {
    const auto round = [](config::Shape k) {
      return k == config::Shape::Sphere || k == config::Shape::Disk;
    };
    const bool shaped_store = std::any_of(c_.particles.begin(), c_.particles.end(),
                                          [&](const auto& g) { return !round(g.kind); });
    return bytes_per_grain(group.kind) + (c_.heat ? kBytesPerGrainHeat : 0.0) +
           (round(group.kind) && shaped_store ? kBytesPerRoundGrainInShapedStore : 0.0);
  }
  /// Mass of a grain of group g with radius r (kg); 2D grains have the domain's thickness.
  double mass(std::size_t g, double r) const {
    const auto& group = c_.particles[g];
    return materials_.at(group.material)->density * grain_measure(group, r) *
           (dim_ == 2 ? c_.domain.thickness : 1.0);
  }
  /// Mean mass of a grain of group g over its radius distribution (kg): midpoint quadrature
  /// of the (truncated) density on 400 points of [min, max].
  double mean_mass(std::size_t g) const {
    const auto& d = c_.particles[g].radius;
    using K = config::SizeDistribution::Kind;
    if (d.kind == K::Fixed || !(d.max > d.min)) return mass(g, d.largest());
    const double sl2 = d.kind == K::Lognormal ? std::log1p(d.std * d.std / (d.mean * d.mean)) : 0;
    const double ml = d.kind == K::Lognormal ? std::log(d.mean) - 0.5 * sl2 : 0;
    double sw = 0, swm = 0;
    constexpr int kPoints = 400;
    for (int k = 0; k < kPoints; ++k) {
      const double r = d.min + (k + 0.5) * (d.max - d.min) / kPoints;
      double w = 1;  // uniform
      if (d.kind == K::Normal && d.std > 0)
        w = std::exp(-0.5 * (r - d.mean) * (r - d.mean) / (d.std * d.std));
      else if (d.kind == K::Lognormal && sl2 > 0)
        w = std::exp(-0.5 * (std::log(r) - ml) * (std::log(r) - ml) / sl2) / r;
      sw += w;
      swm += w * mass(g, r);
    }
    return sw > 0 ? swm / sw : mass(g, d.largest());
  }
  /// Grains per second an inlet of group g inserts: its rate, or its mass_rate over the mean
  /// grain's mass.
  double inlet_rate(std::size_t g) const {
    const auto& in = *c_.particles[g].inlet;
    return in.mass_rate ? *in.mass_rate / mean_mass(g) : in.rate;
  }
  /// Bounding radius of a grain of group g with radius r (cached factor for polygons).
  double reach(std::size_t g, double r) const {
    const auto& group = c_.particles[g];
    if (group.kind == config::Shape::Polygon &&
        group.polygon.kind != config::PolygonSpec::Kind::Vertices)
      return r * reach_factor_[g];
    return bounding_radius(group, r);
  }
  std::string describe(const Placed& p) const;
  /// The contact radius the simulation's default skin is half of: the largest over grains of
  /// groups that are not fixed (fixed grains never move), over all grains when every one is.
  double skin_radius() const {
    double r_free = 0, r_all = 0;
    for (const auto& [name, gs] : grains_) {
      r_free = std::max(r_free, gs.r_max_free);
      r_all = std::max(r_all, gs.r_max);
    }
    return r_free > 0 ? r_free : r_all;
  }
  /// The neighbour search's cut-off, 2 r_max + skin (r_max: the largest bounding radius), with
  /// the simulation's default skin: half the largest contact radius (cap radius of
  /// spherocylinders, equal-area radius of polygons), not of the bounding radius.
  double neighbor_cutoff() const {
    double reach_max = 0;
    for (const auto& [name, gs] : grains_) reach_max = std::max(reach_max, gs.reach_max);
    return 2 * reach_max + c_.neighbor.skin.value_or(0.5 * skin_radius());
  }

  void check_basics() const;
  void check_materials();
  void check_fills();
  /// An outlet's reinsert region must hold the largest free grain.
  void check_outlets() const;
  /// An inlet's batches fit its region, which lies inside the domain.
  void check_inlets();
  void check_explicit();
  void check_overlaps(const std::vector<Placed>& all);
  void check_periodic() const;
  void estimate_counts();
  /// Refuses (InputError) the grains of a fill that cannot fit in memory or in 32-bit indices;
  /// records them for check_memory. `est`: its grains; `sites`: the lattice sites it lists.
  void check_fill_memory(std::size_t g, const config::Fill& f, double est, double sites);
  /// The whole case's memory (grains, neighbour grid, fluid cells) against the machine's.
  void check_memory();
  void check_buoyancy(const config::Fluid& f);  ///< beta dT and gravity, with thermal_expansion
  double grains_estimate_ = 0;  ///< grains at the start (estimate_counts), for the memory check
  void check_time_step();
  /// The resting overlap under sjkr cohesion of the pair (a, b) or of a on walls (wall), with its
  /// warning when large; called by check_time_step for each pair that may touch.
  void check_cohesion(const config::Contact& ct, const contact::PairCoeffs& coeffs,
                      const std::string& a, const std::string& b, bool wall,
                      const std::string& label);
  void check_output();
  void check_fluid();
  void check_shear_walls();
  /// Warnings for moving fixed groups (docs/models/fixed_particles.md).
  void check_fixed_motion();

  const config::Case& c_;
  int dim_;
  CheckReport report_;
  std::map<std::string, const config::Material*> materials_;
  std::map<std::string, GrainSizes> grains_;     ///< particle materials only
  std::vector<std::string> particle_materials_;  ///< in order of first use
  std::map<std::pair<std::string, std::string>, const config::Contact*> contacts_;
  std::vector<double> reach_factor_;  ///< per group: polygon circumradius / equal-area radius
  std::vector<Placed> placed_;
  std::vector<ConvexPolygon> outlines_;  ///< explicit polygons, vertices relative to the centre
  /// Estimated memory use by part (memory_budget.hpp), for check_memory.
  struct MemoryPart {
    config::SourceLoc loc;
    std::string what;
    double bytes = 0;
  };
  std::vector<MemoryPart> memory_;
  double n_grains_ = 0;  ///< estimated grains of all groups
};

config::SourceLoc Validator::particle_loc(std::size_t g, std::size_t i) const {
  const auto& group = c_.particles[g];
  const auto& ex = *group.explicit_particles;
  config::SourceLoc loc = group_loc(g);
  loc.column = 0;
  loc.line = i < ex.lines.size() ? ex.lines[i] : 0;
  if (!ex.file.empty()) {
    loc.file = ex.file.string();
    loc.key_path += ".file";
  } else {
    loc.key_path += fmt::format(".positions[{}]", i);
  }
  if (loc.line == 0) loc = group_loc(g);
  return loc;
}

std::string Validator::describe(const Placed& p) const {
  switch (p.shape) {
    case config::Shape::Sphere:
    case config::Shape::Disk:
      return fmt::format("radius {}", number_text(p.r));
    case config::Shape::Spherocylinder: {
      const double h = norm(p.half_axis);
      Vec3 a = h > 0 ? p.half_axis / h : Vec3{};
      for (int k = 0; k < 3; ++k)
        if (std::abs(a[k]) < 1e-12) a[k] = 0;  // rounding noise of the rotation
      return fmt::format(
          "spherocylinder of radius {:.6g}, length {:.6g}, axis [{:.6g}, {:.6g}, "
          "{:.6g}]",
          p.r, 2 * h, a.x, a.y, a.z);
    }
    case config::Shape::Polygon:
      return fmt::format("polygon of circumradius {:.6g}", p.reach);
  }
  return {};
}

void Validator::check_basics() const {
  if (!(c_.time.step > 0) || !(c_.time.end >= c_.time.step))
    throw_input_error(at(c_.time.loc, "time.step"),
                      "expected time.step > 0 and time.end >= time.step");
  for (int k = 0; k < dim_; ++k)
    if (!(c_.domain.max[k] > c_.domain.min[k]))
      throw_input_error(at(c_.domain.loc, "domain"),
                        "expected domain.max > domain.min in every component");
  if (c_.particles.empty())
    throw_input_error(at({}, "particles"), "expected at least one particle group");
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto kind = c_.particles[g].kind;
    const bool shape_2d = kind == config::Shape::Disk || kind == config::Shape::Polygon;
    if (shape_2d != (dim_ == 2))
      throw_input_error(group_loc(g), fmt::format("shape '{}' is not available in a {}D case",
                                                  c_.particles[g].shape, dim_));
  }
}

void Validator::check_materials() {
  for (const auto& m : c_.materials) materials_[m.name] = &m;
  auto need = [&](const std::string& name, const config::SourceLoc& loc) {
    if (!materials_.count(name)) throw_input_error(loc, fmt::format("unknown material '{}'", name));
  };
  reach_factor_.assign(c_.particles.size(), 1.0);
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    need(group.material, group_loc(g));
    if (group.kind == config::Shape::Polygon)
      reach_factor_[g] = polygon_reach_factor(group.polygon);
    auto& gs = grains_[group.material];
    if (std::find(particle_materials_.begin(), particle_materials_.end(), group.material) ==
        particle_materials_.end())
      particle_materials_.push_back(group.material);
    double lo = 0, hi = 0;
    if (group.explicit_particles && !group.explicit_particles->radii.empty()) {
      const auto& r = group.explicit_particles->radii;
      lo = *std::min_element(r.begin(), r.end());
      hi = *std::max_element(r.begin(), r.end());
    } else {
      if (!(group.radius.smallest() > 0)) throw_input_error(group_loc(g), "expected a radius > 0");
      lo = group.radius.smallest();
      hi = group.radius.largest();
    }
    gs.r_min = std::min(gs.r_min, lo);
    if (!group.fixed) gs.r_min_free = std::min(gs.r_min_free, lo);
    gs.r_max = std::max(gs.r_max, hi);
    if (!group.fixed) gs.r_max_free = std::max(gs.r_max_free, hi);
    gs.reach_max = std::max(gs.reach_max, reach(g, hi));
    gs.smallest.push_back({lo, mass(g, lo), group.fixed});
  }
  for (std::size_t w = 0; w < c_.walls.size(); ++w)
    need(c_.walls[w].material, at(c_.walls[w].loc, fmt::format("walls[{}]", w)));
  for (std::size_t i = 0; i < c_.contacts.size(); ++i) {
    const auto& ct = c_.contacts[i];
    const auto loc = at(ct.loc, fmt::format("contacts[{}]", i));
    need(ct.between[0], loc);
    need(ct.between[1], loc);
    if (!contact::find_model(ct.model))
      throw_input_error(loc, fmt::format("unknown contact model '{}'", ct.model));
    contacts_[std::minmax(ct.between[0], ct.between[1])] = &ct;
    // sjkr cohesion needs a contact area: spheres, spherocylinders and disks have one (the
    // intersection of two spheres; in 2D the strip 2a x depth), a polygon overlap does not.
    const auto coh = ct.params.find("cohesion_energy_density");
    if (coh != ct.params.end() && coh->second > 0)
      for (const auto& g : c_.particles)
        if (g.kind == config::Shape::Polygon &&
            (g.material == ct.between[0] || g.material == ct.between[1])) {
          const auto kl = ct.param_locs.find("cohesion_energy_density");
          config::SourceLoc key = kl != ct.param_locs.end() ? kl->second : ct.loc;
          key.key_path = fmt::format("contacts[{}].cohesion_energy_density", i);
          key = at(key, key.key_path);
          throw_input_error(
              key,
              fmt::format("cohesion is not available for polygon grains (material '{}'): expected "
                          "0 for a pair with polygons (cohesion works for spheres, "
                          "spherocylinders and disks), found {}",
                          g.material,
                          ct.param_found.count("cohesion_energy_density")
                              ? ct.param_found.at("cohesion_energy_density")
                              : number_text(coh->second)));
        }
  }
  auto need_pair = [&](const std::string& a, const std::string& b, const config::SourceLoc& loc) {
    if (!contacts_.count(std::minmax(a, b)))
      throw_input_error(loc, fmt::format("no contacts entry for the material pair ({}, {})",
                                         std::min(a, b), std::max(a, b)));
  };
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    for (std::size_t h = 0; h <= g; ++h)
      need_pair(c_.particles[h].material, c_.particles[g].material, group_loc(g));
    for (std::size_t w = 0; w < c_.walls.size(); ++w)
      need_pair(c_.particles[g].material, c_.walls[w].material,
                at(c_.walls[w].loc, fmt::format("walls[{}]", w)));
  }
}

void Validator::check_fills() {
  const Vec3 lo = c_.domain.min, hi = c_.domain.max;
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (!group.fill) continue;
    const auto& f = *group.fill;
    const auto [flo, fhi] = region_bounds(f.region);
    for (int k = 0; k < dim_; ++k) {
      const double tol = 1e-9 * (hi[k] - lo[k]);
      if (flo[k] < lo[k] - tol || fhi[k] > hi[k] + tol) {
        config::SourceLoc loc = f.loc.line > 0 ? at(f.loc, "") : group_loc(g);
        if (loc.key_path.empty() || f.loc.line == 0)
          loc.key_path = fmt::format("particles[{}].fill", g);
        throw_input_error(
            loc, fmt::format("the fill region (bounds {} - {}) reaches outside the domain {} - {}",
                             text(flo), text(fhi), text(lo), text(hi)));
      }
    }
  }
}

void Validator::check_explicit() {
  const Vec3 lo = c_.domain.min, hi = c_.domain.max;
  std::size_t n_out = 0;
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (!group.explicit_particles) continue;
    const auto& ex = *group.explicit_particles;
    const std::size_t n = ex.positions.size();
    auto same_size = [&](std::size_t m, const char* what) {
      if (m != 0 && m != n)
        throw_input_error(group_loc(g),
                          fmt::format("expected {} {} (one per particle), found {}", n, what, m));
    };
    same_size(ex.velocities.size(), "velocities");
    same_size(ex.angular_velocities.size(), "angular velocities");
    same_size(ex.radii.size(), "radii");
    same_size(ex.orientations.size(), "orientations");
    // Body-frame outline of the group's polygons (vertices given, or a regular n-gon of
    // circumradius 1 with a vertex on the body x axis, as regular_polygon(n, R) builds it).
    ConvexPolygon body;
    if (group.kind == config::Shape::Polygon) {
      if (group.polygon.kind == config::PolygonSpec::Kind::Vertices)
        body = centred_vertices(group.polygon);
      else if (group.polygon.kind == config::PolygonSpec::Kind::Regular)
        body = contact::regular_polygon(group.polygon.sides, 1.0);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& x = ex.positions[i];
      const double r =
          ex.radii.empty() ? group.radius.largest() : ex.radii[i];  // as the simulation builds it
      const Quat q = ex.orientations.empty() ? Quat{} : ex.orientations[i];
      Placed p;
      p.x = x;
      p.r = r;
      p.shape = group.kind;
      p.group = g;
      p.index = i;
      p.reach = reach(g, r);
      p.inner = r;
      Vec3 ext_lo{r, r, r}, ext_hi{r, r, r};  // extent below and above x along each axis
      if (group.kind == config::Shape::Spherocylinder) {
        p.half_axis = rotate(q, Vec3{0, 0, 0.5 * cylinder_length(group, r)});
        for (int k = 0; k < 3; ++k) ext_lo[k] = ext_hi[k] = r + std::abs(p.half_axis[k]);
      } else if (group.kind == config::Shape::Polygon) {
        if (group.polygon.kind == config::PolygonSpec::Kind::Random) {
          // Drawn at run time: only the centroid (inside the grain) and the bounding radius.
          p.exact = false;
          p.inner = 0;
          ext_lo = ext_hi = Vec3{p.reach, p.reach, 0};
        } else {
          const double scale =
              group.polygon.kind == config::PolygonSpec::Kind::Regular ? p.reach : 1.0;
          ConvexPolygon w;
          w.n = body.n;
          ext_lo = ext_hi = Vec3{};
          p.inner = inf;
          for (int k = 0; k < body.n; ++k) {
            const Vec3 v = rotate(q, Vec3{scale * body.v[k].x, scale * body.v[k].y, 0});
            w.v[k] = {v.x, v.y};
            ext_lo = Vec3{std::max(ext_lo.x, -v.x), std::max(ext_lo.y, -v.y), 0};
            ext_hi = Vec3{std::max(ext_hi.x, v.x), std::max(ext_hi.y, v.y), 0};
          }
          for (int k = 0; k < w.n; ++k) {  // inradius about the centroid
            const Vec2 a = w.v[k], b = w.v[(k + 1) % w.n];
            p.inner = std::min(p.inner, std::abs(cross(b - a, a)) / norm(b - a));
          }
          p.poly = static_cast<int>(outlines_.size());
          outlines_.push_back(w);
        }
      }
      for (int k = 0; k < dim_; ++k) {
        if (!(x[k] >= lo[k] && x[k] <= hi[k]))
          throw_input_error(particle_loc(g, i),
                            fmt::format("particle {} at {} lies outside the domain {} - {}", i,
                                        text(x), text(lo), text(hi)));
        if (!c_.domain.periodic[k] && (x[k] - ext_lo[k] < lo[k] || x[k] + ext_hi[k] > hi[k]))
          ++n_out;
      }
      placed_.push_back(p);
    }
  }
  if (n_out > 0)
    report_.warnings.push_back(
        fmt::format("{} explicit particle(s) stick out of the domain through a non-periodic face "
                    "(centre inside, surface outside)",
                    n_out));
}

/// Distance from the point d to the convex CCW polygon `w` (0 when inside), m.
double point_polygon_distance(const Vec2& d, const ConvexPolygon& w) {
  bool inside = true;
  double best = inf;
  for (int k = 0; k < w.n; ++k) {
    const Vec2 a = w.v[k], b = w.v[(k + 1) % w.n], e = b - a;
    if (cross(e, d - a) < 0) inside = false;
    const double t = std::clamp(dot(d - a, e) / dot(e, e), 0.0, 1.0);
    best = std::min(best, norm(d - (a + t * e)));
  }
  return inside ? 0.0 : best;
}

void Validator::check_overlaps(const std::vector<Placed>& all) {
  if (all.size() < 2) return;
  double reach_max = 0;
  for (const auto& p : all) reach_max = std::max(reach_max, p.reach);
  const double h = 2 * reach_max;
  const Vec3 lo = c_.domain.min, len = c_.domain.max - c_.domain.min;
  std::int64_t n[3];
  double size[3];
  for (int k = 0; k < 3; ++k) {
    if (k >= dim_) {  // 2D: one layer of cells
      n[k] = 1;
      size[k] = 1;
      continue;
    }
    n[k] =
        std::clamp<std::int64_t>(static_cast<std::int64_t>(len[k] / h), 1, std::int64_t{1} << 20);
    size[k] = len[k] / static_cast<double>(n[k]);
  }
  auto cell_of = [&](const Vec3& x, std::int64_t ci[3]) {
    for (int k = 0; k < 3; ++k)
      ci[k] = k >= dim_ ? 0
                        : std::clamp<std::int64_t>(
                              static_cast<std::int64_t>((x[k] - lo[k]) / size[k]), 0, n[k] - 1);
  };
  auto id_of = [&](const std::int64_t ci[3]) { return (ci[0] * n[1] + ci[1]) * n[2] + ci[2]; };
  std::vector<std::pair<std::int64_t, std::size_t>> sorted(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::int64_t ci[3];
    cell_of(all[i].x, ci);
    sorted[i] = {id_of(ci), i};
  }
  std::sort(sorted.begin(), sorted.end());
  // Neighbouring cell indices along one axis (all cells when there are at most three).
  auto neighbours = [&](int k, std::int64_t c, std::int64_t out[3]) {
    int m = 0;
    if (n[k] <= 3) {
      for (std::int64_t j = 0; j < n[k]; ++j) out[m++] = j;
      return m;
    }
    for (std::int64_t d = -1; d <= 1; ++d) {
      std::int64_t j = c + d;
      if (j < 0 || j >= n[k]) {
        if (!c_.domain.periodic[k]) continue;
        j = (j + n[k]) % n[k];
      }
      out[m++] = j;
    }
    return m;
  };
  // Whether grains p (at x_j + dx) and q overlap; `detail` says how.
  auto overlap = [&](const Placed& p, const Placed& q, const Vec3& dx, std::string& detail) {
    const double dist = norm(dx);
    if (!p.exact || !q.exact) {
      const double sure = p.inner + q.inner;
      if (dist < sure * (1 - 1e-9) || dist <= 1e-9 * (p.reach + q.reach)) {
        detail = dist < sure * (1 - 1e-9)
                     ? fmt::format(
                           "centre distance {:.6g} m < {:.6g} m, the sum of the radii of "
                           "circles inside the grains",
                           dist, sure)
                     : std::string("their centres coincide");
        return true;
      }
      return false;
    }
    const double reach = p.r + q.r;
    if (p.poly < 0 && q.poly < 0) {  // spheres, disks, spherocylinders: segment distance
      if (p.shape == config::Shape::Spherocylinder || q.shape == config::Shape::Spherocylinder) {
        const auto s = contact::closest_points_segments(dx - p.half_axis, dx + p.half_axis,
                                                        -q.half_axis, q.half_axis);
        const double d = std::sqrt(s.dist2);
        if (!(d < reach * (1 - 1e-9))) return false;
        detail =
            fmt::format("distance of their axes {:.6g} m < {:.6g} m (sum of the radii)", d, reach);
        return true;
      }
      if (!(dist < reach * (1 - 1e-9))) return false;
      detail = fmt::format("centre distance {:.6g} m < {:.6g} m", dist, reach);
      return true;
    }
    if (p.poly >= 0 && q.poly >= 0) {
      ConvexPolygon a = outlines_[p.poly];
      const ConvexPolygon& b = outlines_[q.poly];
      for (int k = 0; k < a.n; ++k) a.v[k] = a.v[k] + Vec2{dx.x, dx.y};
      contact::PolygonOverlap o;
      if (!contact::polygon_overlap(a, b, o)) return false;
      const double area =
          std::min(contact::polygon_properties(a).area, contact::polygon_properties(b).area);
      if (!(o.area > 1e-9 * area)) return false;
      detail = fmt::format("their outlines intersect (overlap area {:.6g} m^2)", o.area);
      return true;
    }
    // A disk and a polygon.
    const bool p_is_poly = p.poly >= 0;
    const ConvexPolygon& w = outlines_[p_is_poly ? p.poly : q.poly];
    const double r = p_is_poly ? q.r : p.r;
    const Vec2 d = p_is_poly ? Vec2{-dx.x, -dx.y} : Vec2{dx.x, dx.y};  // disk centre - polygon's
    const double gap = point_polygon_distance(d, w);
    if (!(gap < r * (1 - 1e-9))) return false;
    detail = gap > 0 ? fmt::format(
                           "the disk's centre is {:.6g} m from the polygon, less than "
                           "its radius",
                           gap)
                     : std::string("the disk's centre lies inside the polygon");
    return true;
  };
  std::size_t n_possible = 0;  // pairs of random polygons whose bounding circles intersect
  // The first particle (in input order) that overlaps an earlier one is reported.
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::int64_t ci[3], nb[3][3];
    int nn[3];
    cell_of(all[i].x, ci);
    for (int k = 0; k < 3; ++k) nn[k] = neighbours(k, ci[k], nb[k]);
    for (int a = 0; a < nn[0]; ++a)
      for (int b = 0; b < nn[1]; ++b)
        for (int d = 0; d < nn[2]; ++d) {
          const std::int64_t cj[3] = {nb[0][a], nb[1][b], nb[2][d]};
          const std::int64_t id = id_of(cj);
          auto range = std::equal_range(
              sorted.begin(), sorted.end(), std::pair<std::int64_t, std::size_t>{id, 0},
              [](const auto& p, const auto& q) { return p.first < q.first; });
          for (auto it = range.first; it != range.second; ++it) {
            const std::size_t j = it->second;
            if (j >= i) continue;
            Vec3 dx = all[i].x - all[j].x;
            for (int k = 0; k < dim_; ++k) {
              if (!c_.domain.periodic[k]) continue;
              if (dx[k] > 0.5 * len[k])
                dx[k] -= len[k];
              else if (dx[k] < -0.5 * len[k])
                dx[k] += len[k];
            }
            const auto& p = all[i];
            const auto& q = all[j];
            if (!(norm(dx) < p.reach + q.reach)) continue;  // bounding spheres apart
            // Fixed grains never touch one another (a rough base may be built of overlapping
            // grains); a free grain must not overlap a fixed one.
            if (c_.particles[p.group].fixed && c_.particles[q.group].fixed) continue;
            std::string detail;
            if (!overlap(p, q, dx, detail)) {
              if (!p.exact || !q.exact) ++n_possible;
              continue;
            }
            throw_input_error(
                particle_loc(p.group, p.index),
                fmt::format(
                    "particle {} of particles[{}] at {} ({}) overlaps particle {} of "
                    "particles[{}] at {} ({}){}: {}",
                    p.index, p.group, text(p.x), describe(p), q.index, q.group, text(q.x),
                    describe(q),
                    q.index < c_.particles[q.group].explicit_particles->lines.size()
                        ? fmt::format(", line {}",
                                      c_.particles[q.group].explicit_particles->lines[q.index])
                        : std::string(),
                    detail));
          }
        }
  }
  if (n_possible > 0)
    report_.warnings.push_back(fmt::format(
        "{} pair(s) of explicit random polygons may overlap: their centres are closer than the "
        "sum of their estimated circumradii, and their outlines are drawn only at run time",
        n_possible));
}

void Validator::check_periodic() const {
  const double cutoff = neighbor_cutoff();
  for (int k = 0; k < dim_; ++k) {
    const double len = c_.domain.max[k] - c_.domain.min[k];
    if (c_.domain.periodic[k] && !(len > 2 * cutoff)) {
      config::SourceLoc loc = at(c_.domain.loc, "domain");
      loc.key_path = "domain.periodic";
      throw_input_error(
          loc, fmt::format("the periodic length along {} ({} m) must exceed twice the neighbour "
                           "cut-off 2 (2 r_max + skin) = {} m (r_max: the largest bounding "
                           "radius), so that a grain meets one image of another at most",
                           "xyz"[k], number_text(len), number_text(2 * cutoff)));
    }
  }
}

double mean_radius(const config::SizeDistribution& d) {
  switch (d.kind) {
    case config::SizeDistribution::Kind::Fixed:
      return d.value;
    case config::SizeDistribution::Kind::Uniform:
      return 0.5 * (d.min + d.max);
    default:
      return d.mean;
  }
}

/// Grains a lattice fill holds (bounding spheres or disks of radius `reach` entirely inside the
/// region), or the requested random count; `region_measure` is the region's volume (3D, m^3) or
/// area (2D, m^2). In 2D the hcp lattice is the hexagonal one.
double estimate_fill(const config::Fill& f, double reach, const Vec3& extent, int dim,
                     double& region_measure) {
  const double r = reach;
  const double s = f.spacing.value_or(2 * r * 1.01);
  const bool hcp = f.lattice == config::Fill::Lattice::Hcp;
  double est = 0;
  if (f.region.kind == config::Region::Kind::Box) {
    const Vec3 len = f.region.max - f.region.min;
    region_measure = dim == 2 ? len.x * len.y : len.x * len.y * len.z;
    // As boundaries/fill.cpp: a cubic lattice without spacing uses the grain's extents.
    const bool own = !hcp && !f.spacing;
    const double pitch[3] = {own ? 2 * extent.x * 1.01 : s,
                             own ? 2 * extent.y * 1.01 : (hcp ? s * std::sqrt(3.0) / 2 : s),
                             own ? 2 * extent.z * 1.01 : (hcp ? s * std::sqrt(2.0 / 3.0) : s)};
    est = 1;
    for (int k = 0; k < dim; ++k) {
      const double inner = len[k] - 2 * (hcp ? r : extent[k]);
      est *= inner < 0 ? 0 : std::floor(inner / pitch[k] + 1e-9) + 1;
    }
  } else if (dim == 2) {
    // A circle: the sites of a square (hexagonal) lattice of pitch s that keep a grain inside,
    // about the area of the inner circle per site.
    region_measure = pi * f.region.radius * f.region.radius;
    const double e = !hcp && !f.spacing ? std::max(extent.x, extent.y) : r;
    const double pitch = !hcp && !f.spacing ? 2 * e * 1.01 : s;
    const double rr = f.region.radius - e;
    est =
        rr < 0 ? 0 : std::floor(pi * rr * rr / (pitch * pitch) * (hcp ? 2 / std::sqrt(3.0) : 1.0));
  } else {
    region_measure = pi * f.region.radius * f.region.radius * f.region.height;
    const Vec3& ax = f.region.axis;
    if (!hcp && !f.spacing) {
      // A cubic lattice with the grain's own pitch (aligned spherocylinders): the grain's extent
      // along the cylinder's axis and across it.
      double along = 0, across = 0;
      for (int k = 0; k < 3; ++k) {
        along += std::abs(ax[k]) * extent[k];
        across = std::max(across, extent[k] * std::sqrt(std::max(0.0, 1 - ax[k] * ax[k])));
      }
      const double rr = f.region.radius - across, hh = f.region.height - 2 * along;
      const double cell = 8 * extent.x * extent.y * extent.z * 1.01 * 1.01 * 1.01;
      est = (rr < 0 || hh < 0) ? 0 : std::floor(pi * rr * rr * hh / cell);
    } else {
      const double rr = f.region.radius - r, hh = f.region.height - 2 * r;
      est = (rr < 0 || hh < 0) ? 0 : pi * rr * rr * hh / (s * s * s) * (hcp ? std::sqrt(2.0) : 1.0);
      est = std::floor(est);
    }
  }
  if (f.lattice == config::Fill::Lattice::Random)
    est = f.count ? static_cast<double>(*f.count) : 0.0;
  if (f.count) est = std::min(est, static_cast<double>(*f.count));
  return est;
}

void Validator::estimate_counts() {
  double total = 0;
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (group.fill) {
      config::Fill f = *group.fill;
      double measure = 0;
      const double r_big = reach(g, group.radius.largest());
      const Vec3 extent = grain_extent(f, group, group.radius.largest());
      std::optional<double> sites;
      if (f.volume_fraction) {
        sites = estimate_fill(f, r_big, extent, dim_, measure);
        f.count = volume_fraction_count(f, group, dim_);
        report_.derived.emplace_back(fmt::format("particles[{}]: grains for volume_fraction {}", g,
                                                 number_text(*f.volume_fraction)),
                                     fmt::format("{}", *f.count));
      }
      const double est = estimate_fill(f, r_big, extent, dim_, measure);
      if (sites && f.lattice != config::Fill::Lattice::Random && *sites < *f.count)
        throw_input_error(
            f.loc,
            fmt::format("particles[{}].fill: the lattice has about {:.0f} sites, fewer than the "
                        "{} grains volume_fraction {} asks for (give a smaller spacing, a "
                        "fixed orientation for elongated grains, or a larger region)",
                        g, *sites, *f.count, number_text(*f.volume_fraction)));
      // A lattice fill that takes a volume fraction's grains at random lists all its sites.
      check_fill_memory(g, f, est,
                        sites && f.lattice != config::Fill::Lattice::Random ? *sites : 0.0);
      const char* lattice = f.lattice == config::Fill::Lattice::Cubic ? "cubic"
                            : f.lattice == config::Fill::Lattice::Hcp
                                ? (dim_ == 2 ? "hexagonal" : "hcp")
                                : "random";
      report_.derived.emplace_back(
          fmt::format("particles[{}]: grains (fill, {}{})", g, lattice, fixed_tag(group)),
          fmt::format("{}{:.0f}", f.lattice == config::Fill::Lattice::Random ? "" : "~", est));
      total += est;
      if (est < 1)
        report_.warnings.push_back(fmt::format(
            "particles[{}]: the fill region is too small to hold a grain of {} radius {} m", g,
            group.kind == config::Shape::Sphere || group.kind == config::Shape::Disk ? ""
                                                                                     : "bounding",
            number_text(r_big)));
      if (f.lattice == config::Fill::Lattice::Random && measure > 0) {
        const double fraction = est * grain_measure(group, mean_radius(group.radius)) / measure;
        // Random sequential insertion jams near 0.38 (spheres) and 0.55 (disks).
        const double usual = dim_ == 2 ? 0.5 : 0.35;
        report_.derived.emplace_back(
            fmt::format("particles[{}]: solid {} fraction asked of the random fill", g,
                        dim_ == 2 ? "area" : "volume"),
            fmt::format("{:.3f}", fraction));
        if (fraction >= 1.0)
          throw_input_error(at(f.loc, fmt::format("particles[{}].fill", g)),
                            fmt::format("expected grains that fit in the region without "
                                        "overlapping, found a solid {} fraction of {:.3g} asked",
                                        dim_ == 2 ? "area" : "volume", fraction));
        if (fraction > usual)
          report_.warnings.push_back(
              fmt::format("particles[{}]: a random fill rarely exceeds a solid fraction of about "
                          "{}; {:.2f} is asked",
                          g, usual, fraction));
        if (group.kind == config::Shape::Spherocylinder || group.kind == config::Shape::Polygon) {
          // Non-round grains inserted at random orientations need room for their bounding
          // spheres (disks) when they are placed without overlap tests on the exact shape.
          const double rb = reach(g, mean_radius(group.radius));
          const double round_measure = dim_ == 2 ? pi * rb * rb : 4.0 / 3.0 * pi * rb * rb * rb;
          const double bounding_fraction = est * round_measure / measure;
          report_.derived.emplace_back(
              fmt::format("particles[{}]: the same for the bounding {} of the grains", g,
                          dim_ == 2 ? "disks" : "spheres"),
              fmt::format("{:.3f}", bounding_fraction));
          if (bounding_fraction > usual && fraction <= usual)
            report_.warnings.push_back(fmt::format(
                "particles[{}]: the bounding {} of the {} grains fill {:.2f} of the region; a "
                "random insertion that keeps them apart rarely exceeds about {} (enlarge the "
                "region or reduce count)",
                g, dim_ == 2 ? "disks" : "spheres", group.shape, bounding_fraction, usual));
        }
      } else if (f.count && est < 0.8 * static_cast<double>(*f.count)) {
        // The estimate is a few per cent off for cylinders: warn only when clearly short.
        report_.warnings.push_back(
            fmt::format("particles[{}]: the lattice holds only ~{:.0f} grains, well below count {}",
                        g, est, *f.count));
      }
    } else if (group.inlet) {
      const auto& in = *group.inlet;
      const double until = std::min(in.stop.value_or(c_.time.end), c_.time.end);
      const double n = std::ceil(inlet_rate(g) * std::max(0.0, until - in.start + in.every));
      report_.derived.emplace_back(fmt::format("particles[{}]: grains (inlet, by the end)", g),
                                   fmt::format("{:.0f}", n));
      total += n;
      n_grains_ += n;
      memory_.push_back(
          {at(in.rate_loc,
              fmt::format("particles[{}].inlet.{}", g, in.mass_rate ? "mass_rate" : "rate")),
           fmt::format("the {:.0f} grains of particles[{}]", n, g), n * grain_bytes(group)});
    } else if (group.explicit_particles) {
      const auto& ex = *group.explicit_particles;
      const double n = static_cast<double>(ex.positions.size());
      report_.derived.emplace_back(
          fmt::format("particles[{}]: grains (explicit{}{})", g,
                      ex.file.empty() ? "" : ", " + ex.file.filename().string(), fixed_tag(group)),
          fmt::format("{:.0f}", n));
      total += n;
      n_grains_ += n;
      memory_.push_back({group_loc(g), fmt::format("the {:.0f} grains of particles[{}]", n, g),
                         n * grain_bytes(group)});
    }
    if (group.kind != config::Shape::Sphere) {
      const double r = group.explicit_particles && !group.explicit_particles->radii.empty()
                           ? *std::max_element(group.explicit_particles->radii.begin(),
                                               group.explicit_particles->radii.end())
                           : group.radius.largest();
      std::string what;
      switch (group.kind) {
        case config::Shape::Spherocylinder:
          what = fmt::format("r = {:.4g} m, L = {:.4g} m", r, cylinder_length(group, r));
          break;
        case config::Shape::Polygon:
          what = fmt::format("equal-area radius {:.4g} m", r);
          break;
        default:
          what = fmt::format("r = {:.4g} m", r);
      }
      report_.derived.emplace_back(
          fmt::format("particles[{}]: {} grains, largest ({})", g, group.shape, what),
          fmt::format("mass {:.4g} kg, bounding radius {:.4g} m", mass(g, r), reach(g, r)));
    }
  }
  report_.derived.emplace_back("grains in total", fmt::format("~{:.0f}", total));
  grains_estimate_ = total;
}

void Validator::check_fill_memory(std::size_t g, const config::Fill& f, double est, double sites) {
  // The key that sets the number: count (volume_fraction), else a lattice's spacing or region.
  config::SourceLoc loc = f.count_loc;
  const bool capped = f.count && est >= static_cast<double>(*f.count);
  if (f.lattice != config::Fill::Lattice::Random && !capped && !f.volume_fraction)
    loc = f.spacing_loc.file.empty() ? f.region_loc : f.spacing_loc;
  loc = at(loc.file.empty() ? f.loc : loc, fmt::format("particles[{}].fill", g));
  n_grains_ += est;
  if (est > kMaxIndexed || n_grains_ > kMaxIndexed)
    throw_input_error(
        loc, fmt::format("expected at most {:.0f} grains in all (the neighbour search indexes "
                         "them with 32-bit integers), found {}{}",
                         kMaxIndexed, number_text(std::round(est)),
                         n_grains_ > est
                             ? fmt::format(" here, {} in all", number_text(std::round(n_grains_)))
                             : std::string()));
  const std::string grains =
      fmt::format("{} grains{}", number_text(std::round(est)),
                  sites > 0 ? fmt::format(" (and the {} lattice sites they are picked from)",
                                          number_text(std::round(sites)))
                            : std::string());
  const double bytes = est * grain_bytes(c_.particles[g]) + sites * kBytesPerLatticeSite;
  check_memory_use(loc, grains, bytes);  // throws above the limit (the total warns)
  memory_.push_back({loc, fmt::format("the {} of particles[{}]", grains, g), bytes});
}

void Validator::check_buoyancy(const config::Fluid& f) {
  // The span of the temperatures the case sets (fluid, its boundaries, grains, walls): the
  // Boussinesq buoyancy takes the density change beta dT as small.
  const double base = c_.heat ? c_.heat->temperature : 0.0;
  double lo = f.temperature.value_or(base), hi = lo;
  const auto take = [&](double t) {
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  };
  if (f.reference_temperature) take(*f.reference_temperature);
  for (const auto& b : f.boundary)
    if (b.temperature) take(*b.temperature);
  for (const auto& g : c_.particles) take(g.temperature.value_or(base));
  for (const auto& w : c_.walls)
    if (w.temperature) take(*w.temperature);
  const double beta_dt = f.thermal_expansion * (hi - lo);
  report_.derived.emplace_back("buoyancy: beta x the case's temperature span",
                               fmt::format("{:.3g} ({:.4g} - {:.4g} K)", beta_dt, lo, hi));
  if (beta_dt > 0.1)
    report_.warnings.push_back(fmt::format(
        "fluid.thermal_expansion: beta x the temperature span {:.4g} - {:.4g} K is {:.3g}; the "
        "Boussinesq buoyancy assumes density changes well below 10 % (the flow stays "
        "incompressible, and the heated fluid keeps its density elsewhere)",
        lo, hi, beta_dt));
  if (norm(c_.gravity) == 0)
    report_.warnings.push_back(
        "fluid.thermal_expansion: the case has no gravity, so the buoyancy does nothing");
}

void Validator::check_memory() {
  // The neighbour search's grid over the domain (as check_periodic: cut-off 2 r_max + skin).
  if (const double cutoff = neighbor_cutoff(); cutoff > 0) {
    const double cells =
        neighbour_cells(c_.domain.max - c_.domain.min, cutoff, dim_, grains_estimate_);
    config::SourceLoc loc = at(c_.domain.loc, "domain");
    const std::string what = fmt::format(
        "the neighbour search's {} cells (of at least the cut-off {:.3g} m, at most 1024 per "
        "axis and max(2^20, 8 per grain) in all, over the domain)",
        number_text(cells), cutoff);
    check_memory_use(loc, what, cells * kBytesPerNeighbourCell);
    memory_.push_back({loc, what, cells * kBytesPerNeighbourCell});
  }
  if (c_.fluid) {
    const auto& f = *c_.fluid;
    const double cells = static_cast<double>(f.cells[0]) * f.cells[1] * f.cells[2];
    config::SourceLoc loc = at(f.cells_loc.file.empty() ? f.loc : f.cells_loc, "fluid.cells");
    const std::string what = fmt::format("{} fluid cells", number_text(cells));
    check_memory_use(loc, what, cells * kBytesPerCfdCell);
    memory_.push_back({loc, what, cells * kBytesPerCfdCell});
  }
  if (memory_.empty()) return;
  double total = 0;
  const MemoryPart* largest = &memory_.front();
  std::vector<std::string> parts;
  for (const auto& m : memory_) {
    total += m.bytes;
    if (m.bytes > largest->bytes) largest = &m;
    parts.push_back(fmt::format("{} ({})", m.what, bytes_text(m.bytes)));
  }
  report_.derived.emplace_back("memory (estimate)", fmt::format("{} (limit {})", bytes_text(total),
                                                                bytes_text(memory_limit_bytes())));
  const std::string what =
      memory_.size() == 1 ? largest->what : fmt::format("{}, together,", join(parts, "; "));
  if (auto w = check_memory_use(largest->loc, what, total)) report_.warnings.push_back(*w);
}

void Validator::check_time_step() {
  const double dt = c_.time.step;

  // Impact speed for the Hertz contact time.
  double v0 = 0;
  for (const auto& group : c_.particles) {
    if (group.fill)
      v0 = std::max(v0, norm(group.fill->velocity) + std::sqrt(3.0) * group.fill->velocity_jitter);
    if (group.explicit_particles)
      for (const auto& v : group.explicit_particles->velocities) v0 = std::max(v0, norm(v));
    if (group.inlet) v0 = std::max(v0, norm(group.inlet->velocity));
  }
  const Vec3 len = c_.domain.max - c_.domain.min;
  // The largest speed of a point moving with `m` within `reach` of the axis (< 0: anywhere in
  // the domain, whose farthest corner from the axis bounds it).
  auto motion_speed = [&](const config::Motion& m, double reach) {
    double v = norm(m.velocity);
    if (!m.rotates) return v;
    if (reach < 0) {
      reach = 0;
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p{corner & 1 ? c_.domain.max.x : c_.domain.min.x,
                     corner & 2 ? c_.domain.max.y : c_.domain.min.y,
                     corner & 4 ? c_.domain.max.z : c_.domain.min.z};
        const Vec3 d = p - m.center;
        reach = std::max(reach, norm(d - dot(d, m.axis) * m.axis));
      }
    }
    return v + std::abs(m.rate) * reach;
  };
  for (const auto& w : c_.walls)
    v0 = std::max(v0,
                  motion_speed(w.motion, w.kind == config::Wall::Kind::Cylinder ? w.radius : -1.0));
  // Fixed groups with a prescribed motion hit free grains as a moving wall does.
  for (const auto& group : c_.particles)
    if (group.motion) v0 = std::max(v0, motion_speed(*group.motion, -1.0));
  const double g = norm(c_.gravity);
  double height = 0;
  if (g > 0)
    for (int k = 0; k < dim_; ++k) height += std::abs(c_.gravity[k] / g) * len[k];
  const double v_impact = std::max(0.1, v0 + std::sqrt(2 * g * height));
  report_.derived.emplace_back(
      "impact speed used for the Hertz contact time (grain-grain: twice this, head-on)",
      fmt::format("{:.4g} m/s (initial {:.4g} m/s + free fall over {:.4g} m)", v_impact, v0,
                  height));

  auto to_material = [](const config::Material& m) {
    return Material{m.name, m.density, m.youngs_modulus, m.poisson_ratio};
  };

  double tc_min = inf;
  std::string tc_what;
  std::set<std::string> elastic;  // materials whose contacts use the elastic moduli
  // The shortest contact time over the smallest grain of each group of material a, against that
  // of each group of material b (or a wall).
  auto pair_time = [&](const std::string& a, const std::string& b, bool wall,
                       const std::string& label) {
    const config::Contact* ct = contacts_.at(std::minmax(a, b));
    const Material ma = to_material(*materials_.at(a)), mb = to_material(*materials_.at(b));
    const GrainSizes& ga = grains_.at(a);
    double r_ref = ga.r_max;
    if (!wall) r_ref = std::max(r_ref, grains_.at(b).r_max);
    contact::PairContext ctx{&ma, &mb, r_ref};
    contact::PairCoeffs coeffs;
    try {
      coeffs = contact::prepare_pair(ct->model, ctx, ct->params);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw_input_error(at(ct->loc, "contacts"),
                        fmt::format("contact model '{}': {}", ct->model, e.what()));
    }
    double tc = inf;
    for (const auto& sa : ga.smallest) {
      // Fixed grains touch neither walls nor one another; against a free grain they are at rest
      // and infinitely heavy (contact::reduced_mass): m* is the free grain's mass and the impact
      // speed that of the free grain alone.
      if (wall) {
        if (!sa.fixed) tc = std::min(tc, contact::contact_time(coeffs, sa.r, sa.m, v_impact));
        continue;
      }
      for (const auto& sb : grains_.at(b).smallest) {
        if (sa.fixed && sb.fixed) continue;
        const double r_eff = sa.r * sb.r / (sa.r + sb.r);
        if (sa.fixed || sb.fixed) {
          tc = std::min(tc, contact::contact_time(coeffs, r_eff, sa.fixed ? sb.m : sa.m, v_impact));
          continue;
        }
        // Two grains may meet head-on, each at the impact speed: twice that relative speed.
        tc = std::min(
            tc, contact::contact_time(coeffs, r_eff, sa.m * sb.m / (sa.m + sb.m), 2 * v_impact));
      }
    }
    if (!(tc < inf)) return;  // only fixed grains: they never touch
    report_.derived.emplace_back(fmt::format("contact time, {} ({})", label, ct->model),
                                 seconds(tc));
    if (coeffs.cohesion > 0) check_cohesion(*ct, coeffs, a, b, wall, label);
    if (tc < tc_min) {
      tc_min = tc;
      tc_what = fmt::format("contact time of {} ({})", label, ct->model);
    }
    if (ct->model != "hooke") {
      elastic.insert(a);
      if (!wall) elastic.insert(b);
    }
  };
  for (std::size_t i = 0; i < particle_materials_.size(); ++i)
    for (std::size_t j = 0; j <= i; ++j) {
      const auto& a = particle_materials_[j];
      const auto& b = particle_materials_[i];
      pair_time(a, b, false, fmt::format("{}-{} grains", a, b));
    }
  std::set<std::pair<std::string, std::string>> wall_pairs;
  for (const auto& w : c_.walls)
    for (const auto& pm : particle_materials_)
      if (wall_pairs.insert({pm, w.material}).second)
        pair_time(pm, w.material, true, fmt::format("{} grains on {} walls", pm, w.material));

  double tr_min = inf;
  std::string tr_what;
  for (const auto& m : particle_materials_) {
    // Over free grains only: fixed grains carry no waves through the packing (they do not move).
    const double r = grains_.at(m).r_min_free;
    if (!(r < inf)) continue;  // every grain of the material is fixed
    const double tr = contact::rayleigh_time(to_material(*materials_.at(m)), r);
    report_.derived.emplace_back(fmt::format("Rayleigh time, {} (r = {} m)", m, number_text(r)),
                                 seconds(tr));
    if (elastic.count(m) && tr < tr_min) {
      tr_min = tr;
      tr_what = fmt::format("Rayleigh time of {} grains of radius {} m", m, number_text(r));
    }
  }
  if (tr_min < inf)
    report_.derived.emplace_back("time step / Rayleigh time", fmt::format("{:.3g}", dt / tr_min));
  if (tc_min < inf)
    report_.derived.emplace_back("time step / contact time", fmt::format("{:.3g}", dt / tc_min));
  const double t_lim = std::min(tr_min, tc_min);
  if (!(t_lim < inf)) return;
  const std::string& what = tr_min <= tc_min ? tr_what : tc_what;
  if (dt > 0.3 * t_lim) {
    throw_input_error(
        at(c_.time.loc, "time.step"),
        fmt::format(
            "expected a time step <= {:.3g} s (0.3 x the {}, {:.3g} s), found '{}' ({:.2f} x)",
            0.3 * t_lim, what, t_lim, number_text(dt), dt / t_lim));
  }
  if (dt > 0.15 * t_lim)
    report_.warnings.push_back(
        fmt::format("time step {} s is {:.2f} x the {} ({:.3g} s); 0.15 x or less is safer",
                    number_text(dt), dt / t_lim, what, t_lim));
}

void Validator::check_cohesion(const config::Contact& ct, const contact::PairCoeffs& coeffs,
                               const std::string& a, const std::string& b, bool wall,
                               const std::string& label) {
  // Two equal grains of the pair (or one on a wall) at rest with no other load
  // (contact::equilibrium_overlap). The smallest and the largest radius that meet: the overlap
  // over the radius does not depend on it for hertz and grows with it for hooke, whose k_n is
  // fixed; the larger ratio is reported (the smaller radius when they agree).
  const GrainSizes& ga = grains_.at(a);
  const double r_lo = wall ? ga.r_min_free : std::min(ga.r_min, grains_.at(b).r_min);
  const double r_hi = wall ? ga.r_max_free : std::max(ga.r_max, grains_.at(b).r_max);
  if (!(r_lo < inf)) return;
  constexpr double kLarge = 0.1;  // overlap / radius beyond which the laws' assumptions fail
  double r = r_lo, ratio = -1, kc_limit = inf;
  for (const double rr : {r_lo, r_hi}) {
    double delta = 0, kc = 0;
    dispatch_index(contact::ContactModels{}, coeffs.model, [&]<class M>() {
      using Normal = typename M::Law::normal_slot;
      delta = contact::equilibrium_overlap<Normal>(coeffs, rr, wall);
      kc = contact::cohesion_for_overlap<Normal>(coeffs, rr, wall, kLarge * rr);
    });
    kc_limit = std::min(kc_limit, kc);
    if (delta / rr > ratio * (1 + 1e-9)) {
      ratio = delta / rr;
      r = rr;
    }
  }
  const std::string key =
      fmt::format("resting overlap / r under cohesion, {} (r = {} m)", label, number_text(r));
  const std::string who =
      wall ? fmt::format("a grain of radius {} m touching a wall", number_text(r))
           : fmt::format("two touching grains of radius {} m", number_text(r));
  const std::string why = fmt::format(
      "the contact laws are meant for overlaps small against the radius (LIGGGHTS' sjkr cohesion "
      "behaves the same, without a word); a cohesion_energy_density of {:.3g} J/m^3 or less keeps "
      "the resting overlap within {} x the radius",
      kc_limit, kLarge);
  const std::string whose = fmt::format("cohesion_energy_density {:.3g} J/m^3 of {} ({})",
                                        coeffs.cohesion, label, ct.model);
  if (!(ratio < inf)) {
    report_.derived.emplace_back(
        key, "none: k_c A exceeds the elastic repulsion at every overlap (cohesion always wins)");
    report_.warnings.push_back(fmt::format(
        "{} exceeds the elastic repulsion at every overlap: {}, at rest with no other load, {} "
        "(no resting overlap); {}",
        whose, who, wall ? "is pulled through the wall" : "are pulled onto each other", why));
    return;
  }
  if (ratio == 0) {
    report_.derived.emplace_back(key, "0 (the elastic repulsion exceeds k_c A at every overlap)");
    return;
  }
  report_.derived.emplace_back(key, fmt::format("{:.3g} (overlap {:.3g} m, at rest with no other "
                                                "load)",
                                                ratio, ratio * r));
  if (ratio > kLarge)
    report_.warnings.push_back(fmt::format(
        "{} pulls {}, at rest with no other load, to an overlap of {:.3g} x the radius: "
        "{}",
        whose, who, ratio, why));
}

void Validator::check_output() {
  const std::pair<const char*, double> blocks[] = {{"vtk", c_.output.vtk.every},
                                                   {"particles_csv", c_.output.particles_csv.every},
                                                   {"contacts_csv", c_.output.contacts_csv.every},
                                                   {"contacts_vtk", c_.output.contacts_vtk.every},
                                                   {"series", c_.output.series.every},
                                                   {"checkpoint", c_.output.checkpoint.every}};
  std::string counts;
  for (const auto& [name, every] : blocks) {
    if (every > c_.time.end)
      report_.warnings.push_back(
          fmt::format("output.{}.every ({} s) is longer than the run (time.end = {} s): only "
                      "the initial state will be written",
                      name, number_text(every), number_text(c_.time.end)));
    if (every <= 0) continue;
    // Outputs at t = 0, every, 2 every, ... up to time.end (checkpoints: not at t = 0).
    const bool at_start = std::string_view(name) != "checkpoint";
    const double n = std::floor(c_.time.end / every * (1 + 1e-12)) + (at_start ? 1 : 0);
    counts += fmt::format("{}{} {:.0f}", counts.empty() ? "" : ", ", name, n);
    // Past this a run's output folder becomes hard to handle (ParaView, the file system).
    constexpr double kManyFiles = 20000;
    if (std::string_view(name) != "series" && n > kManyFiles)
      report_.warnings.push_back(fmt::format(
          "output.{} writes {:.0f} times over the run (every {} s up to {} s), a file or more "
          "each time; is the interval meant to be that short?",
          name, n, number_text(every), number_text(c_.time.end)));
  }
  if (!counts.empty()) report_.derived.emplace_back("outputs over the run", counts);
  double r_max = 0, reach_max = 0;
  bool any_fixed = false;
  for (const auto& [name, gs] : grains_) {
    r_max = std::max(r_max, gs.r_max);
    reach_max = std::max(reach_max, gs.reach_max);
  }
  for (const auto& g : c_.particles) any_fixed |= g.fixed;
  report_.derived.emplace_back(
      "neighbor skin",
      c_.neighbor.skin
          ? fmt::format("{} m", number_text(*c_.neighbor.skin))
          : fmt::format("{:.4g} m (default: half the largest {}{})", 0.5 * skin_radius(),
                        reach_max > r_max ? "contact radius: cap or equal-area radius" : "radius",
                        any_fixed ? " of the grains that are not fixed" : ""));
}

void Validator::check_fluid() {
  if (!c_.fluid || !c_.coupling) return;
  const auto& f = *c_.fluid;
  const auto& cp = *c_.coupling;
  double h_min = 1e300;
  for (int k = 0; k < 3; ++k)
    h_min = std::min(h_min,
                     (c_.domain.max[k] - c_.domain.min[k]) / f.cells[static_cast<std::size_t>(k)]);
  // The largest grain (volume-equivalent diameter) sets the worst cell-to-grain ratio; its
  // material the Stokes number.
  double d = 0, rho_p = 0;
  const config::Material* material_p = nullptr;  // of the largest grain
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    const double r = group.radius.largest();
    const double dv = std::cbrt(6.0 * grain_measure(group, r) / std::numbers::pi);
    if (dv > d) {
      d = dv;
      material_p = materials_.at(group.material);
      rho_p = material_p->density;
    }
  }
  // Reference speed: the fastest inlet (superficial), else the initial fluid speed, else the
  // Stokes settling speed of the largest grain (a quiescent fluid).
  double u = 0;
  std::string u_what = "inlet superficial velocity";
  for (const auto& b : f.boundary)
    if (b.kind == config::FluidBoundary::Kind::VelocityInlet) u = std::max(u, norm(b.velocity));
  if (u == 0) {
    u = norm(f.initial_velocity);
    u_what = "initial fluid speed";
  }
  double u_courant = u;
  if (c_.shear && d > 0) {
    // Sheared grains: the slip scale is the velocity difference across a grain, rate x d
    // (Re = rho_f rate d^2 / mu, St = rho_p rate d^2 / mu, as in Mahajan et al. 2019); the
    // fastest fluid is at the walls (rate h / 2) or the Lees-Edwards images (rate h).
    u = c_.shear->rate * d;
    u_what = "shear rate x d";
    const double h = c_.domain.max.z - c_.domain.min.z;
    u_courant =
        c_.shear->rate * h * (c_.shear->boundary == config::Shear::Boundary::Walls ? 0.5 : 1.0);
  }
  const double g = norm(c_.gravity);
  if (u == 0 && d > 0) {
    u = std::abs(rho_p - f.density) * g * d * d / (18.0 * f.viscosity);
    u_what = "Stokes settling speed";
  }
  const double dt_f = cp.interval * c_.time.step;
  report_.derived.emplace_back(
      "fluid cells",
      fmt::format("{} x {} x {}, h_min = {:.4g} m", f.cells[0], f.cells[1], f.cells[2], h_min));
  if (d > 0) {
    const double ratio = h_min / d;
    report_.derived.emplace_back("cell size / particle diameter", fmt::format("{:.3g}", ratio));
    if (ratio < 3)
      report_.warnings.push_back(fmt::format(
          "fluid cells are {:.3g} particle diameters wide; unresolved CFD-DEM wants >= 3 (the "
          "fluid fraction of a cell then averages over several grains)",
          ratio));
    const double re = f.density * u * d / f.viscosity;
    const double tau_p = rho_p * d * d / (18.0 * f.viscosity);
    report_.derived.emplace_back(fmt::format("particle Reynolds number ({})", u_what),
                                 fmt::format("{:.3g} (U = {:.3g} m/s, d = {:.3g} m)", re, u, d));
    report_.derived.emplace_back("Stokes number tau_p U / d",
                                 fmt::format("{:.3g} (tau_p = {:.3g} s)", tau_p * u / d, tau_p));
  }
  if (cp.torque == "rotational") {
    // The hydrodynamic torque is explicit in the DEM step: a grain's spin relaxes to the
    // fluid's in I / R, rho_p d^2 / (60 mu) for a sphere (elongated grains take longer). The
    // smallest sphere-equivalent grain is the stiffest.
    double tau_rot = std::numeric_limits<double>::infinity();
    for (const auto& group : c_.particles) {
      const double dv =
          std::cbrt(6.0 * grain_measure(group, group.radius.smallest()) / std::numbers::pi);
      const double rho = materials_.at(group.material)->density;
      tau_rot = std::min(tau_rot, rho * dv * dv / (60.0 * f.viscosity));
    }
    if (std::isfinite(tau_rot)) {
      report_.derived.emplace_back(
          "rotational response time rho_p d^2 / (60 mu)",
          fmt::format("{:.3g} s ({:.3g} time steps)", tau_rot, tau_rot / c_.time.step));
      if (c_.time.step > 0.2 * tau_rot)
        report_.warnings.push_back(fmt::format(
            "coupling.torque: the grains' spin relaxes in {:.3g} s, {:.3g} time steps; the "
            "explicit torque wants >= 5 (below 1 it oscillates, below 1/2 it diverges): lower "
            "time.step",
            tau_rot, tau_rot / c_.time.step));
    }
  }
  if (!cp.heat_transfer.empty() && d > 0) {
    // The grains' thermal response to the fluid, m c / (h A) = rho_p c_p d^2 / (6 Nu k_f) for
    // the largest (slowest) grain at the reference slip in clear fluid, and the fluid's own
    // diffusion time across a cell.
    const int law = cfd_dem::heat_transfer_index(cp.heat_transfer);
    const double pr = f.heat_capacity * f.viscosity / f.thermal_conductivity;
    const double nu = cfd_dem::nusselt(law, f.density * u * d / f.viscosity, pr, 1.0);
    report_.derived.emplace_back("fluid Prandtl number c_p mu / k", fmt::format("{:.3g}", pr));
    const double c_p = material_p->heat_capacity.value_or(0.0);
    if (c_p > 0) {
      const double tau = rho_p * c_p * d * d / (6.0 * nu * f.thermal_conductivity);
      report_.derived.emplace_back(
          fmt::format("grain thermal response to the fluid m c / (h A) ({})", cp.heat_transfer),
          fmt::format("{:.3g} s (Nu = {:.3g}, d = {:.3g} m)", tau, nu, d));
    }
    const double alpha = f.thermal_conductivity / (f.density * f.heat_capacity);
    report_.derived.emplace_back("fluid thermal diffusion time over a cell h^2 / alpha",
                                 fmt::format("{:.3g} s", h_min * h_min / alpha));
    if (f.thermal_expansion > 0) check_buoyancy(f);
  }
  const double courant = std::max(u, u_courant) * dt_f / h_min;
  report_.derived.emplace_back("fluid time step (interval x time.step)",
                               fmt::format("{:.4g} s", dt_f));
  report_.derived.emplace_back(fmt::format("fluid Courant number at U"),
                               fmt::format("{:.3g}", courant));
  if (courant > 0.5)
    report_.warnings.push_back(fmt::format(
        "the fluid Courant number at U is {:.3g}; the interstitial speed in a bed is U / eps, and "
        "the fluid step stops above 1: lower coupling.interval",
        courant));
}

/// Spheres between shear walls that resist sliding only: a sphere can roll along a plate with
/// no slip at its contact point, so the walls pass on little of the imposed shear and the flow
/// decays (docs/models/rheology.md, momentum balance: the layer's sigma_xz stayed at twice the
/// walls' traction over strain 40 in the dilute sphere box with friction 0.5).
void Validator::check_shear_walls() {
  if (!c_.shear || c_.shear->boundary != config::Shear::Boundary::Walls) return;
  for (const auto& g : c_.particles) {
    if (g.shape != "sphere") continue;
    for (const auto& ct : c_.contacts) {
      const bool pair = (ct.between[0] == g.material && ct.between[1] == c_.shear->wall_material) ||
                        (ct.between[1] == g.material && ct.between[0] == c_.shear->wall_material);
      if (!pair) continue;
      const auto rolling = ct.params.find("rolling_friction");
      if (rolling != ct.params.end() && rolling->second > 0) continue;
      report_.warnings.push_back(fmt::format(
          "spheres of '{}' against the shear walls ('{}') have no rolling resistance: they can "
          "roll along the walls, which may then not sustain the imposed shear (the flow decays; "
          "the rheology summary's momentum balance tells); rough walls: set rolling_friction "
          "(e.g. 0.5) and friction ~1 for [{}, {}]",
          g.material, c_.shear->wall_material, g.material, c_.shear->wall_material));
      return;
    }
  }
}

CheckReport Validator::run() {
  check_basics();
  check_materials();
  check_periodic();
  check_fills();
  check_explicit();
  check_overlaps(placed_);
  estimate_counts();
  check_memory();
  check_time_step();
  check_output();
  check_fluid();
  check_shear_walls();
  check_fixed_motion();
  check_outlets();
  check_inlets();
  return std::move(report_);
}

void Validator::check_inlets() {
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (!group.inlet) continue;
    const auto& in = *group.inlet;
    const auto loc = at(in.loc, fmt::format("particles[{}].inlet", g));
    // One batch must fit the region loosely: random sequential placement jams near a solid
    // fraction of 0.38 (3D; 0.55 in 2D), and slows down well before.
    const double batch = inlet_rate(g) * in.every;
    const double r = group.radius.largest();
    // (spherocylinders are placed by the sphere that holds any of them)
    const double grain = group.kind == config::Shape::Spherocylinder
                             ? 4.0 / 3.0 * pi * std::pow(reach(g, r), 3)
                             : grain_measure(group, r);
    const double fraction = batch * grain / region_measure(in.region, dim_);
    const double limit = dim_ == 2 ? 0.3 : 0.2;
    if (fraction > limit)
      throw_input_error(
          loc, fmt::format("a batch of the inlet ({} x every = {:.4g} grains) would fill {:.0f} "
                           "% of its region; at most {:.0f} % fit at random: make the region "
                           "larger or 'every' shorter",
                           in.mass_rate ? "mass_rate / mean grain mass" : "rate", batch,
                           100 * fraction, 100 * limit));
    const auto [lo, hi] = region_bounds(in.region);
    for (int k = 0; k < dim_; ++k)
      if (lo[k] < c_.domain.min[k] || hi[k] > c_.domain.max[k])
        throw_input_error(
            loc, fmt::format("the inlet's region (bounds {} - {}) reaches outside "
                             "the domain {} - {}",
                             text(lo), text(hi), text(c_.domain.min), text(c_.domain.max)));
    if (std::min(in.stop.value_or(c_.time.end), c_.time.end) <= in.start)
      report_.warnings.push_back(
          fmt::format("{}:{}: the inlet starts at {} s, after the run's "
                      "end: it inserts nothing",
                      loc.file, loc.line, number_text(in.start)));
  }
}

void Validator::check_outlets() const {
  double reach_max = 0;  // bounding radius of the largest grain an outlet may take
  for (std::size_t g = 0; g < c_.particles.size(); ++g)
    if (!c_.particles[g].fixed)
      reach_max = std::max(reach_max, reach(g, c_.particles[g].radius.largest()));
  for (std::size_t k = 0; k < c_.outlets.size(); ++k) {
    const auto& o = c_.outlets[k];
    if (!o.reinsert) continue;
    const auto& r = *o.reinsert;
    double extent = 2 * r.radius;
    if (r.kind == config::Region::Kind::Box)
      for (int a = 0; a < dim_; ++a)
        extent = a == 0 ? r.max[a] - r.min[a] : std::min(extent, r.max[a] - r.min[a]);
    else if (dim_ == 3)
      extent = std::min(extent, r.height);
    if (extent < 2 * reach_max)
      throw_input_error(at(o.reinsert_loc, fmt::format("outlets[{}].reinsert", k)),
                        fmt::format("the reinsert region of outlet '{}' is {:.6g} m across at "
                                    "its narrowest, less than the largest grain ({:.6g} m "
                                    "across): no grain could be put back there",
                                    o.name, extent, 2 * reach_max));
  }
}

void Validator::check_fixed_motion() {
  // A moving fixed group is carried along periodic axes (wrapped), but not along others: a
  // translation that takes it farther than the box is long leaves its grains outside the box,
  // where they meet nothing. Legal (a plate may pass through), so a warning.
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (!group.motion) continue;
    const double travel_time = std::max(0.0, c_.time.end - group.motion->start);
    for (int k = 0; k < dim_; ++k) {
      const double travel = std::abs(group.motion->velocity[k]) * travel_time;
      const double length = c_.domain.max[k] - c_.domain.min[k];
      if (c_.domain.periodic[k] || !(travel > length)) continue;
      const auto loc = at(group.fixed_loc, fmt::format("particles[{}].fixed", g));
      report_.warnings.push_back(fmt::format(
          "{}:{}: the fixed group's translation carries it {} m along {} by time.end, more than "
          "the domain's length {} m along that non-periodic axis: its grains leave the box",
          loc.file, loc.line, number_text(travel), "xyz"[k], number_text(length)));
    }
  }
}

}  // namespace

CheckReport validate(const config::Case& c) {
  return Validator(c).run();
}

}  // namespace gf::input
