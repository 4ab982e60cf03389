// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the input layer: case.yaml parsing, defaults, located errors, validation, echo.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <set>
#include <string>

#include "contact/geometry/polygon2d.hpp"
#include "core/error.hpp"
#include "io/input/echo.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/stl.hpp"
#include "io/input/validate.hpp"
#include "io/input/yaml_reader.hpp"
#include "simulation/simulation.hpp"
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

/// The part of a case before `particles:` in 2D: glass disks in a 0.1 m square.
const std::string header_2d = R"(dimension: 2
time: {step: 1.0e-5, end: 0.1}
domain: {min: [0, 0], max: [0.1, 0.1]}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
)";

/// The same in 3D (a 0.1 m cube).
const std::string header_3d = R"(time: {step: 1.0e-5, end: 0.1}
domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
)";

/// The derived number of `report` whose name starts with `prefix`, or "".
std::string derived(const input::CheckReport& report, const std::string& prefix) {
  for (const auto& [k, v] : report.derived)
    if (k.rfind(prefix, 0) == 0) return v;
  return "";
}

/// The number at the start of `text` ("1.23e-05 s" -> 1.23e-05).
double leading_number(const std::string& text) {
  return std::stod(text);
}

void expect_quat_near(const Quat& a, const Quat& b, double tol = 1e-12) {
  EXPECT_NEAR(a.w, b.w, tol);
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
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
    {"cohesion_negative.yaml", 8, "contacts[0].cohesion_energy_density", "found '-2.0e4'"},
    {"cohesion_not_a_number.yaml", 11, "contacts[0].cohesion_energy_density", "found 'strong'"},
    {"cohesion_misspelled.yaml", 10, "contacts[0].cohesion_energy_densty",
     "did you mean 'cohesion_energy_density'"},
    {"cohesion_polygons.yaml", 11, "contacts[0].cohesion_energy_density",
     "not available for polygon grains"},
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
    {"dimension_2.yaml", 4, "domain.min", "expected 2 components in a 2D case"},
    {"two_particle_sources.yaml", 12, "particles[0].fill", "only one of fill, positions, file"},
    {"velocities_length.yaml", 12, "particles[0].velocities", "one per position"},
    {"domain_max_below_min.yaml", 3, "domain.max", "greater than"},
    {"rpm_and_rate.yaml", 18, "walls[0].motion.rotate.rate", "only one of rpm, rate"},
    {"box_open_bad_face.yaml", 14, "walls[0].box.open[0]", "'top'"},
    {"shape_not_available.yaml", 9, "particles[0].shape", "not available in a 3D case"},
    {"duplicate_key.yaml", 5, "time.end", "duplicate key"},
    {"periodic_too_short.yaml", 3, "domain.periodic", "periodic length along x"},
    // Shapes, orientations, 2D cases, integrators.
    {"dimension_4.yaml", 2, "dimension", "expected 2 or 3, found '4'"},
    {"vector_2_in_3d.yaml", 10, "gravity", "expected 3 components in a 3D case"},
    {"thickness_in_3d.yaml", 3, "domain.thickness", "2D cases only"},
    {"sphere_in_2d.yaml", 10, "particles[0].shape", "not available in a 2D case"},
    {"cylinder_wall_2d.yaml", 13, "walls[0].cylinder.axis", "unknown key"},
    {"mesh_missing_file.yaml", 13, "walls[0].mesh.file", "no such file"},
    {"mesh_not_stl.yaml", 11, "walls[0].mesh.file", "not a readable STL file"},
    {"mesh_wall_2d.yaml", 12, "walls[0].mesh", "not available in 2D"},
    {"cylinder_fill_2d.yaml", 13, "particles[0].fill.cylinder.height", "unknown key"},
    {"spherocylinder_no_length.yaml", 9, "particles[0].length", "'length' (m"},
    {"spherocylinder_length_and_ratio.yaml", 12, "particles[0].aspect_ratio",
     "only one of length, aspect_ratio"},
    {"aspect_ratio_below_one.yaml", 11, "particles[0].aspect_ratio", "a number >= 1, found '0.5'"},
    {"equivalent_diameter_without_ratio.yaml", 9, "particles[0].aspect_ratio",
     "missing required key 'aspect_ratio'"},
    {"length_on_sphere.yaml", 11, "particles[0].length", "spherocylinder only"},
    {"polygon_not_convex.yaml", 15, "particles[0].polygon.vertices[2]",
     "not strictly convex and counter-clockwise at vertex 2 [0.002, 0.001]"},
    {"polygon_clockwise.yaml", 11, "particles[0].polygon.vertices", "listed clockwise"},
    {"polygon_vertices_with_radius.yaml", 11, "particles[0].radius", "remove 'radius'"},
    {"polygon_regular_too_many.yaml", 12, "particles[0].polygon.regular", "in [3, 16]"},
    {"polygon_random_bad_range.yaml", 13, "particles[0].polygon.random.vertices[1]",
     ">= the minimum (8)"},
    {"orientation_on_sphere.yaml", 13, "particles[0].fill.orientation", "shape: sphere"},
    {"angular_velocity_vector_2d.yaml", 13, "particles[0].angular_velocities[0]",
     "scalars in a 2D case"},
    {"gear_integrator.yaml", 2, "integrator", "did you mean 'gear5'"},
    {"servo_on_box.yaml", 14, "walls[0].servo", "needs a plane wall"},
    {"servo_unknown_span.yaml", 16, "walls[1].servo.span[0][1]", "found 'rigth'"},
    {"servo_two_spans_2d.yaml", 17, "walls[2].servo.span", "expected 1 pair(s)"},
    {"axes_length.yaml", 14, "particles[0].axes", "one per position"},
    {"overlapping_spherocylinders.yaml", 15, "particles[0].positions[1]",
     "distance of their axes 0.001 m < 0.004 m"},
    {"overlapping_polygons.yaml", 15, "particles[0].positions[1]", "outlines intersect"},
    {"periodic_three_in_2d.yaml", 4, "domain.periodic", "expected 2 components in a 2D case"},
    {"rotate_axis_2d.yaml", 15, "walls[0].motion.rotate.axis", "rotation is about z"},
    {"box_zmin_2d.yaml", 13, "walls[0].box.open[1]", "no face 'zmin'"},
    {"csv_z_in_2d.yaml", 2, "particles[0].file", "column 'z' does not apply to a 2D case",
     "csv_z_in_2d.csv"},
    {"csv_partial_quaternion.yaml", 1, "particles[0].file", "qw, qx, qy, qz go together",
     "csv_partial_quaternion.csv"},
    // Outlets.
    {"outlet_outside_domain.yaml", 14, "outlets[0].box", "outlet 'bottom' lies outside the domain"},
    {"duplicate_outlet_name.yaml", 14, "outlets[1].name", "first used at line 13"},
    {"outlet_unknown_in_series.yaml", 15, "output.series.quantities[1]",
     "unknown outlet 'holes' in 'outlet_mass.holes'; declared outlets: hole"},
    {"inlet_batch_too_dense.yaml", 12, "particles[0].inlet", "would fill 26 % of its region"},
    {"inlet_mass_rate_too_dense.yaml", 12, "particles[0].inlet",
     "(mass_rate / mean grain mass x every = 49.66 grains) would fill 26 % of its region"},
    {"inlet_rate_and_mass_rate.yaml", 14, "particles[0].inlet.mass_rate",
     "give only one of rate, mass_rate"},
    {"inlet_outside_domain.yaml", 12, "particles[0].inlet", "reaches outside the domain"},
    {"outlet_reinsert_overlaps.yaml", 16, "outlets[0].reinsert.box", "would be taken again"},
    {"outlet_reinsert_too_small.yaml", 16, "outlets[0].reinsert",
     "0.008 m across at its narrowest, less than the largest grain (0.01 m across)"},
    // Mixing index.
    {"mixing_one_material.yaml", 14, "analysis.mixing.materials", "two material names"},
    {"mixing_unknown_material.yaml", 14, "analysis.mixing.materials[1]", "a declared material"},
    {"lacey_without_mixing.yaml", 14, "output.series.quantities[1]", "needs analysis.mixing"},
    // Regions.
    {"region_outside_domain.yaml", 14, "regions[0].box",
     "region 'pit' lies outside the domain [0, 0] - [0.1, 0.1]: it would never hold a grain"},
    {"duplicate_region_name.yaml", 15, "regions[1].name", "duplicate region name 'pit'"},
    {"region_unknown_in_series.yaml", 16, "output.series.quantities[0]",
     "unknown region 'pits' in 'region_mass.pits'; declared regions: pit"},
    // Flow meters.
    {"flow_meter_outside_domain.yaml", 14, "flow_meters[0].point",
     "misses the domain [0, 0] - [0.1, 0.1]: it would never count a grain"},
    {"duplicate_flow_meter_name.yaml", 15, "flow_meters[1].name", "first used at line 14"},
    {"flow_meter_unknown_in_series.yaml", 16, "output.series.quantities[1]",
     "unknown flow meter 'nek' in 'flow_mass.nek'; declared flow meters: neck"},
    {"flow_meter_zero_normal.yaml", 14, "flow_meters[0].normal", "non-zero vector"},
    {"flow_meter_negative_radius.yaml", 14, "flow_meters[0].radius", "a number > 0"},
    // Heat conduction.
    {"heat_temperature_without_block.yaml", 12, "particles[0].temperature",
     "a temperature needs heat conduction"},
    {"heat_material_without_conductivity.yaml", 6, "materials.glass",
     "needs thermal_conductivity (W/(m K)) and heat_capacity"},
    {"heat_unknown_model.yaml", 9, "heat.model",
     "a conduction model: batchelor_obrien, intersection_area, found 'batchelor'"},
    {"heat_in_2d.yaml", 9, "heat", "heat conduction is for 3D cases"},
    {"heat_series_without_block.yaml", 14, "output.series.quantities[1]",
     "'temperature_mean' needs heat conduction"},
    {"heat_wall_material_without_conductivity.yaml", 7, "materials.steel",
     "of wall 'floor', which has a temperature"},
    {"heat_without_temperature.yaml", 9, "heat.temperature", "missing required key"},
    {"heat_source_without_block.yaml", 12, "particles[0].heat_source",
     "a heat source needs heat conduction"},
    {"fluid_heat_transfer_without_heat.yaml", 16, "coupling.heat_transfer",
     "needs the grains' temperatures"},
    {"fluid_heat_transfer_unknown.yaml", 17, "coupling.heat_transfer", "none, ranz_marshall, gunn"},
    {"fluid_heat_without_capacity.yaml", 14, "fluid.heat_capacity", "needs the fluid's"},
    {"fluid_inlet_without_temperature.yaml", 21, "fluid.boundary.zmin",
     "needs the temperature of its inflow"},
    {"fluid_temperature_convection_central.yaml", 20, "fluid.temperature_convection",
     "one of van_leer, upwind"},
    {"fluid_series_unknown_face.yaml", 23, "output.series.quantities[0]",
     "unknown box face 'top' in 'fluid_boundary_heat_flow.top'; expected one of xmin, xmax"},
    {"fluid_reference_temperature_without_expansion.yaml", 20, "fluid.reference_temperature",
     "needs the fluid's thermal_expansion"},
    {"fluid_heat_capacity_without_exchange.yaml", 18, "fluid.heat_capacity",
     "set coupling.heat_transfer"},
    {"fluid_series_temperature_without_exchange.yaml", 18, "output.series.quantities[1]",
     "needs the fluid's temperature"},
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
  EXPECT_TRUE(input::is_series_quantity("wall_force_mean.floor", walls));
  EXPECT_TRUE(input::is_series_quantity("wall_torque_mean.drum.x", walls));
  EXPECT_TRUE(input::is_series_quantity("wall_contact_count", walls));
  EXPECT_FALSE(input::is_series_quantity("wall_force_mean.roof", walls));
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

TEST(InputEcho, OutletsAndInletsRoundTrip) {
  const auto c = input::load_case_text(header_2d + R"(particles:
  - radius: 0.005
    material: glass
    positions: [[0.05, 0.05]]
  - radius: {distribution: uniform, min: 0.001, max: 0.002}
    material: glass
    inlet: {box: {min: [0, 0.08], max: [0.1, 0.1]}, rate: 50, velocity: [0, -1], stop: 0.05}
  - radius: 0.001
    material: glass
    inlet: {box: {min: [0, 0.08], max: [0.1, 0.1]}, mass_rate: 0.002, start: 0.01}
outlets:
  - {name: slot, box: {min: [0.04, 0], max: [0.06, 0.01]}}
  - name: pit
    cylinder: {center: [0.09, 0.01], radius: 0.01}
    reinsert: {box: {min: [0, 0.08], max: [0.1, 0.1]}}
output:
  series: {every: 0.01, quantities: [particle_count, outlet_mass.pit, outlet_count.slot]}
)",
                                       "outlets.yaml");
  ASSERT_EQ(c.outlets.size(), 2u);
  EXPECT_EQ(c.outlets[0].region.kind, config::Region::Kind::Box);
  EXPECT_EQ(c.outlets[1].region.kind, config::Region::Kind::Cylinder);
  EXPECT_EQ(c.outlets[1].region.radius, 0.01);
  EXPECT_FALSE(c.outlets[0].reinsert);
  ASSERT_TRUE(c.outlets[1].reinsert);
  const auto again = input::load_case_text(input::echo_yaml(c, "1"), "echo.yaml");
  ASSERT_EQ(again.outlets.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(again.outlets[k].name, c.outlets[k].name);
    EXPECT_EQ(again.outlets[k].region.min, c.outlets[k].region.min);
    EXPECT_EQ(again.outlets[k].region.max, c.outlets[k].region.max);
    EXPECT_EQ(again.outlets[k].region.center, c.outlets[k].region.center);
    EXPECT_EQ(again.outlets[k].reinsert.has_value(), c.outlets[k].reinsert.has_value());
  }
  EXPECT_EQ(again.outlets[1].reinsert->max, c.outlets[1].reinsert->max);
  ASSERT_TRUE(again.particles[1].inlet);
  EXPECT_EQ(again.particles[1].inlet->rate, 50);
  EXPECT_EQ(again.particles[1].inlet->velocity, (Vec3{0, -1, 0}));
  EXPECT_EQ(again.particles[1].inlet->stop, 0.05);
  EXPECT_EQ(again.particles[1].inlet->every, 0.01);
  EXPECT_EQ(again.particles[1].inlet->region.max, (Vec3{0.1, 0.1, 0}));
  EXPECT_FALSE(again.particles[1].inlet->mass_rate);
  ASSERT_TRUE(again.particles[2].inlet);
  EXPECT_EQ(again.particles[2].inlet->mass_rate, 0.002);
  EXPECT_EQ(again.particles[2].inlet->rate, 0);
  EXPECT_EQ(again.output.quantities, c.output.quantities);
}

