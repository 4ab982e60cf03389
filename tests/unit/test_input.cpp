// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the input layer: case.yaml parsing, defaults, located errors, validation, echo.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <string>

#include "core/error.hpp"
#include "io/input/echo.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/validate.hpp"
#include "io/input/yaml_reader.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace gf;

namespace {

const fs::path data_dir = fs::path(GF_SOURCE_DIR) / "tests" / "data";

using test::TempDir;

/// The message of the InputError thrown by loading and validating `text`, or "" if none.
std::string error_of(const std::string& text, const std::string& label = "t.yaml") {
  try {
    const auto c = input::load_case_text(text, label);
    input::validate(c);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string minimal_case = R"(time: {step: 1.0e-5, end: 0.1}
domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - radius: 0.005
    material: glass
    positions: [[0.05, 0.05, 0.05]]
)";

}  // namespace

// ---------------------------------------------------------------------------------------------
// A good case: values and defaults

TEST(InputGoodCase, ValuesAndDefaults) {
  const auto c = input::load_case(data_dir / "good_case" / "case.yaml");
  EXPECT_EQ(c.name, "good_case");  // default: the case folder's name
  EXPECT_EQ(c.dimension, 3);
  EXPECT_DOUBLE_EQ(c.time.step, 1e-5);
  EXPECT_DOUBLE_EQ(c.time.end, 0.01);
  EXPECT_EQ(c.time.loc.line, 3);
  EXPECT_EQ(c.time.loc.key_path, "time.step");
  EXPECT_EQ(c.domain.max, (Vec3{0.2, 0.2, 0.4}));
  EXPECT_TRUE(c.domain.periodic[0]);
  EXPECT_FALSE(c.domain.periodic[2]);
  EXPECT_EQ(c.gravity, (Vec3{0, 0, -9.81}));
  EXPECT_EQ(c.integrator, "velocity_verlet");

  ASSERT_EQ(c.materials.size(), 2u);
  EXPECT_EQ(c.materials[0].name, "glass");
  EXPECT_EQ(c.materials[1].name, "steel");
  EXPECT_DOUBLE_EQ(c.materials[1].youngs_modulus, 2e8);
  EXPECT_EQ(c.materials[1].loc.key_path, "materials.steel");

  ASSERT_EQ(c.contacts.size(), 3u);
  const auto& hm = c.contacts[0];
  EXPECT_EQ(hm.model, "hertz_mindlin");
  EXPECT_DOUBLE_EQ(hm.params.at("restitution"), 0.5);
  EXPECT_DOUBLE_EQ(hm.params.at("friction"), 0.4);
  EXPECT_DOUBLE_EQ(hm.params.at("rolling_friction"), 0.0);  // default
  const auto& hk = c.contacts[1];
  EXPECT_EQ(hk.between[0], "steel");
  EXPECT_EQ(hk.model, "hooke");
  EXPECT_DOUBLE_EQ(hk.params.at("max_overlap"), 0.05);
  EXPECT_DOUBLE_EQ(hk.params.at("friction"), 0.5);  // default
  EXPECT_NEAR(hk.params.at("tangential_stiffness_ratio"), 2.0 / 7.0, 1e-15);
  EXPECT_EQ(hk.params.count("stiffness"), 0u);  // the other alternative stays absent
  EXPECT_DOUBLE_EQ(c.contacts[2].params.at("stiffness"), 1e5);

  ASSERT_EQ(c.particles.size(), 3u);
  const auto& g0 = c.particles[0];
  EXPECT_EQ(g0.shape, "sphere");
  EXPECT_EQ(g0.radius.kind, config::SizeDistribution::Kind::Normal);
  EXPECT_DOUBLE_EQ(g0.radius.mean, 0.004);
  EXPECT_DOUBLE_EQ(g0.radius.largest(), 0.005);
  ASSERT_TRUE(g0.fill.has_value());
  EXPECT_EQ(g0.fill->lattice, config::Fill::Lattice::Hcp);
  EXPECT_EQ(g0.fill->region.kind, config::Region::Kind::Box);
  EXPECT_EQ(g0.fill->count, 500);
  EXPECT_EQ(g0.fill->seed, 7u);
  EXPECT_FALSE(g0.fill->spacing.has_value());
  EXPECT_EQ(g0.fill->velocity, (Vec3{0, 0, -0.5}));
  EXPECT_EQ(g0.fill->loc.key_path, "particles[0].fill");

  const auto& g1 = c.particles[1];
  EXPECT_EQ(g1.shape, "sphere");  // default
  EXPECT_DOUBLE_EQ(g1.radius.value, 0.01);
  ASSERT_TRUE(g1.explicit_particles.has_value());
  ASSERT_EQ(g1.explicit_particles->positions.size(), 2u);
  EXPECT_EQ(g1.explicit_particles->lines, (std::vector<int>{38, 39}));
  ASSERT_EQ(g1.explicit_particles->velocities.size(), 2u);
  EXPECT_TRUE(g1.explicit_particles->angular_velocities.empty());

  const auto& g2 = c.particles[2];
  ASSERT_TRUE(g2.explicit_particles.has_value());
  const auto& csv = *g2.explicit_particles;
  EXPECT_EQ(csv.file.filename(), "particles.csv");
  ASSERT_EQ(csv.positions.size(), 2u);
  EXPECT_EQ(csv.lines, (std::vector<int>{3, 5}));  // comment and blank lines skipped
  EXPECT_EQ(csv.radii, (std::vector<double>{0.003, 0.004}));
  EXPECT_EQ(csv.velocities[1], (Vec3{0, 0, 0.1}));
  EXPECT_EQ(g2.radius.kind, config::SizeDistribution::Kind::Uniform);  // bounds of the file's radii
  EXPECT_DOUBLE_EQ(g2.radius.smallest(), 0.003);

  ASSERT_EQ(c.walls.size(), 2u);
  EXPECT_EQ(c.walls[0].kind, config::Wall::Kind::Plane);
  EXPECT_EQ(c.walls[0].normal, (Vec3{0, 0, 1}));  // normalised
  EXPECT_EQ(c.walls[1].kind, config::Wall::Kind::Cylinder);
  EXPECT_TRUE(c.walls[1].inside);  // default
  EXPECT_TRUE(c.walls[1].motion.rotates);
  EXPECT_NEAR(c.walls[1].motion.rate, std::numbers::pi, 1e-12);  // 30 rpm

  EXPECT_EQ(c.output.directory, "results");
  EXPECT_DOUBLE_EQ(c.output.vtk.every, 1e-3);
  EXPECT_DOUBLE_EQ(c.output.particles_csv.every, 0.0);  // off
  EXPECT_EQ(c.output.quantities,
            (std::vector<std::string>{"kinetic_energy", "wall_force.floor.z", "wall_torque.drum"}));
  ASSERT_TRUE(c.neighbor.skin.has_value());
  EXPECT_DOUBLE_EQ(*c.neighbor.skin, 0.001);
}

TEST(InputGoodCase, MinimalCaseDefaults) {
  const auto c = input::load_case_text(minimal_case, "some_folder/case.yaml");
  EXPECT_EQ(c.name, "some_folder");
  EXPECT_EQ(c.gravity, (Vec3{0, 0, -9.81}));
  EXPECT_EQ(c.output.directory, "out");
  EXPECT_FALSE(c.neighbor.skin.has_value());
  EXPECT_TRUE(c.walls.empty());
  EXPECT_EQ(c.domain.periodic, (std::array<bool, 3>{false, false, false}));
}

TEST(InputGoodCase, ValidateReportsDerivedNumbers) {
  const auto c = input::load_case(data_dir / "good_case" / "case.yaml");
  const auto report = input::validate(c);
  auto find = [&](const std::string& prefix) -> std::string {
    for (const auto& [k, v] : report.derived)
      if (k.rfind(prefix, 0) == 0) return v;
    return "";
  };
  EXPECT_NE(find("Rayleigh time, glass"), "");
  EXPECT_NE(find("contact time, glass-glass"), "");
  EXPECT_NE(find("impact speed"), "");
  EXPECT_NE(find("time step / contact time"), "");
  EXPECT_EQ(find("particles[0]: grains"), "~500");  // capped by count
  EXPECT_EQ(find("particles[2]: grains"), "2");
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
}

// ---------------------------------------------------------------------------------------------
// Malformed cases: each file says in its first line what is wrong; the error must name the
// file, the line and the key path.

struct BadCase {
  const char* file;       ///< under tests/data/bad_cases
  int line;               ///< expected line in the message
  const char* key_path;   ///< expected substring (the key path, or what the message is about)
  const char* also = "";  ///< another expected substring of the message
  const char* error_file = nullptr;  ///< file the message names, when not the case file (CSV)
};

const BadCase bad_cases[] = {
    {"unknown_top_key.yaml", 12, "gravty", "did you mean 'gravity'"},
    {"unknown_nested_key.yaml", 2, "time.stop", "accepted keys: step, end"},
    {"unknown_fill_key.yaml", 13, "particles[0].fill.lattise", "unknown key"},
    {"wrong_type.yaml", 2, "time.step", "found 'fast'"},
    {"quoted_number.yaml", 5, "materials.glass.density", "quoted string"},
    {"bool_yes.yaml", 3, "domain.periodic[0]", "true or false"},
    {"out_of_range.yaml", 5, "materials.glass.poisson_ratio", "in (-1, 0.5)"},
    {"missing_required.yaml", 5, "materials.glass.density", "missing required key 'density'"},
    {"missing_time_step.yaml", 2, "time.step", "missing required key 'step'"},
    {"missing_particles.yaml", 2, "particles", "missing required key"},
    {"empty_particles.yaml", 8, "particles", "at least 1"},
    {"unknown_model.yaml", 7, "contacts[0].model", "registered models: hooke, hertz_mindlin"},
    {"unknown_model_param.yaml", 8, "contacts[0].cohesion",
     "restitution, friction, rolling_friction"},
    {"hooke_missing_stiffness.yaml", 7, "contacts[0].stiffness",
     "'max_overlap' and 'reference_velocity'"},
    {"duplicate_contact_pair.yaml", 8, "contacts[1].between", "(glass, glass)"},
    {"unknown_material.yaml", 10, "particles[0].material", "'sand'"},
    {"missing_contact_pair.yaml", 14, "particles[1].material", "(glass, steel)"},
    {"duplicate_wall_name.yaml", 14, "walls[1].name", "'floor'"},
    {"bad_distribution.yaml", 9, "particles[0].radius.max", "> min"},
    {"normal_mean_outside.yaml", 9, "particles[0].radius.mean", "between min"},
    {"negative_radius.yaml", 9, "particles[0].radius", "found '-0.005'"},
    {"dt_too_large.yaml", 2, "time.step", "Rayleigh time"},
    {"end_before_step.yaml", 2, "time.end", ">= time.step"},
    {"particle_outside_domain.yaml", 13, "particles[0].positions[1]", "outside the domain"},
    {"overlapping_particles.yaml", 14, "particles[0].positions[2]", "overlaps particle 0"},
    {"yaml_syntax_error.yaml", 3, "YAML syntax error"},
    {"zero_normal.yaml", 14, "walls[0].plane.normal", "non-zero"},
    {"bad_lattice.yaml", 13, "particles[0].fill.lattice", "cubic, hcp, random"},
    {"random_without_count.yaml", 11, "particles[0].fill.count", "random"},
    {"spacing_too_small.yaml", 13, "particles[0].fill.spacing", "largest radius"},
    {"fill_outside_domain.yaml", 12, "particles[0].fill", "outside the domain"},
    {"unknown_series_quantity.yaml", 15, "output.series.quantities[1]", "kinetic_energie"},
    {"wall_force_unknown_wall.yaml", 15, "output.series.quantities[0]", "unknown wall 'roof'"},
    {"output_every_below_step.yaml", 13, "output.vtk.every", "time.step"},
    {"csv_missing.yaml", 11, "particles[0].file", "no_such_particles.csv"},
    {"csv_bad_number.yaml", 3, "particles[0].file", "column 'y'", "csv_bad_number.csv"},
    {"csv_unknown_column.yaml", 2, "particles[0].file", "unknown column 'mass'",
     "csv_unknown_column.csv"},
    {"dimension_2.yaml", 2, "dimension", "2D runs are not available yet"},
    {"two_particle_sources.yaml", 12, "particles[0].fill", "only one of fill, positions, file"},
    {"velocities_length.yaml", 12, "particles[0].velocities", "one per position"},
    {"domain_max_below_min.yaml", 3, "domain.max", "greater than"},
    {"rpm_and_rate.yaml", 18, "walls[0].motion.rotate.rate", "only one of rpm, rate"},
    {"box_open_bad_face.yaml", 14, "walls[0].box.open[0]", "'top'"},
    {"shape_not_available.yaml", 9, "particles[0].shape", "not available yet"},
    {"duplicate_key.yaml", 5, "time.end", "duplicate key"},
    {"periodic_too_short.yaml", 3, "domain.periodic", "periodic length along x"},
};

class InputBadCases : public ::testing::TestWithParam<BadCase> {};

TEST_P(InputBadCases, ErrorNamesFileLineAndKey) {
  const BadCase& bc = GetParam();
  const fs::path file = data_dir / "bad_cases" / bc.file;
  ASSERT_TRUE(fs::exists(file)) << file;
  std::string message;
  try {
    const auto c = input::load_case(file);
    input::validate(c);
  } catch (const InputError& e) {
    message = e.what();
  } catch (const std::exception& e) {
    FAIL() << "expected gf::InputError, got another exception: " << e.what();
  }
  ASSERT_FALSE(message.empty()) << bc.file << " was accepted";
  const std::string named = bc.error_file ? bc.error_file : bc.file;
  EXPECT_NE(message.find(named + ":" + std::to_string(bc.line) + ":"), std::string::npos)
      << "expected " << named << ":" << bc.line << " in: " << message;
  EXPECT_NE(message.find(": error: "), std::string::npos) << message;
  EXPECT_NE(message.find(bc.key_path), std::string::npos)
      << "expected '" << bc.key_path << "' in: " << message;
  EXPECT_NE(message.find(bc.also), std::string::npos)
      << "expected '" << bc.also << "' in: " << message;
}

INSTANTIATE_TEST_SUITE_P(Input, InputBadCases, ::testing::ValuesIn(bad_cases),
                         [](const ::testing::TestParamInfo<BadCase>& param_info) {
                           return fs::path(param_info.param.file).stem().string();
                         });

TEST(InputBadCaseFiles, EveryFileIsInTheTableAndSaysWhatIsWrong) {
  std::set<std::string> listed;
  for (const auto& bc : bad_cases) listed.insert(bc.file);
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(data_dir / "bad_cases")) {
    if (entry.path().extension() != ".yaml") continue;
    ++n;
    EXPECT_TRUE(listed.count(entry.path().filename().string()))
        << entry.path() << " is not in the table";
    std::ifstream in(entry.path());
    std::string first;
    std::getline(in, first);
    EXPECT_EQ(first.rfind("# ", 0), 0u)
        << entry.path() << " does not open with a comment saying what is wrong";
  }
  EXPECT_EQ(n, listed.size());
  EXPECT_GE(n, 25u);
}

