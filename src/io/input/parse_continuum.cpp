// SPDX-License-Identifier: GPL-3.0-or-later
// Reading the `continuum:` block into the SPH solver's configuration.
#include "io/input/parse_continuum.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "continuum/ktgf.hpp"
#include "continuum/rheology_registry.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "io/input/continuum_input.hpp"
#include "io/input/memory_budget.hpp"

namespace gf::input {

namespace {

struct BoxRead {
  Vec3 lo, hi;
};

BoxRead read_box(const YamlNode& n, int dim) {
  YamlMap m(n, {"min", "max"});
  BoxRead b{m.at("min").as_vec(dim), m.at("max").as_vec(dim)};
  for (int k = 0; k < dim; ++k)
    if (!(b.hi[k] > b.lo[k]))
      n.fail(fmt::format("expected max > min along every axis (axis {})", k));
  return b;
}

struct CylinderRead {
  Vec3 center, axis{0, 0, 1};
  double radius = 0, length = 0, thickness = 0;
};

/// {center, radius, thickness} (3D: also axis and length). A thickness given is > 0 (without
/// it the cylinder is solid). A wall's shell (`dx` > 0: the spacing, `reach` the kernel's support
/// 2h) is at least one particle layer dx thick, or it would have gaps for the fluid to pass;
/// thinner than 2h it adds a warning to `warnings`: fluid next to it sees past its last layer.
CylinderRead read_cylinder(const YamlNode& n, int dim, double dx = 0, double reach = 0,
                           std::vector<std::string>* warnings = nullptr) {
  YamlMap cy(n, dim == 2
                    ? std::vector<std::string>{"center", "radius", "thickness"}
                    : std::vector<std::string>{"center", "radius", "thickness", "axis", "length"});
  CylinderRead c;
  c.center = cy.at("center").as_vec(dim);
  c.radius = cy.number("radius", Range::positive());
  if (auto t = cy.find("thickness")) {
    c.thickness = t->as_number();
    if (!(c.thickness > 0))
      t->fail_expected(fmt::format("a thickness > 0 m (leave thickness out for a solid {})",
                                   dim == 2 ? "disk" : "cylinder"));
    if (dx > 0 && c.thickness < c.radius && c.thickness < dx * (1 - 1e-9))
      t->fail_expected(fmt::format(
          "a wall at least one particle spacing ({} m) thick, or its shell has gaps the fluid "
          "passes through (give 2h = 2 x smoothing_ratio x spacing = {:.3g} m or more)",
          number_text(dx), reach));
    if (warnings && c.thickness < c.radius && c.thickness < reach * (1 - 1e-9))
      warnings->push_back(
          fmt::format("{}: a wall {} m thick is thinner than the kernel's reach 2h = {:.3g} m (2 "
                      "x smoothing_ratio x spacing): fluid next to it sees past its last layer",
                      t->path(), number_text(c.thickness), reach));
  }
  if (dim == 3) {
    c.axis = cy.at("axis").as_direction(3);
    c.length = cy.number("length", Range::positive());
  }
  return c;
}

/// Lattice points of spacing dx in a box, as the solver's box_lattice: floor(L / dx) per axis.
double box_points(const Vec3& lo, const Vec3& hi, int dim, double dx) {
  double n = 1;
  for (int k = 0; k < dim; ++k) n *= std::max(1.0, std::floor((hi[k] - lo[k]) / dx + 1e-6));
  return n;
}

/// Lattice points of spacing dx in a cylinder (2D: a disk) or its shell `thickness` deep: its
/// area (times its length in 3D) over dx^dim, at least 1.
double cylinder_points(double radius, double length, double thickness, int dim, double dx) {
  const double inner = thickness > 0 && thickness < radius ? radius - thickness : 0.0;
  const double area = std::numbers::pi * (radius * radius - inner * inner) / (dx * dx);
  return std::max(1.0, area * (dim == 3 ? std::max(1.0, std::floor(length / dx + 1e-6)) : 1.0));
}

/// An estimated count to 3 digits ("5.75e+08", "1.2e+04"), or "more than 1e308".
std::string count_text(double n) {
  return std::isfinite(n) ? fmt::format("{:.3g}", n) : std::string("more than 1e308");
}

/// Refuses (at `spacing`) a lattice of more particles than memory or 32-bit indices hold:
/// the blocks' and walls' lattice points, and the neighbour search's grid over the domain
/// (cells of the cut-off 2h, at most 1024 per axis); above half the memory: a warning.
void check_sph_memory(ContinuumCase& c, const YamlNode& spacing) {
  const auto& s = c.sph;
  const int dim = s.dimension;
  const double dx = s.spacing;
  double n = 0;
  for (const auto& b : s.blocks)
    n += b.shape == continuum::SphBlock::Shape::Box
             ? box_points(b.lo, b.hi, dim, dx)
             : cylinder_points(b.radius, b.length, b.thickness, dim, dx);
  for (const auto& w : s.walls)
    n += w.shape == continuum::SphWall::Shape::Box
             ? box_points(w.lo, w.hi, dim, dx)
             : cylinder_points(w.radius, w.length, w.thickness, dim, dx);
  const std::string at_spacing = fmt::format("at spacing {} m", number_text(dx));
  if (!(n <= kMaxIndexed))
    spacing.fail(
        fmt::format("expected at most {:.0f} particles (the neighbour search indexes "
                    "them with 32-bit integers), found about {} in the blocks and "
                    "walls {}",
                    kMaxIndexed, count_text(n), at_spacing));
  const double cells =
      neighbour_cells(s.domain.hi - s.domain.lo, 2.0 * s.smoothing_ratio * dx, dim, n);
  const double bytes = n * kBytesPerSphParticle + cells * kBytesPerNeighbourCell;
  if (auto w = check_memory_use(
          spacing.loc(),
          fmt::format("about {} particles (blocks and walls {}) and {} neighbour cells",
                      count_text(n), at_spacing, count_text(cells)),
          bytes))
    c.warnings.push_back(*w);
}

}  // namespace

ContinuumCase parse_continuum(const YamlNode& block) {
  ContinuumCase c;
  YamlMap m(block, {"method", "dimension", "domain", "gravity", "spacing", "smoothing_ratio",
                    "density", "sound_speed", "eos_exponent", "background_pressure",
                    "density_diffusion", "artificial_viscosity", "rheology", "kinetic_theory",
                    "time", "blocks", "walls", "output"});
  m.at("method").as_choice({"sph"});
  auto& s = c.sph;
  const int dim = static_cast<int>(m.at("dimension").as_integer({2, 3}));
  s.dimension = dim;
  {
    const auto dn = m.at("domain");
    YamlMap d(dn, {"min", "max", "periodic"});
    s.domain.lo = d.at("min").as_vec(dim);
    s.domain.hi = d.at("max").as_vec(dim);
    for (int k = 0; k < dim; ++k)
      if (!(s.domain.hi[k] > s.domain.lo[k]))
        dn.fail(fmt::format("expected max > min along every axis (axis {})", k));
    if (auto p = d.find("periodic")) {
      const auto items = p->as_list();
      if (static_cast<int>(items.size()) != dim)
        p->fail_expected(fmt::format("a list of {} booleans (one per axis)", dim));
      for (int k = 0; k < dim; ++k)
        s.domain.periodic[static_cast<std::size_t>(k)] =
            items[static_cast<std::size_t>(k)].as_bool();
    }
  }
  s.gravity = m.find("gravity") ? m.at("gravity").as_vec(dim) : Vec3{};
  s.spacing = m.number("spacing", Range::positive());
  s.smoothing_ratio = m.number_or("smoothing_ratio", 1.3, {1.0, 3.0});
  s.density = m.number("density", Range::positive());
  if (auto cs = m.optional_number("sound_speed", Range::positive())) {
    s.sound_speed = *cs;
    c.sound_speed_given = true;
  }
  s.eos_exponent = m.number_or("eos_exponent", 7.0, {1.0, 10.0});
  s.background_pressure = m.number_or("background_pressure", 0.0, Range::non_negative());
  s.density_diffusion = m.number_or("density_diffusion", 0.1, {0.0, 1.0});
  s.artificial_viscosity = m.number_or("artificial_viscosity", 0.0, {0.0, 1.0});
  {
    const auto rn = m.at("rheology");
    std::vector<std::string> keys{"model"};
    std::vector<std::string> models;
    for (const auto& info : continuum::rheology_infos()) {
      models.emplace_back(info.key);
      for (const auto& p : info.params) keys.emplace_back(p.name);
    }
    YamlMap r(rn);
    const auto model_node = r.at("model");
    c.rheology = model_node.as_string();
    const auto* info = continuum::find_rheology(c.rheology);
    if (!info) model_node.fail_expected("a rheology: " + join(models));
    std::vector<std::string> accepted{"model"};
    for (const auto& p : info->params) accepted.emplace_back(p.name);
    r.check_keys(accepted, fmt::format("parameters of rheology '{}'", c.rheology));
    const auto params = read_schema_params(r, rn, {info->params.begin(), info->params.end()},
                                           fmt::format("rheology '{}'", c.rheology));
    c.rheology_params = params;
    try {
      s.rheology = continuum::prepare_rheology(c.rheology, params);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      rn.fail(e.what());
    }
  }
  if (auto kn = m.find("kinetic_theory")) {
    // kinetic_theory: {closures, radial_distribution, restitution, grain_diameter,
    //                  grain_density, [packing_limit], initial_temperature, min_temperature,
    //                  dense: {model, ...}}; the dense regime: the rheology above a frictional
    // packing limit (default) or Schaeffer's frictional viscosity with the Johnson-Jackson
    // pressure
    const KtgfInput in =
        read_ktgf_input(*kn, {"initial_temperature", "min_temperature"}, "mu_i_switch", false);
    c.ktgf_closures = in.closures;
    c.ktgf_radial = in.radial;
    c.ktgf_dense = in.dense;
    c.ktgf_params = in.params;
    c.ktgf_dense_params = in.dense_params;
    continuum::SphKineticTheory kt;
    kt.closures = in.ktgf;
    kt.dense = *in.frictional;
    YamlMap k(*kn);
    kt.initial_temperature = k.number_or("initial_temperature", 0.0, Range::non_negative());
    kt.min_temperature = k.number_or("min_temperature", 1e-10, Range::positive());
    s.kinetic_theory = kt;
  }
  {
    YamlMap t(m.at("time"), {"end", "cfl", "max_step", "viscous"});
    c.end_time = t.number("end", Range::positive());
    s.cfl = t.number_or("cfl", 0.2, {0.01, 0.5});
    s.max_step = t.number_or("max_step", 1e30, Range::positive());
    if (auto v = t.find("viscous"))
      s.implicit_viscosity = v->as_choice({"explicit", "implicit"}) == "implicit";
  }
  for (const auto& bn : m.at("blocks").as_list(1)) {
    YamlMap b(bn, {"box", "cylinder", "velocity", "hydrostatic", "volume_fraction"});
    continuum::SphBlock blk;
    if (b.exactly_one_of({"box", "cylinder"}) == "box") {
      const auto box = read_box(b.at("box"), dim);
      blk.lo = box.lo;
      blk.hi = box.hi;
    } else {
      const auto cy = read_cylinder(b.at("cylinder"), dim);
      blk.shape = continuum::SphBlock::Shape::Cylinder;
      blk.center = cy.center;
      blk.axis = cy.axis;
      blk.radius = cy.radius;
      blk.length = cy.length;
      blk.thickness = cy.thickness;
      // lo, hi: its bounding box (for the default sound speed below)
      for (int k = 0; k < dim; ++k) {
        const double a = dim == 2 ? 0.0 : cy.axis[k];
        const double half =
            cy.radius * std::sqrt(std::max(0.0, 1.0 - a * a)) + 0.5 * cy.length * std::fabs(a);
        blk.lo[k] = cy.center[k] - half;
        blk.hi[k] = cy.center[k] + half;
      }
    }
    if (b.find("velocity")) blk.velocity = b.at("velocity").as_vec(dim);
    blk.hydrostatic = b.boolean_or("hydrostatic", false);
    if (auto vf = b.find("volume_fraction")) {
      if (!m.has("kinetic_theory"))
        vf->fail(
            "a block's volume fraction needs kinetic_theory (without it the continuum has "
            "the reference density)");
      if (blk.hydrostatic) vf->fail("a block with a volume fraction cannot be hydrostatic");
      blk.volume_fraction = vf->as_number({0.0, 1.0, true, true});
    }
    s.blocks.push_back(blk);
  }
  if (auto wl = m.find("walls")) {
    for (const auto& wn : wl->as_list()) {
      YamlMap w(wn, {"name", "box", "cylinder", "velocity", "angular_velocity", "rotation_center",
                     "initial_angle", "slip"});
      continuum::SphWall wall;
      wall.name = w.string("name");
      for (const auto& other : s.walls)
        if (other.name == wall.name) w.at("name").fail("duplicate wall name");
      const auto kind = w.exactly_one_of({"box", "cylinder"});
      if (kind == "box") {
        const auto box = read_box(w.at("box"), dim);
        wall.lo = box.lo;
        wall.hi = box.hi;
      } else {
        wall.shape = continuum::SphWall::Shape::Cylinder;
        const double reach = 2.0 * s.smoothing_ratio * s.spacing;
        const auto cy = read_cylinder(w.at("cylinder"), dim, s.spacing, reach, &c.warnings);
        wall.center = cy.center;
        wall.axis = cy.axis;
        wall.radius = cy.radius;
        wall.length = cy.length;
        wall.thickness = cy.thickness;
      }
      if (w.find("velocity")) wall.velocity = w.at("velocity").as_vec(dim);
      // Rigid rotation: 2D a rate about z (a number), 3D a vector; about rotation_center
      // (default: the box's centre or the cylinder's center), the lattice first turned by
      // initial_angle about the same axis.
      if (auto av = w.find("angular_velocity")) {
        if (dim == 2) {
          if (!av->is_scalar())
            av->fail_expected("a number in a 2D case (the rotation rate about z, rad/s)");
          wall.angular_velocity = {0, 0, av->as_number()};
        } else {
          wall.angular_velocity = av->as_vec(3);
        }
      }
      if (auto rc = w.find("rotation_center")) wall.rotation_center = rc->as_vec(dim);
      if (auto ia = w.find("initial_angle")) {
        wall.initial_angle = ia->as_number();
        if (dim == 3 && wall.initial_angle != 0.0 && norm2(wall.angular_velocity) == 0.0)
          ia->fail(
              "in 3D an initial_angle turns the wall about its angular_velocity, which is zero or "
              "not given");
      }
      // slip: no_slip | free_slip | {slip_length: b} (partial, Navier) |
      // {specularity: phi', wall_restitution: e_w} (Johnson-Jackson, kinetic theory only)
      if (auto sl = w.find("slip")) {
        if (sl->is_map()) {
          YamlMap ps(*sl, {"slip_length", "specularity", "wall_restitution"});
          const bool jj = ps.has("specularity") || ps.has("wall_restitution");
          if (jj && ps.has("slip_length"))
            sl->fail(
                "either {slip_length: b} (Navier slip) or {specularity: phi', wall_restitution: "
                "e_w} (Johnson-Jackson), not both");
          if (!jj) {
            wall.slip_length = ps.number("slip_length", Range::positive());
          } else {
            if (!m.has("kinetic_theory"))
              ps.at(ps.has("specularity") ? "specularity" : "wall_restitution")
                  .fail(
                      "the Johnson-Jackson wall condition (specularity, wall_restitution) needs "
                      "kinetic_theory: it acts through the granular temperature (without it, "
                      "give {slip_length: b})");
            continuum::SphWall::JohnsonJackson j;
            j.specularity = ps.number("specularity", {0.0, 1.0});
            j.wall_restitution = ps.number("wall_restitution", {0.0, 1.0});
            wall.johnson_jackson = j;
          }
        } else {
          if (!sl->is_scalar())
            sl->fail_expected(
                "no_slip, free_slip, {slip_length: b} (partial slip, m) or {specularity: phi', "
                "wall_restitution: e_w} (Johnson-Jackson, kinetic theory)");
          wall.free_slip = sl->as_choice({"no_slip", "free_slip"}) == "free_slip";
        }
      }
      s.walls.push_back(wall);
    }
  }
  check_sph_memory(c, m.at("spacing"));
  for (const auto& w : c.warnings) log::warn("{}", w);
  if (auto on = m.find("output")) {
    const OutputSchedule o = read_output_schedule(*on);
    c.output = o;
  }
  if (!c.sound_speed_given) {
    // c0 = 10 sqrt(2 |g| H): ten times the speed of a free fall over the fluid's height H (its
    // extent along gravity), so that density varies by about 1 % (Monaghan 1994).
    const double g = norm(s.gravity);
    if (!(g > 0))
      block.fail(
          "[missing key] sound_speed: without gravity it has no default; give about ten "
          "times the largest expected speed");
    double lo = 1e300, hi = -1e300;
    const Vec3 down = s.gravity / g;
    for (const auto& b : s.blocks)
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 x{corner & 1 ? b.hi.x : b.lo.x, corner & 2 ? b.hi.y : b.lo.y,
                     corner & 4 ? b.hi.z : b.lo.z};
        lo = std::min(lo, dot(down, x));
        hi = std::max(hi, dot(down, x));
      }
    s.sound_speed = 10.0 * std::sqrt(2.0 * g * std::max(hi - lo, s.spacing));
  }
  return c;
}

}  // namespace gf::input