TEST(InputEcho, MixingRoundTrip) {
  const auto c = input::load_case_text(R"(time: {step: 1.0e-5, end: 0.1}
domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
  red: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
  - {between: [red, red], model: hertz_mindlin, restitution: 0.5}
  - {between: [red, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - radius: 0.005
    material: glass
    positions: [[0.05, 0.05, 0.05]]
  - radius: 0.005
    material: red
    positions: [[0.02, 0.05, 0.05]]
analysis:
  mixing: {materials: [red, glass], cell: 0.02, min_grains: 3}
output:
  series: {every: 0.01, quantities: [lacey_index]}
)",
                                       "mixing.yaml");
  ASSERT_TRUE(c.analysis.mixing);
  EXPECT_EQ(c.analysis.mixing->materials, (std::vector<std::string>{"red", "glass"}));
  EXPECT_EQ(c.analysis.mixing->cell, 0.02);
  EXPECT_EQ(c.analysis.mixing->min_grains, 3);
  const auto again = input::load_case_text(input::echo_yaml(c, "1"), "echo.yaml");
  ASSERT_TRUE(again.analysis.mixing);
  EXPECT_EQ(again.analysis.mixing->materials, c.analysis.mixing->materials);
  EXPECT_EQ(again.analysis.mixing->cell, c.analysis.mixing->cell);
  EXPECT_EQ(again.analysis.mixing->min_grains, 3);
  EXPECT_EQ(again.output.quantities, c.output.quantities);
}

TEST(InputEcho, RegionsRoundTrip) {
  const auto c = input::load_case_text(header_3d + R"(particles:
  - radius: 0.005
    material: glass
    positions: [[0.05, 0.05, 0.05]]
regions:
  - {name: low, box: {min: [0, 0, 0], max: [0.1, 0.1, 0.03]}}
  - name: core
    cylinder: {center: [0.05, 0.05, 0], axis: [0, 0, 1], radius: 0.02, height: 0.1}
output:
  series: {every: 0.01, quantities: [region_count.low, region_mass.core]}
)",
                                       "regions.yaml");
  ASSERT_EQ(c.regions.size(), 2u);
  EXPECT_EQ(c.regions[1].region.kind, config::Region::Kind::Cylinder);
  const auto again = input::load_case_text(input::echo_yaml(c, "1"), "echo.yaml");
  ASSERT_EQ(again.regions.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(again.regions[k].name, c.regions[k].name);
    EXPECT_EQ(again.regions[k].region.kind, c.regions[k].region.kind);
    EXPECT_EQ(again.regions[k].region.max, c.regions[k].region.max);
    EXPECT_EQ(again.regions[k].region.radius, c.regions[k].region.radius);
  }
  EXPECT_EQ(again.output.quantities, c.output.quantities);
}

TEST(InputEcho, FlowMetersRoundTrip) {
  const auto c = input::load_case_text(header_2d + R"(particles:
  - radius: 0.005
    material: glass
    positions: [[0.05, 0.05]]
flow_meters:
  - {name: neck, point: [0.05, 0.02], normal: [0, -2], radius: 0.01}
  - {name: wide, point: [0.05, 0.05], normal: [1, 1]}
output:
  series: {every: 0.01, quantities: [flow_mass.neck, flow_count.wide, flow_rate.neck]}
)",
                                       "meters.yaml");
  ASSERT_EQ(c.flow_meters.size(), 2u);
  EXPECT_EQ(c.flow_meters[0].normal, (Vec3{0, -1, 0}));  // made unit
  EXPECT_EQ(c.flow_meters[0].radius, 0.01);
  EXPECT_FALSE(c.flow_meters[1].radius);
  EXPECT_NEAR(c.flow_meters[1].normal.x, std::sqrt(0.5), 1e-15);
  const auto again = input::load_case_text(input::echo_yaml(c, "1"), "echo.yaml");
  ASSERT_EQ(again.flow_meters.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(again.flow_meters[k].name, c.flow_meters[k].name);
    EXPECT_EQ(again.flow_meters[k].point, c.flow_meters[k].point);
    EXPECT_LT(norm(again.flow_meters[k].normal - c.flow_meters[k].normal), 1e-15);  // re-made unit
    EXPECT_EQ(again.flow_meters[k].radius, c.flow_meters[k].radius);
  }
  EXPECT_EQ(again.output.quantities, c.output.quantities);
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

namespace {

/// Echoes `c` with its long particle lists as files, writes them into a fresh folder and loads
/// the resolved case back from there.
config::Case echo_and_reload(const config::Case& c, TempDir& dir, std::size_t expect_files) {
  std::vector<input::EchoFile> files;
  const std::string echo = input::echo_yaml(c, "1", &files);
  EXPECT_EQ(files.size(), expect_files) << echo;
  for (const auto& f : files) dir.write(f.name, f.text);
  return input::load_case(dir.write("resolved_case.yaml", echo));
}

}  // namespace

// A run's resolved case puts long particle lists into CSV files beside it (the folder a run
// writes both to): the resolved case loads back into the same particles, velocities and
// orientations (3D rods with axes, 2D polygons with angles and spins), so every resolved case
// runs again as it is.
TEST(InputEcho, LongParticleListsGoToFilesThatLoadBack) {
  std::string text = header_3d +
                     "particles:\n  - radius: 0.001\n    material: glass\n"
                     "    positions:\n";
  std::string vel = "    velocities:\n", spin = "    angular_velocities:\n";
  for (int i = 0; i < 25; ++i) {
    text += fmt::format("      - [{}, 0.05, 0.05]\n", 0.002 + i * 0.004);
    vel += fmt::format("      - [0.1, {}, -0.3]\n", 0.01 * i);
    spin += fmt::format("      - [{}, 0, 1]\n", 2.5 * i);
  }
  text += vel + spin;
  // A second group of rods, tilted one by one, and a short list that stays inline.
  text +=
      "  - {shape: spherocylinder, radius: 0.0005, length: 0.002, material: glass,\n"
      "     positions: [";
  std::string axes = "axes: [";
  for (int i = 0; i < 22; ++i) {
    text += fmt::format("{}[{}, 0.02, 0.08]", i ? ", " : "", 0.003 + i * 0.0042);
    axes += fmt::format("{}[{}, 0.3, 1]", i ? ", " : "", 0.1 * i - 1.0);
  }
  text += "],\n     " + axes + "]}\n";
  text += "  - {radius: 0.001, material: glass, positions: [[0.05, 0.05, 0.09]]}\n";
  const auto c = input::load_case_text(text, "long.yaml");
  input::validate(c);
  TempDir dir;
  const auto again = echo_and_reload(c, dir, 2);
  ASSERT_EQ(again.particles.size(), 3u);
  for (std::size_t g = 0; g < 3; ++g) {
    const auto& a = *c.particles[g].explicit_particles;
    const auto& b = *again.particles[g].explicit_particles;
    ASSERT_EQ(b.positions.size(), a.positions.size()) << g;
    EXPECT_EQ(b.velocities.size(), a.velocities.size()) << g;
    EXPECT_EQ(b.angular_velocities.size(), a.angular_velocities.size()) << g;
    ASSERT_EQ(b.orientations.size(), a.orientations.size()) << g;
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_EQ(norm(b.positions[i] - a.positions[i]), 0.0) << g << " " << i;
      if (!a.velocities.empty()) {
        EXPECT_EQ(norm(b.velocities[i] - a.velocities[i]), 0.0);
      }
      if (!a.angular_velocities.empty()) {
        EXPECT_EQ(norm(b.angular_velocities[i] - a.angular_velocities[i]), 0.0);
      }
      if (!a.orientations.empty()) {
        const Quat &p = a.orientations[i], &q = b.orientations[i];
        EXPECT_NEAR(std::abs(p.w * q.w + p.x * q.x + p.y * q.y + p.z * q.z), 1.0, 1e-15) << i;
      }
    }
  }
  EXPECT_EQ(again.particles[1].kind, config::Shape::Spherocylinder);
  EXPECT_TRUE(again.particles[2].explicit_particles->file.empty());  // short: inline
  // The reloaded case reads its grains from the CSV files; its echo copies them again (a run's
  // folder holds everything it ran from), with the same data.
  TempDir dir2;
  const auto third = echo_and_reload(again, dir2, 2);
  for (std::size_t g = 0; g < 2; ++g) {
    const auto& a = *c.particles[g].explicit_particles;
    const auto& b = *third.particles[g].explicit_particles;
    ASSERT_EQ(b.positions.size(), a.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i)
      EXPECT_EQ(norm(b.positions[i] - a.positions[i]), 0.0) << g << " " << i;
  }
  // Without a list of files (a sweep's plan), a CSV source is named by its absolute path.
  const std::string digest = input::echo_yaml(again, "1");
  EXPECT_NE(digest.find((dir / "resolved_particles_0.csv").lexically_normal().string()),
            std::string::npos)
      << digest;
}

