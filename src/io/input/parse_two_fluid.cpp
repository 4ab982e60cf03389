// SPDX-License-Identifier: GPL-3.0-or-later
// Reading the `two_fluid:` block into the two-fluid model's settings.
//
//   two_fluid:
//     dimension: 2
//     domain: {min: [0, 0], max: [0.2, 0.5]}
//     cells: [40, 100]
//     gravity: [0, -9.81]
//     fluid: {density: 1.2, viscosity: 1.8e-5}
//     solids: {closures: syamlal, radial_distribution: carnahan_starling, restitution: 0.9,
//              grain_diameter: 5e-4, grain_density: 2500, dense: {model: ...} | none,
//              temperature: algebraic | transport, initial_temperature, max_fraction,
//              specularity, wall_restitution}
//     drag: {model: gidaspow, ...parameters}
//     boundaries: {x_min: {type: periodic}, y_min: {type: inlet, velocity: [0, 0.3],
//                  superficial: true, jet: {from: 0.09, to: 0.11, velocity: [0, 3]}},
//                  y_max: {type: outlet, pressure: 0}, x_max: {type: wall, solids: free_slip}}
//     initial: {fluid_velocity: [0, 0.3], regions: [{box: {min, max}, solids_fraction: 0.55}]}
//     fraction_convection: van_leer | upwind
//     time: {end: 1.0, max_step: 1e-3, courant: 0.5}
//     output: {vtk_every: 0.05, series_every: 0.005, checkpoint_every: 0.5}
#include "io/input/parse_two_fluid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "continuum/ktgf.hpp"
#include "continuum/rheology_registry.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/names.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "io/input/continuum_input.hpp"
#include "io/input/memory_budget.hpp"