// ---------------------------------------------------------------------------------------------
// The reader's finer points

TEST(InputReader, IntegersMayBeWrittenInExponentForm) {
  std::string text = minimal_case;
  text.replace(text.find("    positions: [[0.05, 0.05, 0.05]]\n"), std::string::npos,
               "    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}, lattice: random, count: "
               "1e1, seed: 3}\n");
  const auto c = input::load_case_text(text, "t.yaml");
  EXPECT_EQ(c.particles[0].fill->count, 10);
  EXPECT_EQ(c.particles[0].fill->seed, 3u);
  text.replace(text.find("count: 1e1"), 10, "count: 1.5");
  EXPECT_NE(error_of(text).find("expected an integer >= 1, found '1.5'"), std::string::npos)
      << error_of(text);
}

TEST(InputReader, NonFiniteNumbersAreRefused) {
  std::string text = minimal_case;
  text.replace(text.find("end: 0.1"), 8, "end: .inf");
  EXPECT_NE(error_of(text).find("t.yaml:1:"), std::string::npos) << error_of(text);
  EXPECT_NE(error_of(text).find("time.end: expected a number > 0, found '.inf'"),
            std::string::npos);
}

TEST(InputReader, EmptyFileAndMissingFile) {
  EXPECT_NE(error_of("", "empty.yaml").find("empty.yaml:1:1: error: expected a map"),
            std::string::npos)
      << error_of("", "empty.yaml");
  try {
    input::load_case(data_dir / "no_such_case.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_case.yaml: error: case file not found"),
              std::string::npos)
        << e.what();
  }
}