TEST(InputEcho, LongPolygonListsIn2DGoToFilesThatLoadBack) {
  std::string text = header_2d + R"(particles:
  - shape: polygon
    polygon: {regular: 5}
    radius: 0.002
    material: glass
)";
  std::string pos = "    positions: [", ang = "    angles: [", spin = "    angular_velocities: [";
  for (int i = 0; i < 30; ++i) {  // two rows of 15
    pos += fmt::format("{}[{}, {}]", i ? ", " : "", 0.005 + (i % 15) * 0.006, i < 15 ? 0.03 : 0.06);
    ang += fmt::format("{}{}", i ? ", " : "", 0.1 * i);
    spin += fmt::format("{}{}", i ? ", " : "", -3.0 + i);
  }
  text += pos + "]\n" + ang + "]\n" + spin + "]\n";
  const auto c = input::load_case_text(text, "poly.yaml");
  input::validate(c);
  TempDir dir;
  const auto again = echo_and_reload(c, dir, 1);
  const auto& a = *c.particles[0].explicit_particles;
  const auto& b = *again.particles[0].explicit_particles;
  ASSERT_EQ(b.positions.size(), 30u);
  ASSERT_EQ(b.orientations.size(), 30u);
  ASSERT_EQ(b.angular_velocities.size(), 30u);
  for (std::size_t i = 0; i < 30; ++i) {
    EXPECT_EQ(norm(b.positions[i] - a.positions[i]), 0.0) << i;
    EXPECT_EQ(b.angular_velocities[i].z, a.angular_velocities[i].z) << i;
    EXPECT_NEAR(b.orientations[i].z, a.orientations[i].z, 1e-15) << i;
    EXPECT_NEAR(b.orientations[i].w, a.orientations[i].w, 1e-15) << i;
  }
}

// ---------------------------------------------------------------------------------------------
// Shapes

TEST(InputShapes, SpherocylinderWithLengthOrAspectRatio) {
  const auto c = input::load_case_text(header_3d + R"(particles:
  - shape: spherocylinder
    radius: 0.001
    length: 0.004
    material: glass
    positions: [[0.05, 0.05, 0.05]]
  - shape: spherocylinder
    radius: {distribution: uniform, min: 0.001, max: 0.002}
    aspect_ratio: 3
    material: glass
    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.04]}, lattice: cubic}
)",
                                       "t.yaml");
  const auto& g0 = c.particles[0];
  EXPECT_EQ(g0.kind, config::Shape::Spherocylinder);
  EXPECT_EQ(g0.shape, "spherocylinder");
  ASSERT_TRUE(g0.length.has_value());
  EXPECT_DOUBLE_EQ(*g0.length, 0.004);
  EXPECT_FALSE(g0.aspect_ratio.has_value());
  EXPECT_DOUBLE_EQ(input::cylinder_length(g0, 0.001), 0.004);
  EXPECT_DOUBLE_EQ(input::bounding_radius(g0, 0.001), 0.003);
  const auto& g1 = c.particles[1];
  EXPECT_FALSE(g1.length.has_value());
  ASSERT_TRUE(g1.aspect_ratio.has_value());
  EXPECT_DOUBLE_EQ(*g1.aspect_ratio, 3.0);
  EXPECT_EQ(g1.radius.kind, config::SizeDistribution::Kind::Uniform);
  EXPECT_DOUBLE_EQ(input::cylinder_length(g1, 0.002), 0.008);  // L = 2 r (alpha - 1)
  EXPECT_FALSE(g1.fill->orientation.has_value());              // default: random
  // Volume pi r^2 L + 4/3 pi r^3.
  EXPECT_NEAR(input::grain_measure(g0, 0.001),
              std::numbers::pi * 1e-6 * 0.004 + 4.0 / 3.0 * std::numbers::pi * 1e-9, 1e-20);
  EXPECT_EQ(error_of(header_3d + R"(particles:
  - shape: spherocylinder
    radius: 0.001
    length: 0.004
    material: glass
    positions: [[0.05, 0.05, 0.05]]
)"),
            "");
}

TEST(InputShapes, EquivalentDiameterGivesTheCapRadius) {
  const auto c = input::load_case_text(header_3d + R"(particles:
  - shape: spherocylinder
    equivalent_diameter: 0.004
    aspect_ratio: 3
    material: glass
    positions: [[0.05, 0.05, 0.05]]
)",
                                       "t.yaml");
  const auto& g = c.particles[0];
  ASSERT_EQ(g.radius.kind, config::SizeDistribution::Kind::Fixed);
  // r = d / (12 alpha - 4)^(1/3) = 0.004 / 32^(1/3).
  EXPECT_NEAR(g.radius.value, 0.004 / std::cbrt(32.0), 1e-18);
  EXPECT_NEAR(g.radius.value, 1.2599210498948732e-3, 1e-15);
  ASSERT_TRUE(g.aspect_ratio.has_value());
  EXPECT_DOUBLE_EQ(*g.aspect_ratio, 3.0);
  EXPECT_FALSE(g.length.has_value());
  // Same volume as the sphere of diameter d.
  EXPECT_NEAR(input::grain_measure(g, g.radius.value), std::numbers::pi * std::pow(0.004, 3) / 6,
              1e-20);
  // Both radius and equivalent_diameter: refused.
  const std::string msg = error_of(header_3d + R"(particles:
  - shape: spherocylinder
    radius: 0.001
    equivalent_diameter: 0.004
    aspect_ratio: 3
    material: glass
    positions: [[0.05, 0.05, 0.05]]
)");
  EXPECT_NE(msg.find("t.yaml:10:5: error: particles[0].equivalent_diameter: give only one of "
                     "radius, equivalent_diameter"),
            std::string::npos)
      << msg;
}

TEST(InputShapes, PolygonForms) {
  const auto c = input::load_case_text(header_2d + R"(particles:
  - shape: polygon
    polygon: {vertices: [[0, 0], [0.004, 0], [0.004, 0.002], [0, 0.002]]}
    material: glass
    positions: [[0.02, 0.02]]
  - shape: polygon
    radius: 0.002
    polygon: {regular: 6}
    material: glass
    positions: [[0.05, 0.05]]
  - shape: polygon
    radius: {distribution: uniform, min: 0.001, max: 0.002}
    polygon: {random: {vertices: [4, 9]}}
    material: glass
    fill: {box: {min: [0, 0.06], max: [0.1, 0.1]}, lattice: random, count: 10}
  - shape: polygon
    radius: 0.002
    polygon: {random: {vertices: [5, 5], elongation: [1.2, 2]}}
    material: glass
    positions: [[0.08, 0.02]]
  - shape: disk
    radius: 0.002
    material: glass
    positions: [[0.08, 0.04]]
)",
                                       "t.yaml");
  ASSERT_EQ(c.particles.size(), 5u);
  const auto& v = c.particles[0];
  EXPECT_EQ(v.kind, config::Shape::Polygon);
  EXPECT_EQ(v.polygon.kind, config::PolygonSpec::Kind::Vertices);
  ASSERT_EQ(v.polygon.vertices.size(), 4u);
  EXPECT_EQ(v.polygon.vertices[2], (Vec3{0.004, 0.002, 0}));
  // The radius is the equal-area radius of the vertices: pi R^2 = 8e-6 m^2.
  EXPECT_NEAR(v.radius.value, std::sqrt(8e-6 / std::numbers::pi), 1e-15);
  EXPECT_NEAR(input::grain_measure(v, v.radius.value), 8e-6, 1e-18);
  EXPECT_NEAR(input::bounding_radius(v, v.radius.value), std::sqrt(5e-6), 1e-15);  // half diagonal
  const auto& r = c.particles[1];
  EXPECT_EQ(r.polygon.kind, config::PolygonSpec::Kind::Regular);
  EXPECT_EQ(r.polygon.sides, 6);
  // Regular hexagon of area pi R^2: circumradius R sqrt(2 pi / (6 sin(pi/3))).
  EXPECT_NEAR(input::bounding_radius(r, 0.002),
              0.002 * std::sqrt(2 * std::numbers::pi / (6 * std::sin(std::numbers::pi / 3))),
              1e-15);
  EXPECT_NEAR(input::grain_measure(r, 0.002), std::numbers::pi * 4e-6, 1e-18);
  const auto& q = c.particles[2];
  EXPECT_EQ(q.polygon.kind, config::PolygonSpec::Kind::Random);
  EXPECT_EQ(q.polygon.min_vertices, 4);
  EXPECT_EQ(q.polygon.max_vertices, 9);
  EXPECT_EQ(q.polygon.min_elongation, 1.0);  // default [1, 1]
  EXPECT_EQ(q.polygon.max_elongation, 1.0);
  const auto& e = c.particles[3];
  EXPECT_EQ(e.polygon.min_elongation, 1.2);
  EXPECT_EQ(e.polygon.max_elongation, 2.0);
  EXPECT_EQ(c.particles[4].kind, config::Shape::Disk);
  EXPECT_NO_THROW(input::validate(c));
}

TEST(InputShapes, RandomPolygonReachCoversTheGenerator) {
  // The estimate must exceed the circumradius of polygons drawn with another seed.
  config::PolygonSpec p;
  p.kind = config::PolygonSpec::Kind::Random;
  p.min_vertices = 3;
  p.max_vertices = 6;
  p.min_elongation = 1.0;
  p.max_elongation = 2.0;
  const double factor = input::polygon_reach_factor(p);
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int> nv(3, 6);
  std::uniform_real_distribution<double> el(1.0, 2.0);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto poly = contact::random_convex_polygon(rng, nv(rng), 1.0, el(rng));
    for (int k = 0; k < poly.n; ++k) worst = std::max(worst, norm(poly.v[k]));
  }
  EXPECT_GT(factor, worst);
  EXPECT_LT(factor, 2 * worst);  // but not absurdly large
}

TEST(InputShapes, DefaultShapeIsTheRoundOne) {
  const auto c2 = input::load_case_text(
      header_2d + "particles:\n  - {radius: 0.002, material: glass, positions: [[0.05, 0.05]]}\n",
      "t.yaml");
  EXPECT_EQ(c2.particles[0].kind, config::Shape::Disk);
  EXPECT_EQ(c2.particles[0].shape, "disk");
  const auto c3 = input::load_case_text(minimal_case, "t.yaml");
  EXPECT_EQ(c3.particles[0].kind, config::Shape::Sphere);
  EXPECT_EQ(c3.particles[0].shape, "sphere");
}

// ---------------------------------------------------------------------------------------------
// 2D cases

TEST(Input2D, VectorsHaveTwoComponents) {
  const auto c = input::load_case_text(R"(dimension: 2
time: {step: 1.0e-5, end: 0.1}
domain: {min: [-0.1, 0], max: [0.1, 0.2], periodic: [true, false], thickness: 0.005}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - radius: 0.002
    material: glass
    positions: [[0, 0.1], [0.01, 0.1]]
    velocities: [[1, 2], [0, 0]]
    angular_velocities: [3, -4]
  - radius: 0.002
    material: glass
    fill: {box: {min: [-0.1, 0.12], max: [0.1, 0.2]}, velocity: [0, -1]}
walls:
  - {name: floor, plane: {point: [0, 0], normal: [0, 2]}, material: glass}
  - {name: box, box: {min: [-0.1, 0], max: [0.1, 0.2], open: [ymax]}, material: glass,
     motion: {translate: {velocity: [0.1, 0]}}}
  - {name: paddle, plane: {point: [0, 0.05], normal: [1, 0]}, material: glass,
     motion: {rotate: {center: [0, 0.05], rpm: 60}}}
  - {name: reverse, plane: {point: [0, 0.05], normal: [-1, 0]}, material: glass,
     motion: {rotate: {axis: [0, 0, -1], rate: 2}}}
output:
  series: {every: 1.0e-3, quantities: [kinetic_energy, wall_force.box.ymin]}
)",
                                       "t.yaml");
  EXPECT_EQ(c.dimension, 2);
  EXPECT_EQ(c.domain.min, (Vec3{-0.1, 0, 0}));
  EXPECT_EQ(c.domain.max, (Vec3{0.1, 0.2, 0}));
  EXPECT_EQ(c.domain.periodic, (std::array<bool, 3>{true, false, false}));
  EXPECT_DOUBLE_EQ(c.domain.thickness, 0.005);
  EXPECT_EQ(c.gravity, (Vec3{0, -9.81, 0}));  // the 2D default
  const auto& ex = *c.particles[0].explicit_particles;
  EXPECT_EQ(ex.positions[1], (Vec3{0.01, 0.1, 0}));
  EXPECT_EQ(ex.velocities[0], (Vec3{1, 2, 0}));
  EXPECT_EQ(ex.angular_velocities[1], (Vec3{0, 0, -4}));
  EXPECT_EQ(c.particles[1].fill->velocity, (Vec3{0, -1, 0}));
  EXPECT_EQ(c.particles[1].fill->region.max, (Vec3{0.1, 0.2, 0}));
  EXPECT_EQ(c.walls[0].normal, (Vec3{0, 1, 0}));
  EXPECT_EQ(c.walls[1].open, (std::vector<std::string>{"ymax", "zmin", "zmax"}));
  EXPECT_EQ(c.walls[1].motion.velocity, (Vec3{0.1, 0, 0}));
  EXPECT_TRUE(c.walls[2].motion.rotates);
  EXPECT_EQ(c.walls[2].motion.axis, (Vec3{0, 0, 1}));
  EXPECT_EQ(c.walls[2].motion.center, (Vec3{0, 0.05, 0}));
  EXPECT_NEAR(c.walls[2].motion.rate, 2 * std::numbers::pi, 1e-12);
  EXPECT_EQ(c.walls[3].motion.axis, (Vec3{0, 0, 1}));  // -z stored as +z at the opposite rate
  EXPECT_DOUBLE_EQ(c.walls[3].motion.rate, -2.0);
  const auto report = input::validate(c);
  EXPECT_EQ(derived(report, "particles[0]: grains"), "2");
  // 2D masses: rho pi r^2 thickness.
  EXPECT_NE(derived(report, "particles[0]: disk grains")
                .find(fmt::format("mass {:.4g} kg", 2500 * std::numbers::pi * 4e-6 * 0.005)),
            std::string::npos)
      << derived(report, "particles[0]: disk grains");
}