namespace gf::input {

namespace {

// The block's own spelling of the faces (echo, messages); xmin ... zmax are accepted too.
const auto& kFaceNames = kBoxFaceAliases;

/// An initial region sets the cells whose centres it holds (boundaries included; a region may
/// reach past the domain, e.g. to say "everything below y = 0.1"). One with max <= min, or one
/// that holds no cell centre (outside the domain, or a sliver between centres) would set
/// nothing: refused at `box`.
void check_region(const YamlNode& box, const TwoFluidCase::Region& r, const fluid::Grid& g) {
  std::string vlo, vhi, dlo, dhi;
  for (int k = 0; k < g.dimension; ++k) {
    const char* sep = k ? ", " : "";
    vlo += fmt::format("{}{}", sep, number_text(r.lo[k]));
    vhi += fmt::format("{}{}", sep, number_text(r.hi[k]));
    dlo += fmt::format("{}{}", sep, number_text(g.lo[k]));
    dhi +=
        fmt::format("{}{}", sep, number_text(g.lo[k] + g.n[static_cast<std::size_t>(k)] * g.h[k]));
  }
  for (int k = 0; k < g.dimension; ++k)
    if (!(r.hi[k] > r.lo[k]))
      box.fail(
          fmt::format("expected max > min along every axis, found min [{}], max [{}]", vlo, vhi));
  for (int k = 0; k < g.dimension; ++k) {
    // cell i's centre: lo + (i + 1/2) h; those in [r.lo, r.hi]
    const double tol = 1e-9;
    const double first = std::max(0.0, std::ceil((r.lo[k] - g.lo[k]) / g.h[k] - 0.5 - tol));
    const double last = std::min(static_cast<double>(g.n[static_cast<std::size_t>(k)] - 1),
                                 std::floor((r.hi[k] - g.lo[k]) / g.h[k] - 0.5 + tol));
    if (first > last)
      box.fail(fmt::format(
          "expected a region holding at least one cell centre, found min [{}], max [{}], which "
          "{} (domain [{}] - [{}], cells {} m wide along {}): it would set nothing",
          vlo, vhi,
          r.hi[k] < g.lo[k] || r.lo[k] > g.lo[k] + g.n[static_cast<std::size_t>(k)] * g.h[k]
              ? "lies outside the domain"
              : "lies between cell centres",
          dlo, dhi, number_text(g.h[k]), "xyz"[k]));
  }
}

}  // namespace

TwoFluidCase parse_two_fluid(const YamlNode& block) {
  TwoFluidCase c;
  YamlMap m(block, {"dimension", "domain", "cells", "gravity", "fluid", "solids", "drag",
                    "boundaries", "initial", "time", "output", "fraction_convection"});
  const int dim = static_cast<int>(m.at("dimension").as_integer({2, 3}));
  auto& g = c.grid;
  auto& s = c.settings;
  g.dimension = dim;
  Vec3 lo, hi;
  {
    const auto dn = m.at("domain");
    YamlMap d(dn, {"min", "max"});
    lo = d.at("min").as_vec(dim);
    hi = d.at("max").as_vec(dim);
    for (int k = 0; k < dim; ++k)
      if (!(hi[k] > lo[k]))
        dn.fail(fmt::format("expected max > min along every axis (axis {})", k));
  }
  {
    const auto cn = m.at("cells");
    const auto items = cn.as_list();
    if (static_cast<int>(items.size()) != dim)
      cn.fail_expected(fmt::format("a list of {} cell counts (one per axis)", dim));
    double cells = 1;
    for (int k = 0; k < dim; ++k) {
      g.n[static_cast<std::size_t>(k)] =
          static_cast<int>(items[static_cast<std::size_t>(k)].as_integer({1, 1e5}));
      cells *= g.n[static_cast<std::size_t>(k)];
    }
    // Before anything is allocated (the model probe below builds the whole grid).
    if (auto w = check_memory_use(cn.loc(), fmt::format("{} cells", number_text(cells)),
                                  cells * kBytesPerTwoFluidCell))
      c.warnings.push_back(*w);
    g.lo = lo;
    for (int k = 0; k < dim; ++k) g.h[k] = (hi[k] - lo[k]) / g.n[static_cast<std::size_t>(k)];
    if (dim == 2) {
      g.n[2] = 1;
      g.h[2] = g.h[0];  // the depth of the 2D layer: volumes per cell are h_x h_y h_z
    }
    for (int k = 1; k < dim; ++k)
      if (std::abs(g.h[k] / g.h[0] - 1.0) > 0.5)
        cn.fail(fmt::format(
            "cells of {:.3g} x {:.3g} m are too elongated (the solids stencils assume cells of "
            "similar size along every axis: keep the aspect ratio within 1.5)",
            g.h[0], g.h[k]));
  }
  s.fluid.gravity = m.find("gravity") ? m.at("gravity").as_vec(dim) : Vec3{};
  {
    YamlMap f(m.at("fluid"), {"density", "viscosity"});
    s.fluid.density = f.number("density", Range::positive());
    s.fluid.dynamic_viscosity = f.number("viscosity", Range::positive());
  }
  {
    const auto sn = m.at("solids");
    std::vector<std::string> extra{"temperature",    "initial_temperature", "max_fraction",
                                   "specularity",    "wall_restitution",    "rheology",
                                   "dense_pressure", "particle_pressure"};
    const KtgfInput kt = read_ktgf_input(sn, extra, "schaeffer_johnson_jackson", true);
    c.closures = kt.closures;
    c.radial = kt.radial;
    c.dense = kt.dense;
    c.ktgf_params = kt.params;
    c.dense_params = kt.dense_params;
    s.ktgf = kt.ktgf;
    s.frictional = kt.frictional.has_value();
    YamlMap sm(sn);
    if (kt.frictional) s.dense = *kt.frictional;
    // mu_i_switch (the seed's regime switch): the mu(I) rheology above the frictional limit and
    // the seed's logarithmic pressure; both blocks required there, refused elsewhere.
    const bool mu_i = c.dense == continuum::MuISwitch::key;
    for (const char* key : {"rheology", "dense_pressure"})
      if (!mu_i && sm.has(key))
        sm.at(key).fail(
            fmt::format("'{}' belongs to the dense model '{}' (the dense model is '{}')", key,
                        continuum::MuISwitch::key, c.dense));
    if (mu_i) {
      const auto rn = sm.at("rheology");
      YamlMap r(rn, {"mu_s", "mu_2", "i0", "max_viscosity"});
      const auto* info = continuum::find_rheology(continuum::MuI::key);
      std::vector<ParamSpec> schema;
      for (const auto& p : info->params)
        if (p.name != "grain_diameter" && p.name != "grain_density") schema.push_back(p);
      c.rheology_params = read_schema_params(r, rn, schema, "rheology 'mu_i'");
      auto params = c.rheology_params;
      params["grain_diameter"] = s.ktgf.diameter;
      params["grain_density"] = s.ktgf.density;
      try {
        s.dense_rheology = continuum::prepare_rheology(continuum::MuI::key, params);
      } catch (const InputError&) {
        throw;
      } catch (const Error& e) {
        rn.fail(e.what());
      }
      const auto pn = sm.at("dense_pressure");
      YamlMap pm(pn, {"p0", "min_fraction", "max_fraction"});
      s.log_pressure.p0 = pm.number("p0", Range::positive());
      s.log_pressure.min_fraction = pm.number("min_fraction", {0.0, 1.0, true, true});
      s.log_pressure.max_fraction = pm.number("max_fraction", {0.0, 1.0, true, true});
      if (!(s.log_pressure.max_fraction > s.log_pressure.min_fraction))
        pm.at("max_fraction").fail("expected max_fraction > min_fraction");
    }
    if (auto pn = sm.find("particle_pressure");
        pn && !(pn->is_scalar() && pn->as_string() == "none")) {
      std::tie(c.particle_pressure, std::ignore, c.particle_pressure_params) = read_model_block(
          *pn, continuum::particle_pressure_model_infos(), "particle-pressure model", " (or none)");
      s.particle_pressure =
          continuum::prepare_particle_pressure(c.particle_pressure, c.particle_pressure_params);
    }
    s.temperature = continuum::GranularTemperature::Algebraic;
    if (auto t = sm.find("temperature"))
      s.temperature = t->as_choice({"algebraic", "transport"}) == "transport"
                          ? continuum::GranularTemperature::Transport
                          : continuum::GranularTemperature::Algebraic;
    else if (c.closures != continuum::Syamlal::key)
      s.temperature = continuum::GranularTemperature::Transport;
    if (s.temperature == continuum::GranularTemperature::Algebraic &&
        c.closures != continuum::Syamlal::key)
      sm.at("temperature")
          .fail(fmt::format("the algebraic granular temperature needs closures: syamlal (with "
                            "'{}' the local balance gives Theta ~ 1/a^2 in dilute cells); use "
                            "temperature: transport",
                            c.closures));
    c.initial_temperature = sm.number_or("initial_temperature", 0.0, Range::non_negative());
    s.max_fraction = sm.number_or("max_fraction", 0.0, {0.0, 1.0, false, true});
    s.specularity = sm.number_or("specularity", 0.5, {0.0, 1.0});
    s.wall_restitution = sm.number_or("wall_restitution", 0.9, {0.0, 1.0});
  }
  {
    const auto dn = m.at("drag");
    std::tie(c.drag, std::ignore, c.drag_params) =
        read_model_block(dn, cfd_dem::drag_infos(), "drag law");
    try {
      s.drag = cfd_dem::prepare_drag(c.drag, c.drag_params);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      dn.fail(e.what());
    }
  }
  // Boundaries: every face of the box a wall unless given.
  for (int f = 0; f < 6; ++f) s.fluid.boundary[f] = fluid::BoundaryCondition::no_slip();
  if (auto bn = m.find("boundaries")) {
    std::vector<std::string> faces(kFaceNames.begin(), kFaceNames.begin() + 2 * dim);
    faces.insert(faces.end(), kBoxFaceNames.begin(), kBoxFaceNames.begin() + 2 * dim);
    YamlMap b(*bn, faces);
    for (int f = 0; f < 2 * dim; ++f) {
      auto fn = b.find_either(kFaceNames[f], kBoxFaceNames[f]);
      if (!fn) continue;
      YamlMap fm(*fn);
      const std::string type = fm.at("type").as_choice({"wall", "inlet", "outlet", "periodic"});
      const int axis = f / 2;
      if (type == "periodic") {
        fm.check_keys({"type"}, "keys of a periodic face");
        s.fluid.boundary[f] = fluid::BoundaryCondition::periodic();
        g.periodic[static_cast<std::size_t>(axis)] = true;
      } else if (type == "wall") {
        fm.check_keys({"type", "solids", "velocity"}, "keys of a wall");
        Vec3 v = fm.find("velocity") ? fm.at("velocity").as_vec(dim) : Vec3{};
        if (v[axis] != 0.0)
          fm.at("velocity").fail("a wall slides in its own plane: its normal velocity must be 0");
        s.fluid.boundary[f] = norm(v) > 0 ? fluid::BoundaryCondition::moving_wall(v)
                                          : fluid::BoundaryCondition::no_slip();
        if (auto sw = fm.find("solids")) {
          const auto k = sw->as_choice({"no_slip", "free_slip", "johnson_jackson"});
          s.solids_wall[f] = k == "no_slip"     ? continuum::SolidsWall::NoSlip
                             : k == "free_slip" ? continuum::SolidsWall::FreeSlip
                                                : continuum::SolidsWall::JohnsonJackson;
        }
      } else if (type == "inlet") {
        fm.check_keys({"type", "velocity", "superficial", "jet"}, "keys of an inlet");
        const Vec3 v = fm.at("velocity").as_vec(dim);
        const bool superficial = fm.boolean_or("superficial", true);
        if (auto jn = fm.find("jet")) {
          YamlMap jm(*jn, {"from", "to", "velocity"});
          if (dim != 2) jn->fail("a jet is a strip of a 2D inlet (3D: not supported yet)");
          TwoFluidCase::Jet jet;
          jet.face = f;
          jet.from = jm.number("from");
          jet.to = jm.number("to");
          jet.velocity = jm.at("velocity").as_vec(dim);
          const int across = 1 - axis;
          if (!(jet.to > jet.from) || jet.from < lo[across] || jet.to > hi[across])
            jn->fail(fmt::format("expected lo <= from < to <= hi along the face ({} .. {})",
                                 lo[across], hi[across]));
          c.jets.push_back(jet);
          s.fluid.boundary[f] = fluid::BoundaryCondition::velocity_inlet(
              [v, jet, across](const Vec3& x) {
                return x[across] >= jet.from && x[across] <= jet.to ? jet.velocity : v;
              },
              superficial);
        } else {
          s.fluid.boundary[f] = fluid::BoundaryCondition::velocity_inlet(v, superficial);
        }
      } else {
        fm.check_keys({"type", "pressure"}, "keys of an outlet");
        s.fluid.boundary[f] =
            fluid::BoundaryCondition::pressure_outlet(fm.number_or("pressure", 0.0));
      }
    }
    // Incompressible gas: without an outlet the inlets must not all push in (or all draw
    // out), or the pressure solve stops at the first step. (Whether inlets of both senses
    // balance depends on the fluid fraction at interstitial ones: not judged here.)
    bool outlet = false, in = false, out = false;
    for (int f = 0; f < 2 * dim; ++f) {
      const auto& bc = s.fluid.boundary[f];
      if (bc.kind == fluid::BcKind::PressureOutlet) outlet = true;
      if (bc.kind != fluid::BcKind::VelocityInlet) continue;
      const double sign = f % 2 == 0 ? 1.0 : -1.0;  // inward normal along the face's axis
      auto sense = [&](double normal_velocity) {
        in = in || sign * normal_velocity > 0;
        out = out || sign * normal_velocity < 0;
      };
      // (a profile: its value at the face's two ends, away from a jet in its middle)
      for (const Vec3& at : {lo, hi}) sense((bc.profile ? bc.profile(at) : bc.velocity)[f / 2]);
      for (const auto& jet : c.jets)
        if (jet.face == f) sense(jet.velocity[f / 2]);
    }
    if (!outlet && in != out)
      bn->fail(
          fmt::format("no face is an outlet (type: outlet), so the gas the inlets {} has "
                      "nowhere to {}",
                      in ? "push in" : "draw out", in ? "go" : "come from"));
    for (int a = 0; a < dim; ++a) {
      const bool p0 = s.fluid.boundary[2 * a].kind == fluid::BcKind::Periodic;
      const bool p1 = s.fluid.boundary[2 * a + 1].kind == fluid::BcKind::Periodic;
      if (p0 != p1)
        bn->fail(fmt::format("{} and {} must both be periodic or neither", kFaceNames[2 * a],
                             kFaceNames[2 * a + 1]));
    }
  }
  if (auto fc = m.find("fraction_convection"))
    s.fraction_convection = fc->as_choice({"van_leer", "upwind"}) == "upwind"
                                ? fluid::Convection::Upwind
                                : fluid::Convection::VanLeer;
  {
    YamlMap t(m.at("time"), {"end", "max_step", "courant"});
    c.end_time = t.number("end", Range::positive());
    c.max_step = t.number_or("max_step", 1e-3, Range::positive());
    s.max_courant = t.number_or("courant", 0.5, {0.0, 1.0, true, false});
  }
  if (auto in = m.find("initial")) {
    YamlMap im(*in, {"fluid_velocity", "regions"});
    if (im.find("fluid_velocity")) c.fluid_velocity = im.at("fluid_velocity").as_vec(dim);
    if (auto rn = im.find("regions"))
      for (const auto& r : rn->as_list()) {
        YamlMap rm(r, {"box", "solids_fraction", "solids_velocity"});
        YamlMap bm(rm.at("box"), {"min", "max"});
        TwoFluidCase::Region reg;
        reg.lo = bm.at("min").as_vec(dim);
        reg.hi = bm.at("max").as_vec(dim);
        check_region(rm.at("box"), reg, g);
        reg.solids_fraction = rm.number("solids_fraction", {0.0, 1.0, false, true});
        if (rm.find("solids_velocity")) reg.solids_velocity = rm.at("solids_velocity").as_vec(dim);
        c.initial.push_back(reg);
      }
  }
  if (auto on = m.find("output")) {
    const OutputSchedule o = read_output_schedule(*on);
    c.output = o;
  }
  for (const auto& w : c.warnings) log::warn("{}", w);
  // The model's own checks (packing limits, periodic grid axes) with the block's location.
  try {
    continuum::TwoFluidModel probe(g, s);
    for (const auto& r : c.initial)
      if (r.solids_fraction > probe.packing_fraction())
        block.fail(
            fmt::format("an initial solids_fraction of {} is above the packing limit {} of "
                        "the closures (max_fraction)",
                        r.solids_fraction, probe.packing_fraction()));
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    block.fail(e.what());
  }
  return c;
}

std::string echo_two_fluid_yaml(const TwoFluidCase& c, const std::string& version) {
  const auto& g = c.grid;
  const auto& s = c.settings;
  const int dim = g.dimension;
  auto vec = [&](const Vec3& v) {
    return dim == 2 ? fmt::format("[{:.17g}, {:.17g}]", v[0], v[1])
                    : fmt::format("[{:.17g}, {:.17g}, {:.17g}]", v[0], v[1], v[2]);
  };
  auto params = [](const std::map<std::string, double>& p) {
    std::string out;
    for (const auto& [k, v] : p) out += fmt::format(", {}: {:.17g}", k, v);
    return out;
  };
  std::ostringstream o;
  o << fmt::format("# resolved by grainflow {}\nname: {}\ntwo_fluid:\n", version, c.name);
  o << fmt::format("  dimension: {}\n  domain: {{min: {}, max: {}}}\n", dim, vec(g.lo),
                   vec(g.hi()));
  o << fmt::format("  cells: {}\n", dim == 2 ? fmt::format("[{}, {}]", g.n[0], g.n[1])
                                             : fmt::format("[{}, {}, {}]", g.n[0], g.n[1], g.n[2]));
  o << fmt::format("  gravity: {}\n", vec(s.fluid.gravity));
  o << fmt::format("  fluid: {{density: {:.17g}, viscosity: {:.17g}}}\n", s.fluid.density,
                   s.fluid.dynamic_viscosity);
  o << fmt::format("  solids: {{closures: {}, radial_distribution: {}{}, dense: {}", c.closures,
                   c.radial, params(c.ktgf_params),
                   s.frictional ? fmt::format("{{model: {}{}}}", c.dense, params(c.dense_params))
                                : std::string("none"));
  if (c.dense == continuum::MuISwitch::key)
    o << fmt::format(
        ", rheology: {{{}}}, dense_pressure: {{p0: {:.17g}, min_fraction: {:.17g}, "
        "max_fraction: {:.17g}}}",
        params(c.rheology_params).substr(2), s.log_pressure.p0, s.log_pressure.min_fraction,
        s.log_pressure.max_fraction);
  std::string particle = "none";  // with its defaults filled in
  if (const auto* info = continuum::find_particle_pressure_model(c.particle_pressure))
    particle = fmt::format("{{model: {}{}}}", c.particle_pressure,
                           params(with_defaults(info->params, c.particle_pressure_params)));
  o << ", particle_pressure: " << particle;
  o << fmt::format(
      ", temperature: {}, initial_temperature: {:.17g}, max_fraction: {:.17g}, specularity: "
      "{:.17g}, wall_restitution: {:.17g}}}\n",
      s.temperature == continuum::GranularTemperature::Algebraic ? "algebraic" : "transport",
      c.initial_temperature, s.max_fraction, s.specularity, s.wall_restitution);
  const auto* law = cfd_dem::find_drag(c.drag);
  o << fmt::format("  drag: {{model: {}{}}}\n  boundaries:\n", c.drag,
                   params(law ? with_defaults(law->params, c.drag_params) : c.drag_params));
  for (int f = 0; f < 2 * dim; ++f) {
    const auto& b = s.fluid.boundary[f];
    o << "    " << kFaceNames[f] << ": ";
    switch (b.kind) {
      case fluid::BcKind::Periodic:
        o << "{type: periodic}\n";
        break;
      case fluid::BcKind::NoSlip:
      case fluid::BcKind::MovingWall: {
        const auto w = s.solids_wall[f];
        o << fmt::format("{{type: wall, velocity: {}, solids: {}}}\n", vec(b.velocity),
                         w == continuum::SolidsWall::NoSlip     ? "no_slip"
                         : w == continuum::SolidsWall::FreeSlip ? "free_slip"
                                                                : "johnson_jackson");
        break;
      }
      case fluid::BcKind::VelocityInlet: {
        std::string jet;
        Vec3 v = b.velocity;
        for (const auto& j : c.jets)
          if (j.face == f) {
            jet = fmt::format(", jet: {{from: {:.17g}, to: {:.17g}, velocity: {}}}", j.from, j.to,
                              vec(j.velocity));
            // the uniform part: sample the profile outside the jet
            const int across = 1 - f / 2;
            Vec3 x = g.lo;
            x[across] = j.from > g.lo[across] ? g.lo[across] : g.hi()[across];
            v = b.profile(x);
          }
        o << fmt::format("{{type: inlet, velocity: {}, superficial: {}{}}}\n", vec(v),
                         b.superficial, jet);
        break;
      }
      case fluid::BcKind::PressureOutlet:
        o << fmt::format("{{type: outlet, pressure: {:.17g}}}\n", b.pressure);
        break;
    }
  }
  o << fmt::format("  initial:\n    fluid_velocity: {}\n    regions:\n", vec(c.fluid_velocity));
  for (const auto& r : c.initial)
    o << fmt::format(
        "      - {{box: {{min: {}, max: {}}}, solids_fraction: {:.17g}, solids_velocity: {}}}\n",
        vec(r.lo), vec(r.hi), r.solids_fraction, vec(r.solids_velocity));
  o << fmt::format("  fraction_convection: {}\n",
                   s.fraction_convection == fluid::Convection::Upwind ? "upwind" : "van_leer");
  o << fmt::format("  time: {{end: {:.17g}, max_step: {:.17g}, courant: {:.17g}}}\n", c.end_time,
                   c.max_step, s.max_courant);
  o << fmt::format(
      "  output: {{vtk_every: {:.17g}, series_every: {:.17g}, checkpoint_every: {:.17g}}}\n",
      c.output.vtk_every, c.output.series_every, c.output.checkpoint_every);
  return o.str();
}

}  // namespace gf::input