TEST(InputReader, TwoDocumentsAreRefused) {
  EXPECT_NE(error_of(minimal_case + "---\nname: x\n").find("one YAML document"), std::string::npos);
}

TEST(InputReader, HookeWithBothStiffnessFormsIsRefused) {
  std::string text = minimal_case;
  text.replace(text.find("model: hertz_mindlin"), 20,
               "model: hooke, stiffness: 1000, max_overlap: 0.01, reference_velocity: 1");
  const std::string msg = error_of(text);
  EXPECT_NE(msg.find("contacts[0].stiffness: contact model 'hooke' needs exactly one of"),
            std::string::npos)
      << msg;
}

TEST(InputReader, SeriesQuantityNames) {
  const std::vector<std::string> walls{"floor", "drum"};
  EXPECT_TRUE(input::is_series_quantity("kinetic_energy", walls));
  EXPECT_TRUE(input::is_series_quantity("wall_force.floor", walls));
  EXPECT_TRUE(input::is_series_quantity("wall_torque.drum.y", walls));
  EXPECT_FALSE(input::is_series_quantity("wall_force.roof", walls));
  EXPECT_FALSE(input::is_series_quantity("wall_force.floor.w", walls));
  EXPECT_FALSE(input::is_series_quantity("wall_force.", walls));
}