TEST(Input2D, ThicknessDefaultsAndChecksIgnoreZ) {
  // Overlapping disks are found in 2D; the z extent of zero trips no check.
  const auto c = input::load_case_text(
      header_2d +
          "particles:\n  - {radius: 0.002, material: glass, positions: [[0.05, 0.05], "
          "[0.0545, 0.05]]}\n",
      "t.yaml");
  EXPECT_DOUBLE_EQ(c.domain.thickness, 1.0);
  EXPECT_NO_THROW(input::validate(c));
  const std::string msg = error_of(header_2d +
                                   "particles:\n  - {radius: 0.002, material: glass, positions: "
                                   "[[0.05, 0.05], [0.053, 0.05]]}\n");
  EXPECT_NE(msg.find("overlaps particle 0"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[0.053, 0.05]"), std::string::npos) << msg;  // 2D coordinates
}

TEST(Input2D, CsvWithTwoDimensionalColumns) {
  TempDir dir;
  dir.write("grains.csv", "x,y,vx,vy,wz,angle,radius\n0.02,0.03,1,2,3,0.5,0.002\n");
  const auto c = input::load_case(dir.write("case.yaml", header_2d + R"(particles:
  - shape: polygon
    polygon: {regular: 5}
    material: glass
    file: grains.csv
)"));
  const auto& ex = *c.particles[0].explicit_particles;
  ASSERT_EQ(ex.positions.size(), 1u);
  EXPECT_EQ(ex.positions[0], (Vec3{0.02, 0.03, 0}));
  EXPECT_EQ(ex.velocities[0], (Vec3{1, 2, 0}));
  EXPECT_EQ(ex.angular_velocities[0], (Vec3{0, 0, 3}));
  ASSERT_EQ(ex.orientations.size(), 1u);
  expect_quat_near(ex.orientations[0], quat_from_axis_angle({0, 0, 1}, 0.5));
  EXPECT_EQ(ex.radii, (std::vector<double>{0.002}));
  // Orientation columns for disks are refused.
  dir.write("disks.csv", "x,y,angle\n0.02,0.03,0.5\n");
  const std::string msg = error_of(header_2d + R"(particles:
  - {radius: 0.002, material: glass, file: disks.csv}
)",
                                   (dir.path() / "case2.yaml").string());
  EXPECT_NE(msg.find("disks.csv:1:5: error: particles[0].file: column 'angle': orientations "
                     "apply to spherocylinder and polygon grains only"),
            std::string::npos)
      << msg;
}

// ---------------------------------------------------------------------------------------------
// Orientations and integrators

TEST(InputOrientation, FillAxisAngleAndRandom) {
  auto fill_with = [](const std::string& orientation) {
    return header_3d + R"(particles:
  - shape: spherocylinder
    radius: 0.001
    length: 0.002
    material: glass
    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}, )" +
           orientation + "}\n";
  };
  auto c = input::load_case_text(fill_with("orientation: {axis: [1, 1, 0]}"), "t.yaml");
  ASSERT_TRUE(c.particles[0].fill->orientation.has_value());
  const Quat q = *c.particles[0].fill->orientation;
  const Vec3 a = rotate(q, Vec3{0, 0, 1});
  EXPECT_NEAR(a.x, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(a.y, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(a.z, 0, 1e-15);
  EXPECT_NEAR(norm2(q), 1, 1e-15);
  // Antiparallel: a half turn.
  c = input::load_case_text(fill_with("orientation: {axis: [0, 0, -2]}"), "t.yaml");
  const Vec3 down = rotate(*c.particles[0].fill->orientation, Vec3{0, 0, 1});
  EXPECT_NEAR(down.z, -1, 1e-15);
  // Parallel: the identity.
  c = input::load_case_text(fill_with("orientation: {axis: [0, 0, 3]}"), "t.yaml");
  expect_quat_near(*c.particles[0].fill->orientation, Quat{});
  c = input::load_case_text(fill_with("orientation: random"), "t.yaml");
  EXPECT_FALSE(c.particles[0].fill->orientation.has_value());
  EXPECT_NE(error_of(fill_with("orientation: {angle: 1}")).find("unknown key 'angle'"),
            std::string::npos);
  EXPECT_NE(error_of(fill_with("orientation: aligned"))
                .find("expected random or {axis: [x, y, z]}, found 'aligned'"),
            std::string::npos)
      << error_of(fill_with("orientation: aligned"));

  const auto c2 = input::load_case_text(header_2d + R"(particles:
  - shape: polygon
    radius: 0.002
    polygon: {regular: 4}
    material: glass
    fill: {box: {min: [0, 0], max: [0.1, 0.1]}, orientation: {angle: 0.25}}
)",
                                        "t.yaml");
  expect_quat_near(*c2.particles[0].fill->orientation,
                   Quat{std::cos(0.125), 0, 0, std::sin(0.125)});
}

TEST(InputOrientation, ExplicitAxesAnglesAndCsvQuaternions) {
  const auto c = input::load_case_text(header_3d + R"(particles:
  - shape: spherocylinder
    radius: 0.001
    aspect_ratio: 2
    material: glass
    positions: [[0.02, 0.05, 0.05], [0.08, 0.05, 0.05]]
    axes: [[1, 0, 0], [0, 0, -1]]
)",
                                       "t.yaml");
  const auto& ex = *c.particles[0].explicit_particles;
  ASSERT_EQ(ex.orientations.size(), 2u);
  const Vec3 a0 = rotate(ex.orientations[0], Vec3{0, 0, 1});
  EXPECT_NEAR(a0.x, 1, 1e-15);
  EXPECT_NEAR(rotate(ex.orientations[1], Vec3{0, 0, 1}).z, -1, 1e-15);

  const auto c2 = input::load_case_text(header_2d + R"(particles:
  - shape: polygon
    polygon: {vertices: [[0, 0], [0.002, 0], [0, 0.002]]}
    material: glass
    positions: [[0.02, 0.05], [0.08, 0.05]]
    angles: [0, 1.5]
)",
                                        "t.yaml");
  expect_quat_near(c2.particles[0].explicit_particles->orientations[1],
                   quat_from_axis_angle({0, 0, 1}, 1.5));

  TempDir dir;
  dir.write("rods.csv", "x,y,z,qw,qx,qy,qz\n0.05,0.05,0.05,2,0,0,0\n0.02,0.02,0.02,1,1,0,0\n");
  const auto c3 = input::load_case(dir.write("case.yaml", header_3d + R"(particles:
  - shape: spherocylinder
    radius: 0.001
    length: 0.002
    material: glass
    file: rods.csv
)"));
  const auto& o = c3.particles[0].explicit_particles->orientations;
  ASSERT_EQ(o.size(), 2u);
  expect_quat_near(o[0], Quat{});  // normalised
  expect_quat_near(o[1], Quat{std::sqrt(0.5), std::sqrt(0.5), 0, 0});
  EXPECT_NO_THROW(input::validate(c3));
}

TEST(InputIntegrator, Gear5IsAccepted) {
  std::string text = minimal_case + "integrator: gear5\n";
  EXPECT_EQ(input::load_case_text(text, "t.yaml").integrator, "gear5");
  EXPECT_EQ(input::load_case_text(minimal_case, "t.yaml").integrator, "velocity_verlet");
}

// ---------------------------------------------------------------------------------------------
// Validation of shapes

TEST(InputValidate, ParallelRodsCloseTogetherDoNotOverlap) {
  // Bounding spheres (r + L/2 = 6 mm) overlap heavily; the rods themselves are 0.1 mm apart.
  const std::string text = header_3d + R"(particles:
  - shape: spherocylinder
    radius: 0.001
    length: 0.01
    material: glass
    positions: [[0.05, 0.05, 0.05], [0.0521, 0.05, 0.05], [0.05, 0.05, 0.0621]]
    axes: [[0, 0, 1], [0, 0, 1], [0, 0, 1]]
)";
  EXPECT_EQ(error_of(text), "");
  // End to end along the axis, 0.1 mm apart: fine too; 0.1 mm closer: overlap.
  std::string closer = text;
  closer.replace(closer.find("0.0621"), 6, "0.0619");
  EXPECT_NE(error_of(closer).find("particles[0].positions[2]: particle 2"), std::string::npos)
      << error_of(closer);
}

TEST(InputValidate, ContactTimeUsesTheShapeMass) {
  // A rod of cap radius r is heavier than a sphere of radius r: longer Hertz contact time, same
  // Rayleigh time (the cap radius).
  auto report_for = [](const std::string& group) {
    return input::validate(input::load_case_text(header_3d + "particles:\n" + group +
                                                     "    material: glass\n"
                                                     "    positions: [[0.05, 0.05, 0.05]]\n",
                                                 "t.yaml"));
  };
  const auto sphere = report_for("  - radius: 0.002\n");
  const auto rod = report_for("  - shape: spherocylinder\n    radius: 0.002\n    length: 0.02\n");
  const double t_sphere = leading_number(derived(sphere, "contact time, glass-glass"));
  const double t_rod = leading_number(derived(rod, "contact time, glass-glass"));
  // Hertz: t ~ m_eff^(2/5) at the same radius and speed; mass ratio (pi r^2 L + 4/3 pi r^3) /
  // (4/3 pi r^3) = 1 + 3 L / (4 r) = 8.5.
  EXPECT_NEAR(t_rod / t_sphere, std::pow(8.5, 0.4), 1e-3 * std::pow(8.5, 0.4));
  EXPECT_EQ(derived(sphere, "Rayleigh time, glass"), derived(rod, "Rayleigh time, glass"));
  EXPECT_NE(derived(rod, "particles[0]: spherocylinder grains"), "");
}

TEST(InputValidate, PolygonMassAndRayleighRadius) {
  // A square of side 4 mm: area 1.6e-5 m^2, equal-area radius sqrt(A/pi).
  const auto c = input::load_case_text(R"(dimension: 2
time: {step: 1.0e-5, end: 0.1}
domain: {min: [0, 0], max: [0.1, 0.1], thickness: 0.01}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - shape: polygon
    polygon: {vertices: [[0, 0], [0.004, 0], [0.004, 0.004], [0, 0.004]]}
    material: glass
    positions: [[0.05, 0.05]]
)",
                                       "t.yaml");
  const auto report = input::validate(c);
  const double r_eq = std::sqrt(1.6e-5 / std::numbers::pi);
  EXPECT_NE(derived(report, "particles[0]: polygon grains")
                .find(fmt::format("mass {:.4g} kg", 2500 * 1.6e-5 * 0.01)),
            std::string::npos)
      << derived(report, "particles[0]: polygon grains");
  EXPECT_NE(derived(report, "Rayleigh time, glass (r = " + input::number_text(r_eq)), "");
}

