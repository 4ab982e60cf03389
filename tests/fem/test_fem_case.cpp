// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the `fluid_fem:` case block: strict parsing with located errors, and a tiny run.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fem_case_text.hpp"
#include "fluid/fem/case.hpp"
#include "temp_dir.hpp"

using namespace gf::fem;

namespace {

const char* kGood = gf::test::kFemChannelCase;
using gf::test::replaced;

std::string error_of(const std::string& yaml) {
  try {
    parse_fluid_fem(YAML::Load(yaml)["fluid_fem"], "case.yaml");
  } catch (const gf::InputError& e) {
    return e.what();
  }
  return "no error";
}

/// Rows of a CSV file after its header.
std::vector<std::vector<double>> csv_rows(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::size_t at = 0;
    while (at <= line.size()) {
      const auto next = std::min(line.find(',', at), line.size());
      row.push_back(std::stod(line.substr(at, next - at)));
      at = next + 1;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

/// What a run leaves: the first line of fem_summary.txt and the rows of fem_forces.csv (columns
/// t, dt, order, then per body). The run's temporary folder is removed.
struct CaseRun {
  std::string summary;
  std::vector<std::vector<double>> forces;
};

CaseRun run_case(const FemCaseConfig& cfg) {
  // A folder of this test and process: ctest runs the tests side by side (a shared fixed name
  // let one test remove another's outputs while it wrote them).
  const gf::test::TempDir tmp;
  const auto& dir = tmp.path();
  run_fluid_fem(cfg, dir);
  CaseRun r;
  std::ifstream in(dir / "fem_summary.txt");
  std::getline(in, r.summary);
  r.forces = csv_rows(dir / "fem_forces.csv");
  return r;
}

CaseRun run_case(const std::string& yaml) {
  return run_case(parse_fluid_fem(YAML::Load(yaml)["fluid_fem"], "case.yaml"));
}

}  // namespace

TEST(FemCase, ParsesAGoodBlock) {
  const auto cfg = parse_fluid_fem(YAML::Load(kGood)["fluid_fem"], "case.yaml");
  EXPECT_FALSE(cfg.steady);
  EXPECT_EQ(cfg.time.order, 2);
  EXPECT_DOUBLE_EQ(cfg.time.dt, 0.05);
  ASSERT_EQ(cfg.mesh.bodies.size(), 2u);
  EXPECT_EQ(cfg.body_names[1], "tri");
  EXPECT_EQ(cfg.outline_bc[1].kind, OutlineBcKind::Outflow);
  EXPECT_EQ(cfg.outline_bc[3].kind, OutlineBcKind::Inflow);
  EXPECT_DOUBLE_EQ(cfg.inflow_time[3](0.05), 0.5);
  EXPECT_DOUBLE_EQ(cfg.body_motion[0].angular_velocity, 1.0);
  EXPECT_NEAR(cfg.mesh.bodies[1].centre.x, 0.65, 1e-15);
}

TEST(FemCase, ErrorsNameLocationKeyExpectedAndFound) {
  auto e = error_of(replaced(kGood, "viscosity: 0.01", "viscosity: -1"));
  EXPECT_NE(e.find("case.yaml:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("fluid_fem.fluid.viscosity"), std::string::npos) << e;
  EXPECT_NE(e.find("found '-1'"), std::string::npos) << e;
  e = error_of(replaced(kGood, "grading: 0.3", "grading: 0.3, colour: red"));
  EXPECT_NE(e.find("case.yaml:12:"), std::string::npos) << e;
  EXPECT_NE(e.find("fluid_fem.mesh.colour"), std::string::npos) << e;
  e = error_of(replaced(kGood, "type: outflow", "type: outlet"));
  EXPECT_NE(e.find("fluid_fem.domain.boundaries[1].type"), std::string::npos) << e;
  EXPECT_NE(e.find("wall | inflow | outflow"), std::string::npos) << e;
  e = error_of(replaced(kGood, "mode: unsteady, scheme: bdf2, step: 0.05,",
                        "mode: unsteady, scheme: bdf2,"));
  EXPECT_NE(e.find("fluid_fem.time.step"), std::string::npos) << e;
  EXPECT_NE(e.find("required"), std::string::npos) << e;
  e = error_of(replaced(kGood, "scheme: bdf2", "scheme: auto"));  // auto needs adaptive steps
  EXPECT_NE(e.find("case.yaml:13:"), std::string::npos) << e;
  EXPECT_NE(e.find("fluid_fem.time.scheme"), std::string::npos) << e;
  EXPECT_NE(e.find("adaptive"), std::string::npos) << e;
  EXPECT_NE(e.find("found 'auto'"), std::string::npos) << e;
  e = error_of(replaced(kGood, "scheme: bdf2", "scheme: bdf4"));
  EXPECT_NE(e.find("bdf1 | bdf2 | bdf3 | auto"), std::string::npos) << e;
  e = error_of(replaced(kGood, "scheme: bdf2", "scheme: bdf2, initial: warm"));
  EXPECT_NE(e.find("fluid_fem.time.initial"), std::string::npos) << e;
  EXPECT_NE(e.find("rest | steady"), std::string::npos) << e;
  e = error_of(replaced(kGood, "mode: unsteady, scheme: bdf2, step: 0.05, end: 0.2",
                        "mode: steady, initial: steady"));
  EXPECT_NE(e.find("no such key with mode: steady"), std::string::npos) << e;
  e = error_of(replaced(kGood, "edges: [1]", "edges: [7]"));
  EXPECT_NE(e.find("edges[0]"), std::string::npos) << e;
  e = error_of(replaced(kGood, "edges: [1]", "edges: [0]"));
  EXPECT_NE(e.find("not listed before"), std::string::npos) << e;
  e = error_of(replaced(kGood, "radius: 0.05", "radius: [1]"));
  EXPECT_NE(e.find("a list of 1 items"), std::string::npos) << e;
}

TEST(FemCase, VariableOrderRunReportsStepsPerOrder) {
  const auto cfg = parse_fluid_fem(
      YAML::Load(
          replaced(kGood, "scheme: bdf2, step: 0.05, end: 0.2",
                   "scheme: auto, step: 0.01, end: 0.2, adaptive: {rtol: 1.0e-3}"))["fluid_fem"],
      "case.yaml");
  EXPECT_TRUE(cfg.time.variable_order);
  EXPECT_EQ(cfg.time.order, 3);
  EXPECT_TRUE(cfg.time.adaptive);
  const CaseRun run = run_case(cfg);
  EXPECT_NE(run.summary.find("unsteady BDF1-3: steps"), std::string::npos) << run.summary;
  EXPECT_NE(run.summary.find("at orders 1/2/3"), std::string::npos) << run.summary;
  // fem_forces.csv carries each step's size and order: BDF1 first, higher orders later.
  std::vector<int> orders;
  for (const auto& row : run.forces) {
    EXPECT_GT(row[1], 0.0);
    orders.push_back(static_cast<int>(row[2]));
  }
  ASSERT_GE(orders.size(), 3u);
  EXPECT_EQ(orders.front(), 1);
  EXPECT_GE(*std::max_element(orders.begin(), orders.end()), 2);
}

// `initial: steady` starts the BDF steps from the steady Newton solution for the data at t = 0
// (consistent initial conditions). With constant boundary data that state is a fixed point of
// the steps: every force stays at the steady run's value (to the Newton tolerance, 1e-10 on the
// velocity updates; we allow 1e-7 of the largest force; measured: identical in all 10 digits of
// the CSV). A start from rest with the same constant data is an impulsive start: measured 1.56
// times the largest force off at the first step.
TEST(FemCase, SteadyInitialStateIsAFixedPointOfTheSteps) {
  const std::string constant = replaced(kGood, ", time_function: {type: ramp, duration: 0.1}", "");
  auto forces = [](const std::string& yaml) { return run_case(yaml).forces; };
  const auto steady = forces(
      replaced(constant, "mode: unsteady, scheme: bdf2, step: 0.05, end: 0.2", "mode: steady"));
  const auto from_steady =
      forces(replaced(constant, "scheme: bdf2", "scheme: bdf2, initial: steady"));
  const auto from_rest = forces(constant);
  ASSERT_EQ(steady.size(), 1u);
  ASSERT_EQ(from_steady.size(), 4u);
  ASSERT_EQ(from_rest.size(), 4u);
  double scale = 0;
  for (std::size_t c = 3; c < steady[0].size(); ++c)
    scale = std::max(scale, std::abs(steady[0][c]));
  ASSERT_GT(scale, 0);
  double drift = 0, impulsive = 0;
  for (std::size_t c = 3; c < steady[0].size(); ++c) {
    for (const auto& row : from_steady) drift = std::max(drift, std::abs(row[c] - steady[0][c]));
    impulsive = std::max(impulsive, std::abs(from_rest[0][c] - steady[0][c]));
  }
  std::printf("steady start: drift %.2e, start from rest: %.2e (of the largest force)\n",
              drift / scale, impulsive / scale);
  EXPECT_LT(drift, 1e-7 * scale);
  EXPECT_GT(impulsive, 1e-3 * scale);
}

// newton.picard_iterations serve steady solves (a poor first guess); the time steps start from
// the extrapolated predictor and skip them. With 12 Picard iterations applied per step, the 4
// steps would take >= 52 iterations; measured without them: 36 (chord Newton to 1e-10).
TEST(FemCase, PicardIterationsServeSteadySolvesOnly) {
  const auto cfg = parse_fluid_fem(
      YAML::Load(replaced(
          kGood, "  output:", "  newton: {picard_iterations: 12}\n  output:"))["fluid_fem"],
      "case.yaml");
  EXPECT_EQ(cfg.newton.picard_iterations, 12);
  const std::string line = run_case(cfg).summary;
  const auto at = line.find("Newton iterations ");
  ASSERT_NE(at, std::string::npos) << line;
  const int iterations = std::stoi(line.substr(at + 18));
  std::printf("%s\n", line.c_str());
  EXPECT_LT(iterations, 12 * 4);
}

TEST(FemCase, RunWritesSeriesAndCsv) {
  const auto cfg = parse_fluid_fem(YAML::Load(kGood)["fluid_fem"], "case.yaml");
  const gf::test::TempDir tmp;
  const auto& dir = tmp.path();
  run_fluid_fem(cfg, dir);
  for (const char* f :
       {"fem_mesh.vtu", "fem_fields.pvd", "fem_fields_00000.vtu", "fem_fields_00002.vtu",
        "fem_forces.csv", "fem_probes.csv", "fem_summary.txt"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::ifstream in(dir / "fem_forces.csv");
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("t,dt,order,", 0), 0u) << header;
  EXPECT_NE(header.find("disk.torque"), std::string::npos);
  EXPECT_NE(header.find("tri.cd"), std::string::npos);
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 4);  // t = 0.05 .. 0.2
}