TEST(InputReader, RangeDescriptions) {
  EXPECT_EQ(input::Range::positive().describe(), "> 0");
  EXPECT_EQ(input::Range::non_negative().describe(), ">= 0");
  EXPECT_EQ((input::Range{-1, 0.5, true, true}).describe(), "in (-1, 0.5)");
  EXPECT_EQ((input::Range{0, 1, true, false}).describe(), "in (0, 1]");
  EXPECT_TRUE((input::Range{0, 1, true, false}).contains(1.0));
  EXPECT_FALSE((input::Range{0, 1, true, false}).contains(0.0));
}

// ---------------------------------------------------------------------------------------------
// Validation

TEST(InputValidate, TimeStepWarningBetweenLimits) {
  // 5 mm glass: Rayleigh time 4.33e-4 s; 0.2 x that is above 0.15 x, below 0.3 x.
  std::string text = minimal_case;
  text.replace(text.find("step: 1.0e-5"), 12, "step: 8.7e-5");
  const auto report = input::validate(input::load_case_text(text, "t.yaml"));
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("Rayleigh time"), std::string::npos) << report.warnings[0];
}

TEST(InputValidate, ManyExplicitParticlesWithoutOverlapAreFast) {
  // 39 x 40 x 40 = 62400 touching grains on a cubic lattice in a periodic box, with a gap along x;
  // then one extra grain in the gap that overlaps a grain only across the periodic boundary.
  TempDir dir;
  std::string csv = "x,y,z\n";
  const int n = 40;
  const double d = 0.01;
  for (int i = 0; i < n - 1; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        csv += fmt::format("{},{},{}\n", (i + 0.5) * d, (j + 0.5) * d, (k + 0.5) * d);
  dir.write("grains.csv", csv);
  std::string text = minimal_case;
  text.replace(text.find("max: [0.1, 0.1, 0.1]}"), 21,
               "max: [0.4, 0.4, 0.4], periodic: [true, true, true]}");
  text.replace(text.find("    positions: [[0.05, 0.05, 0.05]]\n"), std::string::npos,
               "    file: grains.csv\n");
  const fs::path file = dir.write("case.yaml", text);
  const auto c = input::load_case(file);
  EXPECT_EQ(c.particles[0].explicit_particles->positions.size(), 62400u);
  EXPECT_NO_THROW(input::validate(c));

  std::ofstream(dir.path() / "grains.csv", std::ios::app)
      << "0.3975,0.005,0.005\n";  // 0.0075 from x = 0.005
  try {
    input::validate(input::load_case(file));
    FAIL() << "overlap across the periodic boundary not found";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("grains.csv:62402: error: particles[0].file: particle 62400"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("overlaps particle 0 "), std::string::npos) << msg;
  }
}

TEST(InputValidate, HookeSoftSpringIgnoresRayleighTime) {
  // A stiff material but a soft hooke spring: the contact time governs, not the Rayleigh time.
  std::string text = minimal_case;
  text.replace(text.find("youngs_modulus: 1.0e7"), 21, "youngs_modulus: 2.0e11");
  text.replace(text.find("model: hertz_mindlin"), 20, "model: hooke, stiffness: 1000");
  EXPECT_EQ(error_of(text), "");
}

// ---------------------------------------------------------------------------------------------
// Echo

TEST(InputEcho, RoundTripGivesTheSameCase) {
  const auto c = input::load_case(data_dir / "good_case" / "case.yaml");
  const std::string text = input::echo_yaml(c, "9.9.9");
  EXPECT_EQ(text.rfind("# grainflow 9.9.9: resolved configuration of ", 0), 0u) << text;
  TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", text));
  EXPECT_EQ(again.name, c.name);
  EXPECT_EQ(again.time.step, c.time.step);
  EXPECT_EQ(again.domain.periodic, c.domain.periodic);
  ASSERT_EQ(again.contacts.size(), c.contacts.size());
  for (std::size_t i = 0; i < c.contacts.size(); ++i)
    EXPECT_EQ(again.contacts[i].params, c.contacts[i].params);
  ASSERT_EQ(again.particles.size(), c.particles.size());
  EXPECT_EQ(again.particles[0].radius.std, c.particles[0].radius.std);
  EXPECT_EQ(again.particles[0].fill->spacing.value_or(0),
            2 * 0.005 * 1.01);  // the default, now explicit
  EXPECT_EQ(again.particles[1].explicit_particles->velocities,
            c.particles[1].explicit_particles->velocities);
  EXPECT_EQ(again.particles[2].explicit_particles->radii, c.particles[2].explicit_particles->radii);
  EXPECT_EQ(again.walls[1].motion.rate, c.walls[1].motion.rate);
  EXPECT_EQ(again.walls[0].normal, c.walls[0].normal);
  EXPECT_EQ(again.output.quantities, c.output.quantities);
  EXPECT_EQ(again.neighbor.skin, c.neighbor.skin);
}

TEST(InputEcho, LongParticleListsAreSummarised) {
  std::string positions = "    positions:\n";
  for (int i = 0; i < 25; ++i)
    positions += fmt::format("      - [{}, 0.05, 0.05]\n", 0.002 + i * 0.004);
  std::string text = minimal_case;
  text.replace(text.find("radius: 0.005"), 13, "radius: 0.001");
  text.replace(text.find("    positions: [[0.05, 0.05, 0.05]]\n"), std::string::npos, positions);
  const auto c = input::load_case_text(text, "long.yaml");
  input::validate(c);
  const std::string echo = input::echo_yaml(c, "1");
  EXPECT_NE(echo.find("positions: {count: 25, source: long.yaml}"), std::string::npos) << echo;
  EXPECT_EQ(echo.find("0.098"), std::string::npos) << echo;
}