// ---------------------------------------------------------------------------------------------
// Echo of shapes and 2D cases

TEST(InputEcho, SpherocylinderCaseRoundTrip) {
  const auto c = input::load_case_text(header_3d + R"(particles:
  - shape: spherocylinder
    equivalent_diameter: 0.004
    aspect_ratio: 3
    material: glass
    fill: {box: {min: [0, 0, 0.05], max: [0.1, 0.1, 0.1]}, orientation: {axis: [1, 2, 3]}}
  - shape: spherocylinder
    radius: 0.001
    length: 0.006
    material: glass
    positions: [[0.02, 0.02, 0.02], [0.08, 0.02, 0.02]]
    axes: [[0, 1, 0], [0, 0, -1]]
    angular_velocities: [[0, 0, 1], [1, 0, 0]]
  - shape: spherocylinder
    radius: 0.001
    length: 0.002
    material: glass
    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.01]}}
)",
                                       "t.yaml");
  input::validate(c);
  const std::string text = input::echo_yaml(c, "1");
  TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", text));
  ASSERT_EQ(again.particles.size(), 3u);
  const auto& g0 = again.particles[0];
  EXPECT_EQ(g0.kind, config::Shape::Spherocylinder);
  EXPECT_EQ(g0.radius.value, c.particles[0].radius.value);
  EXPECT_EQ(g0.aspect_ratio, c.particles[0].aspect_ratio);
  EXPECT_FALSE(g0.length.has_value());
  expect_quat_near(*g0.fill->orientation, *c.particles[0].fill->orientation);
  // An oriented spherocylinder on a cubic lattice without spacing is spaced by its own extent
  // along each axis (no single number): the echo leaves spacing out, and so the run again.
  EXPECT_EQ(g0.fill->spacing, c.particles[0].fill->spacing);
  EXPECT_FALSE(g0.fill->spacing.has_value());
  const auto& g1 = again.particles[1];
  EXPECT_EQ(g1.length, c.particles[1].length);
  EXPECT_FALSE(g1.aspect_ratio.has_value());
  const auto& ex = *g1.explicit_particles;
  ASSERT_EQ(ex.orientations.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i)
    expect_quat_near(ex.orientations[i], c.particles[1].explicit_particles->orientations[i]);
  EXPECT_EQ(ex.angular_velocities, c.particles[1].explicit_particles->angular_velocities);
  EXPECT_FALSE(again.particles[2].fill->orientation.has_value());
  EXPECT_NE(text.find("orientation: random"), std::string::npos) << text;
  EXPECT_NO_THROW(input::validate(again));
}

TEST(InputEcho, TwoDimensionalPolygonCaseRoundTrip) {
  const auto c = input::load_case_text(R"(dimension: 2
time: {step: 1.0e-5, end: 0.1}
domain: {min: [0, 0], max: [0.1, 0.1], periodic: [true, false], thickness: 0.02}
gravity: [0.5, -9]
integrator: gear5
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - shape: polygon
    polygon: {vertices: [[0, 0], [0.004, 0], [0.003, 0.003], [0, 0.002]]}
    material: glass
    positions: [[0.02, 0.02], [0.04, 0.02]]
    velocities: [[1, 0], [0, 1]]
    angular_velocities: [2, -3]
    angles: [0.5, -1]
  - shape: polygon
    radius: 0.002
    polygon: {regular: 7}
    material: glass
    fill: {box: {min: [0, 0.05], max: [0.1, 0.07]}, lattice: hcp, orientation: {angle: 0.3},
           velocity: [0, -1]}
  - shape: polygon
    radius: {distribution: uniform, min: 0.001, max: 0.0015}
    polygon: {random: {vertices: [4, 7], elongation: [1, 1.5]}}
    material: glass
    fill: {box: {min: [0, 0.08], max: [0.1, 0.1]}, lattice: random, count: 20}
  - shape: disk
    radius: 0.002
    material: glass
    positions: [[0.07, 0.02]]
walls:
  - {name: floor, plane: {point: [0, 0], normal: [0, 1]}, material: glass}
  - {name: box, box: {min: [0, 0], max: [0.1, 0.1], open: [ymax]}, material: glass}
  - {name: paddle, plane: {point: [0.05, 0.03], normal: [1, 0]}, material: glass,
     motion: {rotate: {center: [0.05, 0.03], rpm: 10}, translate: {velocity: [0.1, 0]}}}
)",
                                       "t.yaml");
  input::validate(c);
  const std::string text = input::echo_yaml(c, "1");
  EXPECT_NE(text.find("thickness: 0.02"), std::string::npos) << text;
  EXPECT_NE(text.find("gravity: [0.5, -9]"), std::string::npos) << text;
  EXPECT_NE(text.find("open: [ymax]"), std::string::npos) << text;
  TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", text));
  EXPECT_EQ(again.dimension, 2);
  EXPECT_EQ(again.integrator, "gear5");
  EXPECT_EQ(again.domain.min, c.domain.min);
  EXPECT_EQ(again.domain.periodic, c.domain.periodic);
  EXPECT_EQ(again.domain.thickness, c.domain.thickness);
  EXPECT_EQ(again.gravity, c.gravity);
  ASSERT_EQ(again.particles.size(), 4u);
  const auto& v = again.particles[0];
  EXPECT_EQ(v.polygon.kind, config::PolygonSpec::Kind::Vertices);
  EXPECT_EQ(v.polygon.vertices, c.particles[0].polygon.vertices);
  EXPECT_EQ(v.radius.value, c.particles[0].radius.value);
  const auto& ex = *v.explicit_particles;
  EXPECT_EQ(ex.positions, c.particles[0].explicit_particles->positions);
  EXPECT_EQ(ex.velocities, c.particles[0].explicit_particles->velocities);
  EXPECT_EQ(ex.angular_velocities, c.particles[0].explicit_particles->angular_velocities);
  ASSERT_EQ(ex.orientations.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i)
    expect_quat_near(ex.orientations[i], c.particles[0].explicit_particles->orientations[i]);
  const auto& r = again.particles[1];
  EXPECT_EQ(r.polygon.sides, 7);
  EXPECT_EQ(r.fill->lattice, config::Fill::Lattice::Hcp);
  expect_quat_near(*r.fill->orientation, *c.particles[1].fill->orientation);
  EXPECT_EQ(r.fill->velocity, c.particles[1].fill->velocity);
  const auto& q = again.particles[2];
  EXPECT_EQ(q.polygon.kind, config::PolygonSpec::Kind::Random);
  EXPECT_EQ(q.polygon.min_vertices, 4);
  EXPECT_EQ(q.polygon.max_vertices, 7);
  EXPECT_EQ(q.polygon.max_elongation, 1.5);
  EXPECT_EQ(q.radius.max, 0.0015);
  EXPECT_EQ(again.particles[3].kind, config::Shape::Disk);
  ASSERT_EQ(again.walls.size(), 3u);
  EXPECT_EQ(again.walls[1].open, c.walls[1].open);
  EXPECT_EQ(again.walls[2].motion.rate, c.walls[2].motion.rate);
  EXPECT_EQ(again.walls[2].motion.center, c.walls[2].motion.center);
  EXPECT_EQ(again.walls[2].motion.velocity, c.walls[2].motion.velocity);
  EXPECT_NO_THROW(input::validate(again));
}

// Shear, analysis and sweep blocks

namespace {

/// A 3D case with a shear block `shear` (periodic flags `per`) and optional extra text.
std::string shear_case(const std::string& per, const std::string& shear,
                       const std::string& extra = "") {
  return R"(time: {step: 1.0e-5, end: 0.1}
domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1], periodic: )" +
         per + R"(}
gravity: [0, 0, 0]
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - shape: sphere
    radius: 0.004
    material: glass
    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}, volume_fraction: 0.1}
)" + shear +
         extra;
}

}  // namespace

// Spheres between shear walls without rolling resistance can roll along them (the walls then
// lose the shear: docs/models/rheology.md): `check` warns, naming the pair; with rolling
// resistance, or between Lees-Edwards images, it does not.
TEST(InputShear, WarnsOfSpheresRollingAlongTheWalls) {
  const std::string walls = "shear: {rate: 10, boundary: walls, wall_material: glass}\n";
  auto rolling_warnings = [](const config::Case& c) {
    int n = 0;
    for (const auto& w : input::validate(c).warnings)
      n += w.find("no rolling resistance") != std::string::npos &&
           w.find("[glass, glass]") != std::string::npos;
    return n;
  };
  EXPECT_EQ(rolling_warnings(input::load_case_text(shear_case("[true, true, false]", walls), "t")),
            1);
  TempDir dir;
  const auto rough =
      input::load_case(dir.write("case.yaml", shear_case("[true, true, false]", walls)),
                       {{"contacts[0].rolling_friction", "0.5"}});
  EXPECT_EQ(rolling_warnings(rough), 0);
  const std::string le = "shear: {rate: 10, boundary: lees_edwards}\n";
  EXPECT_EQ(rolling_warnings(input::load_case_text(shear_case("[true, true, true]", le), "t")), 0);
}

TEST(InputShear, ErrorsNameTheKeyAndWhatIsExpected) {
  const std::string le = "shear: {rate: 10, boundary: lees_edwards}\n";
  // Lees-Edwards needs periodic z; walls need z not periodic and a wall material.
  EXPECT_NE(error_of(shear_case("[true, true, false]", le))
                .find("shear: Lees-Edwards shear "
                      "needs domain.periodic: [true, "
                      "true, true]"),
            std::string::npos);
  EXPECT_NE(error_of(shear_case("[true, true, true]", "shear: {rate: 10}\n"))
                .find("needs domain.periodic: [true, true, false]"),
            std::string::npos);
  EXPECT_NE(error_of(shear_case("[true, true, false]", "shear: {rate: 10}\n"))
                .find("missing required key 'wall_material'"),
            std::string::npos)
      << error_of(shear_case("[true, true, false]", "shear: {rate: 10}\n"));
  EXPECT_NE(error_of(shear_case("[true, true, true]",
                                "shear: {rate: -1, boundary: "
                                "lees_edwards}\n"))
                .find("shear.rate: expected a number > 0, found '-1'"),
            std::string::npos);
  // time.end and shear.strain exclude each other.
  EXPECT_NE(error_of(shear_case("[true, true, true]",
                                "shear: {rate: 10, boundary: lees_edwards, strain: 2}\n"))
                .find("give either time.end or shear.strain"),
            std::string::npos);
  // every_strain needs a shear block; count and volume_fraction exclude each other.
  EXPECT_NE(
      error_of(shear_case("[true, true, true]", "", "analysis: {rheology: {every_strain: 0.1}}\n"))
          .find("'every_strain' needs a shear: block"),
      std::string::npos);
  EXPECT_NE(error_of(shear_case("[true, true, true]", le, "analysis: {rheology: {every: 1}}\n"))
                .find("an interval that gives at least 2 samples"),
            std::string::npos);
  EXPECT_NE(error_of(shear_case("[true, true, true]", le, "sweep: {shear_rate: []}\n"))
                .find("sweep.shear_rate: expected a list of at least 1 item"),
            std::string::npos);
  EXPECT_NE(error_of(shear_case("[true, true, true]", "", "sweep: {shear_rate: [1, 2]}\n"))
                .find("the case needs a shear: block"),
            std::string::npos);
  // A valid Lees-Edwards case loads, with the count from the volume fraction.
  const auto c = input::load_case_text(
      shear_case("[true, true, true]", le, "analysis: {rheology: {every: 0.01, bins: 8}}\n"),
      "t.yaml");
  EXPECT_EQ(input::volume_fraction_count(*c.particles[0].fill, c.particles[0], 3),
            std::llround(0.1 * 1e-3 / (4.0 / 3.0 * M_PI * 0.004 * 0.004 * 0.004)));
  EXPECT_EQ(c.analysis.rheology->bins, 8);
}

