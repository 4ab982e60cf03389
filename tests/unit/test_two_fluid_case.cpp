// SPDX-License-Identifier: GPL-3.0-or-later
// `two_fluid:` cases: the block's reading and its located errors, the resolved echo, a run's
// outputs, and restarts that continue bit-identically.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "input_error.hpp"
#include "io/restart/h5.hpp"
#include "simulation/two_fluid_case.hpp"
#include "temp_dir.hpp"

namespace gf {
namespace {

using ::testing::HasSubstr;

const char* const kCase = R"(two_fluid:
  dimension: 2
  domain: {min: [0, 0], max: [0.04, 0.08]}
  cells: [8, 16]
  gravity: [0, -9.81]
  fluid: {density: 1.2, viscosity: 1.8e-5}
  solids:
    closures: syamlal
    restitution: 0.9
    grain_diameter: 5.0e-4
    grain_density: 2500
  drag: {model: gidaspow}
  boundaries:
    x_min: {type: periodic}
    x_max: {type: periodic}
    y_min: {type: inlet, velocity: [0, 0.4], jet: {from: 0.015, to: 0.025, velocity: [0, 1.5]}}
    y_max: {type: outlet}
  initial:
    fluid_velocity: [0, 0.8]
    regions:
      - {box: {min: [0, 0], max: [0.04, 0.03]}, solids_fraction: 0.5}
  time: {end: 1.0, max_step: 5.0e-4}
  output: {vtk_every: 0.01, series_every: 0.002, checkpoint_every: 0.02}
)";

input::TwoFluidCase parse_text(const std::string& text) {
  const auto root = input::YamlNode::parse_text(text, "case.yaml");
  input::YamlMap top(root, {"name", "two_fluid", "output"});
  auto c = input::parse_two_fluid(top.at("two_fluid"));
  c.file = "case.yaml";
  c.name = "test";
  return c;
}

std::string error_of(const std::string& text) {
  return test::input_error_of([&] { parse_text(text); });
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(TwoFluidInput, ReadsTheBlock) {
  const auto c = parse_text(kCase);
  EXPECT_EQ(c.grid.n[0], 8);
  EXPECT_EQ(c.grid.n[1], 16);
  EXPECT_DOUBLE_EQ(c.grid.h.x, 0.005);
  EXPECT_TRUE(c.grid.periodic[0]);
  EXPECT_FALSE(c.grid.periodic[1]);
  EXPECT_EQ(c.settings.fluid.boundary[2].kind, fluid::BcKind::VelocityInlet);
  EXPECT_TRUE(c.settings.fluid.boundary[2].superficial);
  // the jet: its velocity inside the strip, the uniform one outside
  EXPECT_DOUBLE_EQ(c.settings.fluid.boundary[2].profile({0.02, 0, 0}).y, 1.5);
  EXPECT_DOUBLE_EQ(c.settings.fluid.boundary[2].profile({0.005, 0, 0}).y, 0.4);
  EXPECT_EQ(c.settings.fluid.boundary[3].kind, fluid::BcKind::PressureOutlet);
  EXPECT_EQ(c.settings.temperature, continuum::GranularTemperature::Algebraic);
  EXPECT_TRUE(c.settings.frictional);  // the default dense model
  EXPECT_EQ(c.dense, "schaeffer_johnson_jackson");
  ASSERT_EQ(c.initial.size(), 1u);
  EXPECT_DOUBLE_EQ(c.initial[0].solids_fraction, 0.5);
  // Lun's closures default to the transported temperature, and `dense: none` switches the
  // frictional closure off.
  const auto lun = parse_text(replaced(replaced(kCase, "closures: syamlal", "closures: lun"),
                                       "    grain_density: 2500\n",
                                       "    grain_density: 2500\n    dense: none\n"));
  EXPECT_EQ(lun.settings.temperature, continuum::GranularTemperature::Transport);
  EXPECT_FALSE(lun.settings.frictional);
  // The seed's regime switch: mu(I) with the logarithmic pressure; its echo reads back too.
  const auto mui = parse_text(
      replaced(kCase, "    grain_density: 2500\n",
               "    grain_density: 2500\n    dense: {model: mu_i_switch, frictional_limit: 0.5}\n"
               "    rheology: {mu_s: 0.38, max_viscosity: 50}\n"
               "    dense_pressure: {p0: 2000, min_fraction: 0.55, max_fraction: 0.6}\n"));
  EXPECT_EQ(mui.dense, "mu_i_switch");
  EXPECT_DOUBLE_EQ(mui.settings.log_pressure.p0, 2000.0);
  EXPECT_DOUBLE_EQ(mui.settings.dense_rheology.max_viscosity, 50.0);
  {
    const std::string e1 = input::echo_two_fluid_yaml(mui, "test");
    const auto r1 = input::YamlNode::parse_text(e1, "echo.yaml");
    input::YamlMap t1(r1, {"name", "two_fluid"});
    auto b1 = input::parse_two_fluid(t1.at("two_fluid"));
    b1.name = mui.name;
    EXPECT_EQ(input::echo_two_fluid_yaml(b1, "test"), e1);
  }
  // A particle pressure (elastic modulus): none by default; a model with its defaults filled in
  // by the echo, which reads back.
  EXPECT_LT(c.settings.particle_pressure.model, 0);
  const auto pe =
      parse_text(replaced(kCase, "    grain_density: 2500\n",
                          "    grain_density: 2500\n"
                          "    particle_pressure: {model: gidaspow_ettehadieh, exponent: 9.0}\n"));
  EXPECT_EQ(pe.settings.particle_pressure.model, 0);
  EXPECT_DOUBLE_EQ(pe.settings.particle_pressure.exponent, 9.0);
  EXPECT_DOUBLE_EQ(pe.settings.particle_pressure.log10_modulus, 5.43);
  {
    const std::string e1 = input::echo_two_fluid_yaml(pe, "test");
    EXPECT_THAT(e1, HasSubstr("particle_pressure: {model: gidaspow_ettehadieh, exponent: 9, "
                              "log10_modulus: 5.4299999999999997}"));
    const auto r1 = input::YamlNode::parse_text(e1, "echo.yaml");
    input::YamlMap t1(r1, {"name", "two_fluid"});
    auto b1 = input::parse_two_fluid(t1.at("two_fluid"));
    b1.name = pe.name;
    EXPECT_EQ(input::echo_two_fluid_yaml(b1, "test"), e1);
  }
  EXPECT_LT(parse_text(replaced(kCase, "    grain_density: 2500\n",
                                "    grain_density: 2500\n    particle_pressure: none\n"))
                .settings.particle_pressure.model,
            0);
  // The echo reads back to the same case.
  const std::string echo = input::echo_two_fluid_yaml(c, "test");
  const auto root = input::YamlNode::parse_text(echo, "echo.yaml");
  input::YamlMap top(root, {"name", "two_fluid"});
  auto back = input::parse_two_fluid(top.at("two_fluid"));
  back.name = c.name;
  EXPECT_EQ(input::echo_two_fluid_yaml(back, "test"), echo);
}

TEST(TwoFluidInput, ErrorsNameLineKeyAndExpectation) {
  struct Bad {
    std::string from, to, expect;
  };
  const std::vector<Bad> bad{
      {"cells: [8, 16]", "cells: [8]", "a list of 2 cell counts"},
      {"cells: [8, 16]", "cells: [8, 2]", "too elongated"},
      {"closures: syamlal", "closures: lunn", "a KTGF closure set: lun, syamlal, gidaspow"},
      {"restitution: 0.9", "restitution: 1.5", "restitution"},
      {"    grain_diameter: 5.0e-4\n", "", "needs 'grain_diameter'"},
      {"closures: syamlal", "closures: lun\n    temperature: algebraic",
       "algebraic granular temperature needs closures: syamlal"},
      {"    grain_density: 2500\n", "    grain_density: 2500\n    dense: {model: mu_i_switch}\n",
       "missing required key 'rheology'"},
      {"    grain_density: 2500\n", "    grain_density: 2500\n    rheology: {mu_s: 0.4}\n",
       "'rheology' belongs to the dense model 'mu_i_switch'"},
      {"    grain_density: 2500\n",
       "    grain_density: 2500\n    particle_pressure: {model: elastic}\n",
       "a particle-pressure model: gidaspow_ettehadieh (or none)"},
      {"    grain_density: 2500\n",
       "    grain_density: 2500\n    particle_pressure: {model: gidaspow_ettehadieh, c: 8}\n",
       "'c'"},
      {"    grain_density: 2500\n", "    grain_density: 2500\n    particle_pressure: yes\n",
       "none"},
      {"model: gidaspow", "model: ergun", "a drag law: schiller_naumann"},
      {"model: gidaspow", "model: gidaspow, switch_fractio: 0.8", "switch_fractio"},
      {"    x_max: {type: periodic}\n", "", "x_min and x_max must both be periodic"},
      {"y_max: {type: outlet}", "y_max: {type: outflow}", "wall, inlet, outlet, periodic"},
      {"y_max: {type: outlet}", "y_max: {type: wall, velocity: [0, 1]}", "normal velocity"},
      {"jet: {from: 0.015, to: 0.025", "jet: {from: 0.025, to: 0.015", "from < to"},
      {"solids_fraction: 0.5", "solids_fraction: 0.7", "above the packing limit"},
      {"end: 1.0", "end: -1.0", "> 0"},
      {"vtk_every: 0.01", "vtk_evry: 0.01", "vtk_evry"},
      {"  time: {end: 1.0", "  fraction_convection: central\n  time: {end: 1.0", "van_leer"},
  };
  for (const auto& b : bad) {
    const std::string e = error_of(replaced(kCase, b.from, b.to));
    EXPECT_THAT(e, HasSubstr(b.expect)) << b.to;
    EXPECT_THAT(e, HasSubstr("case.yaml:")) << b.to;  // file:line:column
  }
}

// A run writes its series, ParaView series, summary and checkpoints; a run continued from a
// checkpoint (in a fresh folder, and appended in the first run's folder) ends in the same state,
// bit for bit, and the appended series equals the straight one.
TEST(TwoFluidInput, InletsWithoutAnOutletAreRefused) {
  // The gas pushed in has nowhere to go: the pressure solve used to stop at the first step
  // (exit 1) after `check` had passed.
  const auto m = error_of(replaced(kCase, "y_max: {type: outlet}", "y_max: {type: wall}"));
  EXPECT_THAT(m, HasSubstr("case.yaml:14:"));  // (the block's first face)
  EXPECT_THAT(m, HasSubstr("two_fluid.boundaries: no face is an outlet"));
  EXPECT_THAT(m, HasSubstr("push in"));
  // A jet alone counts too (base velocity 0), and an inlet drawing out at the top balancing the
  // bottom's inflow is accepted (whether it balances is the case's own business).
  EXPECT_THAT(error_of(replaced(replaced(kCase, "y_max: {type: outlet}", "y_max: {type: wall}"),
                                "velocity: [0, 0.4], jet", "velocity: [0, 0], jet")),
              HasSubstr("push in"));
  EXPECT_EQ(error_of(replaced(kCase, "y_max: {type: outlet}",
                              "y_max: {type: inlet, velocity: [0, 0.4]}")),
            "");
}

// The other blocks' spelling of the faces (xmin ... ymax) names the same faces here; one face
// under both spellings is refused.
TEST(TwoFluidInput, FaceKeysTakeEitherSpelling) {
  const auto a = parse_text(kCase);
  const auto b = parse_text(replaced(replaced(kCase, "y_min:", "ymin:"), "x_max:", "xmax:"));
  for (int f = 0; f < 4; ++f)
    EXPECT_EQ(a.settings.fluid.boundary[f].kind, b.settings.fluid.boundary[f].kind);
  EXPECT_TRUE(b.settings.fluid.boundary[2].superficial == a.settings.fluid.boundary[2].superficial);
  EXPECT_EQ(b.jets.size(), a.jets.size());
  const auto m = error_of(replaced(kCase, "    y_max: {type: outlet}\n",
                                   "    y_max: {type: outlet}\n    ymax: {type: outlet}\n"));
  EXPECT_THAT(m, HasSubstr("give only one of y_max, ymax"));
  EXPECT_THAT(m, HasSubstr("case.yaml:"));
}

TEST(TwoFluidCase, RunsAndContinuesBitIdentically) {
  test::TempDir tmp;
  const auto c = parse_text(kCase);
  RunOptions straight;
  straight.output = tmp.path() / "straight";
  straight.steps = 60;
  ASSERT_EQ(run_two_fluid_case(c, {}, straight), 0);
  for (const char* f :
       {"two_fluid_series.csv", "two_fluid.pvd", "two_fluid_00000.vti", "two_fluid_summary.txt",
        "resolved_case.yaml", "two_fluid_checkpoint_final.h5"})
    EXPECT_TRUE(std::filesystem::exists(tmp.path() / "straight" / f)) << f;
  RunOptions first = straight;
  first.output = tmp.path() / "split";
  first.steps = 25;
  ASSERT_EQ(run_two_fluid_case(c, {}, first), 0);
  RunOptions fresh;
  fresh.output = tmp.path() / "fresh";
  fresh.restart = tmp.path() / "split" / "two_fluid_checkpoint_final.h5";
  fresh.steps = 35;
  ASSERT_EQ(run_two_fluid_case(c, {}, fresh), 0);
  RunOptions append = fresh;
  append.output = tmp.path() / "split";
  append.append = true;
  ASSERT_EQ(run_two_fluid_case(c, {}, append), 0);
  auto state = [](const std::filesystem::path& f) {
    auto h = io::h5::File::open_read(f);
    return std::make_tuple(h.read_double("solids/alpha"), h.read_double("solids/theta"),
                           h.read_double("solids/us1"), h.read_double("fluid/u1"),
                           h.read_double("fluid/p"), h.read_int_attribute("/", "steps"),
                           h.read_double_attribute("/", "time"));
  };
  const auto ref = state(tmp.path() / "straight" / "two_fluid_checkpoint_final.h5");
  EXPECT_EQ(std::get<5>(ref), 60);
  EXPECT_TRUE(state(tmp.path() / "fresh" / "two_fluid_checkpoint_final.h5") == ref);
  EXPECT_TRUE(state(tmp.path() / "split" / "two_fluid_checkpoint_final.h5") == ref);
  EXPECT_EQ(read_file(tmp.path() / "split" / "two_fluid_series.csv"),
            read_file(tmp.path() / "straight" / "two_fluid_series.csv"));
  // A checkpoint of another grid is refused before anything is written.
  auto other = parse_text(replaced(kCase, "cells: [8, 16]", "cells: [4, 8]"));
  auto elsewhere = fresh;
  elsewhere.output = tmp.path() / "other";
  EXPECT_THROW(run_two_fluid_case(other, {}, elsewhere), InputError);
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / "other"));
}

}  // namespace
}  // namespace gf