TEST(InputShear, WallsAreGeneratedAndEchoRoundTrips) {
  const auto c = input::load_case_text(
      shear_case("[true, true, false]", "shear: {rate: 20, wall_material: glass}\n"), "t.yaml");
  ASSERT_EQ(c.walls.size(), 2u);
  EXPECT_EQ(c.walls[1].name, "shear_top");
  EXPECT_DOUBLE_EQ(c.walls[1].motion.velocity.x, 0.5 * 20 * 0.1);
  EXPECT_DOUBLE_EQ(c.walls[0].motion.velocity.x, -0.5 * 20 * 0.1);
  TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", input::echo_yaml(c, "1")));
  ASSERT_EQ(again.walls.size(), 2u);  // made again by the shear block, not echoed twice
  EXPECT_EQ(again.shear->rate, 20);
  EXPECT_EQ(*again.particles[0].fill->volume_fraction, 0.1);
}

TEST(InputShear, OutputIntervalsInStrain) {
  // In a shear case the output intervals may be given in strain: one case then writes as many
  // frames, rows and checkpoints per unit strain at every shear rate of a sweep.
  const std::string le = "shear: {rate: 20, boundary: lees_edwards}\n";
  const std::string out =
      "output:\n  vtk: {every_strain: 0.5}\n  particles_csv: {every: 0.01}\n"
      "  contacts_csv: {every_strain: 0.25}\n"
      "  contacts_vtk: {every_strain: 0.5}\n"
      "  series: {every_strain: 0.01, quantities: [kinetic_energy]}\n"
      "  checkpoint: {every_strain: 1}\n";
  const auto c = input::load_case_text(shear_case("[true, true, true]", le, out), "t.yaml");
  EXPECT_DOUBLE_EQ(c.output.vtk.every, 0.5 / 20);
  EXPECT_DOUBLE_EQ(c.output.series.every, 0.01 / 20);
  EXPECT_DOUBLE_EQ(c.output.checkpoint.every, 1.0 / 20);
  EXPECT_EQ(c.output.particles_csv.every, 0.01);
  EXPECT_FALSE(c.output.particles_csv.every_strain);
  EXPECT_DOUBLE_EQ(c.output.contacts_csv.every, 0.25 / 20);
  EXPECT_DOUBLE_EQ(c.output.contacts_vtk.every, 0.5 / 20);
  // A sweep's --set shear.rate=... rescales them (the strain is what the case says).
  TempDir dir;
  const auto slow = input::load_case(
      dir.write("case.yaml", shear_case("[true, true, true]", le, out)), {{"shear.rate", "0.5"}});
  EXPECT_DOUBLE_EQ(slow.output.vtk.every, 0.5 / 0.5);
  EXPECT_DOUBLE_EQ(slow.output.series.every, 0.01 / 0.5);
  // The smallest strain the message names is accepted (no round-off below one step).
  EXPECT_NO_THROW(input::load_case(
      dir / "case.yaml", {{"output.series.every_strain", "2.0e-4"}, {"shear.rate", "20"}}));
  // `check` says how many outputs the run writes (t = 0 included, checkpoints not) and warns
  // about tens of thousands of files.
  EXPECT_EQ(derived(input::validate(c), "outputs over the run"),
            "vtk 5, particles_csv 11, contacts_csv 9, contacts_vtk 5, series 201, checkpoint 2");
  EXPECT_TRUE(input::validate(c).warnings.empty());
  const auto many = input::validate(input::load_case(
      dir / "case.yaml", {{"time.end", "1"}, {"output.vtk.every_strain", "2.0e-4"}}));
  ASSERT_EQ(many.warnings.size(), 1u);
  EXPECT_NE(many.warnings[0].find("output.vtk writes 100001 times over the run"), std::string::npos)
      << many.warnings[0];
  // The echo keeps the strain, so that a resolved case read again has the same intervals.
  const auto again = input::load_case(dir.write("echo.yaml", input::echo_yaml(c, "1")));
  EXPECT_EQ(*again.output.vtk.every_strain, 0.5);
  EXPECT_DOUBLE_EQ(again.output.vtk.every, c.output.vtk.every);
  EXPECT_DOUBLE_EQ(again.output.series.every, c.output.series.every);
  EXPECT_DOUBLE_EQ(again.output.checkpoint.every, c.output.checkpoint.every);
  EXPECT_EQ(again.output.particles_csv.every, 0.01);
  EXPECT_EQ(*again.output.contacts_csv.every_strain, 0.25);
  EXPECT_EQ(*again.output.contacts_vtk.every_strain, 0.5);
  // Errors: no shear block; both keys; an interval below one time step.
  EXPECT_NE(error_of(shear_case("[true, true, true]", "", "output: {vtk: {every_strain: 0.5}}\n"))
                .find("output.vtk.every_strain: 'every_strain' needs a shear: block"),
            std::string::npos)
      << error_of(shear_case("[true, true, true]", "", "output: {vtk: {every_strain: 0.5}}\n"));
  EXPECT_NE(error_of(shear_case("[true, true, true]", le,
                                "output: {checkpoint: {every: 1, every_strain: 0.5}}\n"))
                .find("give only one of every, every_strain"),
            std::string::npos);
  const std::string tiny = error_of(shear_case("[true, true, true]", le,
                                               "output: {series: {every_strain: 1.0e-5, "
                                               "quantities: [kinetic_energy]}}\n"));
  EXPECT_NE(tiny.find("output.series.every_strain: expected 0 (off) or an interval >= time.step "
                      "(1e-05 s): a strain >= 0.0002 at shear.rate 20"),
            std::string::npos)
      << tiny;
}

TEST(InputShear, CommandLineOverrides) {
  TempDir dir;
  const auto file = dir.write(
      "c.yaml", shear_case("[true, true, true]", "shear: {rate: 10, boundary: lees_edwards}\n"));
  const auto c = input::load_case(file, {input::parse_override("shear.rate=250"),
                                         input::parse_override("particles[0].fill.seed=9"),
                                         input::parse_override("neighbor.skin=0.001")});
  EXPECT_EQ(c.shear->rate, 250);
  EXPECT_EQ(c.particles[0].fill->seed, 9u);
  EXPECT_EQ(*c.neighbor.skin, 0.001);
  EXPECT_THROW(input::parse_override("shear.rate"), InputError);
  EXPECT_THROW(input::load_case(file, {input::parse_override("particles[3].radius=1")}),
               InputError);
  // A key given instead of its alternative replaces it: every for every_strain (and back),
  // count for volume_fraction.
  const auto strained = dir.write(
      "s.yaml", shear_case("[true, true, true]", "shear: {rate: 10, boundary: lees_edwards}\n",
                           "output: {vtk: {every_strain: 0.5}}\n"));
  const auto off = input::load_case(strained, {input::parse_override("output.vtk.every=0")});
  EXPECT_EQ(off.output.vtk.every, 0.0);
  EXPECT_FALSE(off.output.vtk.every_strain);
  const auto seconds = input::load_case(file, {input::parse_override("output.vtk.every=0.01"),
                                               input::parse_override("output.vtk.every_strain=1")});
  EXPECT_DOUBLE_EQ(seconds.output.vtk.every, 0.1);
  const auto counted = input::load_case(file, {input::parse_override("particles[0].fill.count=7")});
  EXPECT_FALSE(counted.particles[0].fill->volume_fraction);
  EXPECT_EQ(*counted.particles[0].fill->count, 7);
}

// ---------------------------------------------------------------------------------------------
// CFD-DEM: the fluid: and coupling: blocks

namespace {

/// minimal_case (header lines 1-9) made periodic along x and y, plus `blocks`.
std::string cfd_case(const std::string& blocks) {
  std::string text = minimal_case;
  const std::string box = "max: [0.1, 0.1, 0.1]}";
  text.replace(text.find(box), box.size(), "max: [0.1, 0.1, 0.1], periodic: [true, true, false]}");
  return text + blocks;
}

const std::string good_fluid = R"(fluid:
  density: 1000
  viscosity: 1.0e-3
  cells: [4, 4, 8]
  boundary: {zmin: {velocity_inlet: [0, 0, 0.01]}, zmax: {pressure_outlet: 0}}
coupling: {drag: gidaspow}
)";

/// The CFD-DEM case of good_fluid with more keys in its coupling map, e.g. "interval: 0".
std::string case_with_coupling(const std::string& extra) {
  std::string blocks = good_fluid;
  const std::string plain = "{drag: gidaspow}";
  blocks.replace(blocks.find(plain), plain.size(), "{drag: gidaspow, " + extra + "}");
  return cfd_case(blocks);
}

}  // namespace

TEST(InputCfdDem, BlocksParseWithDefaultsAndEchoBack) {
  const auto c = input::load_case_text(cfd_case(good_fluid), "t.yaml");
  ASSERT_TRUE(c.fluid && c.coupling);
  EXPECT_EQ(c.fluid->density, 1000);
  EXPECT_EQ(c.fluid->viscosity, 1e-3);
  EXPECT_EQ(c.fluid->cells, (std::array<int, 3>{4, 4, 8}));
  using K = config::FluidBoundary::Kind;
  // Faces not given: periodic on the periodic axes x and y.
  EXPECT_EQ(c.fluid->boundary[0].kind, K::Periodic);
  EXPECT_EQ(c.fluid->boundary[3].kind, K::Periodic);
  EXPECT_EQ(c.fluid->boundary[4].kind, K::VelocityInlet);
  EXPECT_EQ(c.fluid->boundary[4].velocity, (Vec3{0, 0, 0.01}));
  EXPECT_EQ(c.fluid->boundary[5].kind, K::PressureOutlet);
  EXPECT_EQ(c.fluid->convection, "van_leer");
  EXPECT_EQ(c.coupling->drag, "gidaspow");
  EXPECT_EQ(c.coupling->fluid_fraction, "divided");
  EXPECT_EQ(c.coupling->interval, 100);
  EXPECT_EQ(c.coupling->min_fraction, 0.3);
  EXPECT_EQ(c.coupling->fluid_fraction_rate, "flux");
  EXPECT_EQ(c.coupling->rate_relaxation, 0.3);
  EXPECT_TRUE(c.coupling->pressure_gradient_force);
  EXPECT_EQ(c.coupling->interpolation, "trilinear");
  const auto report = input::validate(c);
  // Smallest cell 0.1 m / 8 along z over the grain diameter 0.01 m.
  EXPECT_NEAR(leading_number(derived(report, "cell size / particle diameter")), 1.25, 1e-9);
  EXPECT_FALSE(derived(report, "particle Reynolds number").empty());
  EXPECT_NEAR(leading_number(derived(report, "fluid time step")), 1e-3, 1e-15);
  // 1.25 < 3: warned.
  bool warned = false;
  for (const auto& w : report.warnings)
    warned |= w.find("particle diameters wide") != std::string::npos;
  EXPECT_TRUE(warned);

  TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", input::echo_yaml(c, "9.9.9")));
  ASSERT_TRUE(again.fluid && again.coupling);
  EXPECT_EQ(again.fluid->cells, c.fluid->cells);
  for (int f = 0; f < 6; ++f) {
    EXPECT_EQ(again.fluid->boundary[f].kind, c.fluid->boundary[f].kind) << f;
    EXPECT_EQ(again.fluid->boundary[f].velocity, c.fluid->boundary[f].velocity) << f;
  }
  EXPECT_EQ(again.coupling->drag, c.coupling->drag);
  EXPECT_EQ(again.coupling->interval, c.coupling->interval);
  EXPECT_EQ(again.coupling->min_fraction, c.coupling->min_fraction);
  EXPECT_EQ(again.coupling->fluid_fraction_rate, c.coupling->fluid_fraction_rate);
  EXPECT_EQ(again.coupling->rate_relaxation, c.coupling->rate_relaxation);
  EXPECT_EQ(again.coupling->pressure_gradient_force, c.coupling->pressure_gradient_force);

  // Drag only (the pressure-gradient force off), and echoed as such.
  const auto off =
      input::load_case_text(case_with_coupling("pressure_gradient_force: false"), "t.yaml");
  ASSERT_TRUE(off.coupling);
  EXPECT_FALSE(off.coupling->pressure_gradient_force);
  const auto off_again = input::load_case(dir.write("echo_off.yaml", input::echo_yaml(off, "9")));
  EXPECT_FALSE(off_again.coupling->pressure_gradient_force);
  EXPECT_EQ(off_again.coupling->interpolation, "trilinear");

  // Each convection scheme parses and echoes back; an unknown one is refused.
  for (const char* scheme : {"central", "upwind"}) {
    std::string text = cfd_case(good_fluid);
    const std::string cells = "  cells: [4, 4, 8]\n";
    text.replace(text.find(cells), cells.size(), cells + "  convection: " + scheme + "\n");
    const auto cv = input::load_case_text(text, "t.yaml");
    EXPECT_EQ(cv.fluid->convection, scheme);
    const auto cv_again = input::load_case(
        dir.write(std::string("echo_") + scheme + ".yaml", input::echo_yaml(cv, "9")));
    EXPECT_EQ(cv_again.fluid->convection, scheme);
    text.replace(text.find(scheme), std::string(scheme).size(), "quick");
    EXPECT_THROW(input::load_case_text(text, "t.yaml"), InputError);
  }

  // Cell-value reads (CFDEMcoupling's default), echoed as such.
  const auto cell = input::load_case_text(case_with_coupling("interpolation: cell"), "t.yaml");
  ASSERT_TRUE(cell.coupling);
  EXPECT_EQ(cell.coupling->interpolation, "cell");
  const auto cell_again =
      input::load_case(dir.write("echo_cell.yaml", input::echo_yaml(cell, "9")));
  EXPECT_EQ(cell_again.coupling->interpolation, "cell");
}

// The drag law as a block with its parameters (the two-fluid block's form), echoed with every
// parameter at its value; a bare key gets the defaults; wrong parameters are located errors.
TEST(InputCfdDem, DragBlockCarriesTheLawsParameters) {
  auto with_drag = [](const std::string& drag) {
    std::string blocks = good_fluid;
    blocks.replace(blocks.find("gidaspow"), 8, drag);
    return cfd_case(blocks);
  };
  const auto c =
      input::load_case_text(with_drag("{model: gidaspow, switch_fraction: 0.6}"), "t.yaml");
  ASSERT_TRUE(c.coupling);
  EXPECT_EQ(c.coupling->drag, "gidaspow");
  EXPECT_EQ(c.coupling->drag_params.at("switch_fraction"), 0.6);
  const std::string echo = input::echo_yaml(c, "9");
  EXPECT_NE(echo.find("drag: {model: gidaspow, switch_fraction: 0.6}"), std::string::npos) << echo;
  TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", echo));
  EXPECT_EQ(again.coupling->drag_params, c.coupling->drag_params);
  // A bare key: no parameters given, the default echoed.
  const auto bare = input::load_case_text(cfd_case(good_fluid), "t.yaml");
  EXPECT_TRUE(bare.coupling->drag_params.empty());
  EXPECT_NE(input::echo_yaml(bare, "9").find("drag: {model: gidaspow, switch_fraction: 0.8}"),
            std::string::npos);
  struct Bad {
    std::string drag, expect;
  };
  for (const auto& b :
       std::vector<Bad>{{"{model: gidaspow, switch_fraction: 1.5}", "switch_fraction"},
                        {"{model: gidaspow, switch: 0.6}", "switch"},
                        {"{model: wen_yu, switch_fraction: 0.6}", "switch_fraction"},
                        {"{model: gidaspw}", "did you mean 'gidaspow'"},
                        {"{switch_fraction: 0.6}", "model"}}) {
    const std::string message = error_of(with_drag(b.drag));
    EXPECT_NE(message.find("t.yaml:16:"), std::string::npos) << b.drag << ": " << message;
    EXPECT_NE(message.find(b.expect), std::string::npos) << b.drag << ": " << message;
  }
}

TEST(InputCfdDem, UnknownDragLawListsTheKeys) {
  std::string blocks = good_fluid;
  blocks.replace(blocks.find("gidaspow"), 8, "gidaspw");
  const std::string message = error_of(cfd_case(blocks));
  // The coupling line is line 16 of the case (10 lines of minimal_case + 5 of fluid).
  EXPECT_NE(message.find("t.yaml:16:"), std::string::npos) << message;
  EXPECT_NE(message.find("coupling.drag"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'gidaspow'"), std::string::npos) << message;
  EXPECT_NE(message.find("schiller_naumann, di_felice"), std::string::npos) << message;
}

TEST(InputCfdDem, PeriodicFacesMustMatchTheDomain) {
  std::string blocks = good_fluid;
  blocks.replace(blocks.find("zmax: {pressure_outlet: 0}"), 26, "zmax: periodic");
  std::string message = error_of(cfd_case(blocks));
  EXPECT_NE(message.find("t.yaml:15:"), std::string::npos) << message;
  EXPECT_NE(message.find("fluid.boundary.zmax"), std::string::npos) << message;
  EXPECT_NE(message.find("not periodic along z"), std::string::npos) << message;

  blocks = good_fluid;
  blocks.replace(blocks.find("{zmin:"), 6, "{xmin: no_slip, zmin:");
  message = error_of(cfd_case(blocks));
  EXPECT_NE(message.find("fluid.boundary.xmin"), std::string::npos) << message;
  EXPECT_NE(message.find("must be periodic too"), std::string::npos) << message;
}

// The two-fluid block's spelling of the faces (x_min ... z_max) names the same faces in
// fluid.boundary and in a box's `open` list; one face under both spellings is refused at the
// later key.
TEST(InputCfdDem, FaceKeysTakeEitherSpelling) {
  std::string blocks = good_fluid;
  blocks.replace(blocks.find("{zmin:"), 6, "{z_min:");
  const auto c = input::load_case_text(cfd_case(blocks), "t.yaml");
  using K = config::FluidBoundary::Kind;
  EXPECT_EQ(c.fluid->boundary[4].kind, K::VelocityInlet);
  EXPECT_EQ(c.fluid->boundary[4].velocity, (Vec3{0, 0, 0.01}));
  EXPECT_EQ(c.fluid->boundary[5].kind, K::PressureOutlet);
  // The echo writes the block's own spelling back.
  EXPECT_NE(input::echo_yaml(c, "test").find("zmin:"), std::string::npos);

  blocks = good_fluid;
  blocks.replace(blocks.find("{zmin:"), 6, "{z_min: no_slip, zmin:");
  const std::string message = error_of(cfd_case(blocks));
  EXPECT_NE(message.find("t.yaml:15:"), std::string::npos) << message;
  EXPECT_NE(message.find("give only one of zmin, z_min"), std::string::npos) << message;
  blocks = good_fluid;
  blocks.replace(blocks.find("{zmin:"), 6, "{z_low:");
  EXPECT_NE(error_of(cfd_case(blocks)).find("z_low"), std::string::npos);

  std::string text = minimal_case + R"(walls:
  - {name: box, box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1], open: [z_max, xmin]}, material: glass}
)";
  const auto b = input::load_case_text(text, "t.yaml");
  EXPECT_EQ(b.walls.back().open, (std::vector<std::string>{"zmax", "xmin"}));
  text.replace(text.find("xmin]"), 4, "zmax");
  EXPECT_NE(error_of(text).find("face 'zmax' is listed twice"), std::string::npos)
      << error_of(text);
}

TEST(InputCfdDem, BlocksNeedEachOtherAndValidValues) {
  const std::string fluid_only = good_fluid.substr(0, good_fluid.find("coupling:"));
  std::string message = error_of(cfd_case(fluid_only));
  EXPECT_NE(message.find("t.yaml:11:"), std::string::npos) << message;
  EXPECT_NE(message.find("needs a coupling: block"), std::string::npos) << message;

  message = error_of(cfd_case("coupling: {drag: di_felice}\n"));
  EXPECT_NE(message.find("t.yaml:11:"), std::string::npos) << message;
  EXPECT_NE(message.find("needs a fluid: block"), std::string::npos) << message;

  message = error_of(case_with_coupling("interval: 0"));
  EXPECT_NE(message.find("coupling.interval"), std::string::npos) << message;

  message = error_of(case_with_coupling("fluid_fraction_rate: differences"));
  EXPECT_NE(message.find("t.yaml:16:"), std::string::npos) << message;
  EXPECT_NE(message.find("coupling.fluid_fraction_rate"), std::string::npos) << message;
  EXPECT_NE(message.find("difference"), std::string::npos) << message;

  // The time derivative of the deposit only for the continuous ones.
  for (const char* scheme : {"trilinear", "smoothed"}) {
    const auto c =
        input::load_case_text(case_with_coupling(std::string("fluid_fraction: ") + scheme +
                                                 ", fluid_fraction_rate: derivative"),
                              "t.yaml");
    EXPECT_EQ(c.coupling->fluid_fraction, scheme);
    EXPECT_EQ(c.coupling->fluid_fraction_rate, "derivative");
    const auto again = input::load_case_text(input::echo_yaml(c, "1"), "echo.yaml");
    EXPECT_EQ(again.coupling->fluid_fraction, scheme);
    EXPECT_EQ(again.coupling->fluid_fraction_rate, "derivative");
  }
  for (const char* scheme : {"divided", "centre"}) {
    message = error_of(case_with_coupling(std::string("fluid_fraction: ") + scheme +
                                          ", fluid_fraction_rate: derivative"));
    EXPECT_NE(message.find("coupling.fluid_fraction_rate"), std::string::npos) << message;
    EXPECT_NE(message.find("'derivative' needs 'fluid_fraction: smoothed' or 'trilinear'"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find(scheme), std::string::npos) << message;
  }
  message = error_of(case_with_coupling("fluid_fraction: smooth"));
  EXPECT_NE(message.find("smoothed"), std::string::npos) << message;

  message = error_of(case_with_coupling("rate_relaxation: 0"));
  EXPECT_NE(message.find("coupling.rate_relaxation"), std::string::npos) << message;
  EXPECT_NE(message.find("(0, 1]"), std::string::npos) << message;

  message = error_of(case_with_coupling("pressure_gradient_force: maybe"));
  EXPECT_NE(message.find("coupling.pressure_gradient_force"), std::string::npos) << message;

  message = error_of(case_with_coupling("interpolation: linear"));
  EXPECT_NE(message.find("t.yaml:16:"), std::string::npos) << message;
  EXPECT_NE(message.find("coupling.interpolation"), std::string::npos) << message;
  EXPECT_NE(message.find("trilinear"), std::string::npos) << message;

  std::string blocks = good_fluid;
  blocks.replace(blocks.find("[4, 4, 8]"), 9, "[4, 4]");
  message = error_of(cfd_case(blocks));
  EXPECT_NE(message.find("t.yaml:14:"), std::string::npos) << message;
  EXPECT_NE(message.find("fluid.cells"), std::string::npos) << message;

  message = error_of(minimal_case +
                     "output: {series: {every: 0.01, quantities: [fluid_pressure_drop]}}\n");
  EXPECT_NE(message.find("needs a fluid: block"), std::string::npos) << message;
}

// With shear walls the fluid's zmin and zmax are those walls: no-slip, moving at -+ rate h / 2
// along x; writing them again is refused, and a fluid in a Lees-Edwards box is refused.
TEST(InputCfdDem, ShearWallsDriveTheFluid) {
  const std::string fluid =
      "fluid: {density: 1.2, viscosity: 1.8e-5, cells: [2, 2, 4]}\n"
      "coupling: {drag: holzer_sommerfeld}\n";
  const std::string walls = "shear: {rate: 50, boundary: walls, wall_material: glass}\n";
  const auto c = input::load_case_text(cfd_case(walls + fluid), "t.yaml");
  ASSERT_TRUE(c.fluid);
  using K = config::FluidBoundary::Kind;
  EXPECT_EQ(c.fluid->boundary[4].kind, K::MovingWall);
  EXPECT_EQ(c.fluid->boundary[5].kind, K::MovingWall);
  EXPECT_NEAR(c.fluid->boundary[4].velocity.x, -2.5, 1e-12);  // 50 1/s x 0.1 m / 2
  EXPECT_NEAR(c.fluid->boundary[5].velocity.x, 2.5, 1e-12);
  EXPECT_EQ(c.fluid->boundary[0].kind, K::Periodic);
  // The echoed case reads back the same (the shear walls are not written under fluid:).
  TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", input::echo_yaml(c, "9.9.9")));
  ASSERT_TRUE(again.fluid);
  EXPECT_EQ(again.fluid->boundary[5].velocity, c.fluid->boundary[5].velocity);

  std::string explicit_wall = fluid;
  explicit_wall.replace(explicit_wall.find("}\n"), 2, ", boundary: {zmax: no_slip}}\n");
  std::string message = error_of(cfd_case(walls + explicit_wall));
  EXPECT_NE(message.find("fluid.boundary.zmax"), std::string::npos) << message;
  EXPECT_NE(message.find("is a shear wall"), std::string::npos) << message;

  std::string le = cfd_case("shear: {rate: 50, boundary: lees_edwards}\n" + fluid);
  le.replace(le.find("periodic: [true, true, false]"), 29, "periodic: [true, true, true]");
  message = error_of(le);
  EXPECT_NE(message.find("Lees-Edwards"), std::string::npos) << message;
  EXPECT_NE(message.find("t.yaml:12:"), std::string::npos) << message;
}

// ---------------------------------------------------------------------------------------------
// Mesh walls: STL files

namespace {

/// A binary STL of the same unit cube as tests/data/stl/unit_cube_ascii.stl (12 triangles, every
/// vertex written once per triangle), plus one zero-area triangle.
void write_binary_cube(const fs::path& file) {
  const auto ascii = gf::io::read_stl(data_dir / "stl" / "unit_cube_ascii.stl");
  std::ofstream out(file, std::ios::binary);
  char header[80] = "binary cube written by test_input.cpp";
  out.write(header, 80);
  const std::uint32_t n = static_cast<std::uint32_t>(ascii.triangles.size()) + 1;
  out.write(reinterpret_cast<const char*>(&n), 4);
  auto put = [&](const Vec3& p) {
    const float f[3] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    out.write(reinterpret_cast<const char*>(f), 12);
  };
  const std::uint16_t attr = 0;
  for (const auto& t : ascii.triangles) {
    put({0, 0, 0});  // the normal (not used: the reader recomputes nothing from it)
    for (int k = 0; k < 3; ++k) put(ascii.points[static_cast<std::size_t>(t[k])]);
    out.write(reinterpret_cast<const char*>(&attr), 2);
  }
  put({0, 0, 0});
  for (int k = 0; k < 3; ++k) put({0.5, 0.5, 0.0});  // degenerate
  out.write(reinterpret_cast<const char*>(&attr), 2);
}

}  // namespace

// ASCII and binary STL give the same surface: 8 distinct vertices (each written 4-6 times),
// 12 triangles, scaled and offset into the case's frame; a zero-area triangle is left out and
// counted; the echo names the file and round-trips.
TEST(InputMesh, AsciiAndBinaryStlGiveTheSameSurface) {
  TempDir dir;
  write_binary_cube(dir / "cube.stl");
  fs::copy_file(data_dir / "stl" / "unit_cube_ascii.stl", dir / "cube_ascii.stl");
  for (const std::string file : {"cube_ascii.stl", "cube.stl"}) {
    const auto path =
        dir.write("case.yaml", minimal_case + "walls:\n  - {name: bin, mesh: {file: " + file +
                                   ", scale: 0.05, offset: [0.02, 0.02, 0.02]},\n"
                                   "     material: glass}\n");
    const auto c = input::load_case(path);
    ASSERT_EQ(c.walls.size(), 1u);
    const auto& w = c.walls[0];
    EXPECT_EQ(w.kind, config::Wall::Kind::Mesh);
    EXPECT_EQ(w.mesh_file, dir / file);
    EXPECT_EQ(w.mesh_points.size(), 8u) << file;
    EXPECT_EQ(w.mesh_triangles.size(), 12u) << file;
    EXPECT_EQ(w.mesh_dropped, file == "cube.stl" ? 1u : 0u);
    Vec3 lo{1, 1, 1}, hi{-1, -1, -1};
    for (const auto& p : w.mesh_points)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    for (int k = 0; k < 3; ++k) {
      EXPECT_DOUBLE_EQ(lo[k], 0.02);
      EXPECT_DOUBLE_EQ(hi[k], 0.07);
    }
    const std::string echo = input::echo_yaml(c, "test");
    EXPECT_NE(echo.find((dir / file).string()), std::string::npos) << echo;
    const auto again = input::load_case_text(echo, "echo.yaml");
    EXPECT_EQ(again.walls[0].mesh_points.size(), 8u);
    EXPECT_EQ(again.walls[0].mesh_offset, w.mesh_offset);
    // The sphere at the centre of the meshed cube (0.045) stays inside under gravity: the mesh
    // is closed, the floor carries the weight.
    Simulation sim(c);
    for (int s = 0; s < 40000; ++s) sim.step();
    const Vec3 x = sim.particles().x()[0];
    EXPECT_NEAR(x.z, 0.02 + 0.005, 1e-4) << file;
    EXPECT_NEAR(sim.walls()[0].force.z, -9.81 * sim.particles().mass()[0], 1e-6) << file;
  }
}

// ---------------------------------------------------------------------------------------------
// Checks added after an audit of bad input (2026-12-03): each refused with file, line, key.

namespace {

/// The message of the InputError thrown by loading and validating the shipped case `rel` (under
/// cases/) with overrides, or "" if none.
std::string case_error(const std::string& rel, const std::vector<input::Override>& sets) {
  try {
    input::validate(input::load_case(fs::path(GF_SOURCE_DIR) / "cases" / rel, sets));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(InputAudit, MoreThan1e15StepsAreRefused) {
  // (a step of 1e-320 s used to overflow the step count that check prints)
  std::string text = minimal_case;
  text.replace(text.find("step: 1.0e-5"), 12, "step: 1.0e-17");
  const auto m = error_of(text);
  EXPECT_NE(m.find("t.yaml:1:"), std::string::npos) << m;
  EXPECT_NE(m.find("time.step"), std::string::npos) << m;
  EXPECT_NE(m.find("more than 1e15 steps"), std::string::npos) << m;
  text = minimal_case;
  text.replace(text.find("step: 1.0e-5"), 12, "step: 1.0e-15");  // 1e14 steps: allowed
  EXPECT_EQ(error_of(text), "");
}

TEST(InputAudit, OverrideErrorsNameTheOptionNotAPlaceInTheFile) {
  const auto m = case_error("dem/terrain_settling/case.yaml", {{"time.end", "abc"}});
  EXPECT_NE(m.find("case.yaml (--set time.end=abc): error: time.end: "), std::string::npos) << m;
  // ... also for a key inside an overridden map; the file's own keys keep their lines.
  const auto n =
      case_error("dem/terrain_settling/case.yaml", {{"time", "{step: 1.0e-5, end: -1}"}});
  EXPECT_NE(n.find("(--set time={step: 1.0e-5, end: -1}): error: time.end"), std::string::npos)
      << n;
  const auto k = case_error("dem/terrain_settling/case.yaml",
                            {{"time.end", "1"}, {"output.series.every", "1.0e-9"}});
  EXPECT_NE(k.find("output.series.every"), std::string::npos) << k;
  EXPECT_NE(k.find("--set output.series.every=1.0e-9"), std::string::npos) << k;
  EXPECT_EQ(k.find("--set time.end"), std::string::npos) << k;
}

TEST(InputAudit, AFluidWithoutOutletMustLetOutWhatItLetsIn) {
  // The fluidized bed's zmax is its pressure outlet: a no-slip lid leaves the inlet's flow
  // nowhere to go (the pressure solve used to stop at the first fluid step, exit 1).
  const auto m =
      case_error("cfd_dem/fluidized_bed/case.yaml", {{"fluid.boundary.zmax", "no_slip"}});
  EXPECT_NE(m.find("case.yaml:"), std::string::npos) << m;
  EXPECT_NE(m.find("fluid.boundary: the fluid has no pressure_outlet face"), std::string::npos)
      << m;
  // Inflow through zmin and the same outflow through zmax (an inlet with a negative speed)
  // balance: accepted.
  EXPECT_EQ(case_error("cfd_dem/fluidized_bed/case.yaml",
                       {{"fluid.boundary.zmax", "{velocity_inlet: [0, 0, 0.03]}"},
                        {"fluid.boundary.zmin", "{velocity_inlet: [0, 0, 0.03]}"}}),
            "");
}

TEST(InputAudit, SweepValuesMustDifferAsTheirRunsFoldersDo) {
  const auto m = case_error("rheology/shear_box_rods/case.yaml",
                            {{"sweep.volume_fraction", "[0.45, 0.2, 0.45]"}});
  EXPECT_NE(m.find("sweep.volume_fraction[2]"), std::string::npos) << m;
  EXPECT_NE(m.find("item 0 is 0.45"), std::string::npos) << m;
  const auto r =
      case_error("rheology/shear_box_rods/case.yaml", {{"sweep.shear_rate", "[100, 100.0000001]"}});
  EXPECT_NE(r.find("sweep.shear_rate[1]"), std::string::npos) << r;
  EXPECT_EQ(case_error("rheology/shear_box_rods/case.yaml", {{"sweep.shear_rate", "[10, 100]"}}),
            "");
}

TEST(InputAudit, AServoSpanIsTwoDifferentParallelWalls) {
  const auto m =
      case_error("dem2d/biaxial/case.yaml", {{"walls[3].servo.span", "[[right, right]]"}});
  EXPECT_NE(m.find("walls[3].servo.span[0]"), std::string::npos) << m;
  EXPECT_NE(m.find("two different walls"), std::string::npos) << m;
  const auto n =
      case_error("dem2d/biaxial/case.yaml", {{"walls[3].servo.span", "[[left, floor]]"}});
  EXPECT_NE(n.find("walls[3].servo.span[0]"), std::string::npos) << n;
  EXPECT_NE(n.find("two parallel plane walls"), std::string::npos) << n;
  EXPECT_EQ(case_error("dem2d/biaxial/case.yaml", {}), "");
}

TEST(InputAudit, ARandomFillAskingMoreThanTheRegionHoldsIsRefused) {
  const std::string fill = header_3d + R"(particles:
  - radius: 0.005
    material: glass
    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}, lattice: random, count: 3000}
)";
  const auto m = error_of(fill);  // 3000 spheres of 5 mm: a solid fraction of 1.57
  EXPECT_NE(m.find("t.yaml:10:"), std::string::npos) << m;
  EXPECT_NE(m.find("particles[0].fill"), std::string::npos) << m;
  EXPECT_NE(m.find("solid volume fraction of 1.57"), std::string::npos) << m;
}

TEST(InputAudit, AFolderIsNotACaseFile) {
  try {
    input::load_case(fs::path(GF_SOURCE_DIR) / "cases");
    ADD_FAILURE() << "a folder was read as a case";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a folder, not a case file"), std::string::npos)
        << e.what();
  }
}

// Boussinesq buoyancy: `check` states beta x the span of the case's temperatures and warns when
// it is not small (air heated from 293 to 373 K with beta = 1/293 K: 0.27), or when there is no
// gravity to act on.
TEST(InputValidate, BuoyancyStatesItsDensityChangeAndWarnsWhenLarge) {
  auto c = input::load_case(std::filesystem::path(GF_SOURCE_DIR) / "cases" / "cfd_dem" /
                            "fluidized_bed_heating" / "case.yaml");
  const auto has = [](const std::vector<std::string>& list, const std::string& part) {
    return std::any_of(list.begin(), list.end(),
                       [&](const std::string& w) { return w.find(part) != std::string::npos; });
  };
  auto report = input::validate(c);
  EXPECT_TRUE(derived(report, "buoyancy").empty());  // no thermal_expansion, no line
  c.fluid->thermal_expansion = 1.0 / 293.0;
  report = input::validate(c);
  EXPECT_EQ(derived(report, "buoyancy: beta"), "0.273 (293 - 373 K)");
  EXPECT_TRUE(
      has(report.warnings, "fluid.thermal_expansion: beta x the temperature span 293 - 373"));
  c.fluid->thermal_expansion = 2.1e-4;
  report = input::validate(c);
  EXPECT_EQ(derived(report, "buoyancy: beta"), "0.0168 (293 - 373 K)");
  EXPECT_FALSE(has(report.warnings, "fluid.thermal_expansion"));
  c.gravity = Vec3{};
  report = input::validate(c);
  EXPECT_TRUE(has(report.warnings, "the case has no gravity, so the buoyancy does nothing"));
}
