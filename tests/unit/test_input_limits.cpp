// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the input layer's limits: memory estimates (grains, lattice sites, neighbour
// cells, SPH particles, two-fluid and CFD-DEM cells), absurd STL scales, SPH wall thickness,
// two-fluid initial regions outside the domain, and YAML values tagged as strings.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "input_error.hpp"
#include "io/input/memory_budget.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/parse_continuum.hpp"
#include "io/input/parse_two_fluid.hpp"
#include "io/input/validate.hpp"
#include "io/input/yaml_reader.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace gf;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {

/// Sets GRAINFLOW_MEMORY_LIMIT for the scope (unset: removes it), then restores it.
class MemoryLimit {
 public:
  explicit MemoryLimit(const char* value) {
    if (const char* old = std::getenv("GRAINFLOW_MEMORY_LIMIT")) old_ = old;
    if (value)
      setenv("GRAINFLOW_MEMORY_LIMIT", value, 1);
    else
      unsetenv("GRAINFLOW_MEMORY_LIMIT");
  }
  ~MemoryLimit() {
    if (old_)
      setenv("GRAINFLOW_MEMORY_LIMIT", old_->c_str(), 1);
    else
      unsetenv("GRAINFLOW_MEMORY_LIMIT");
  }
  MemoryLimit(const MemoryLimit&) = delete;
  MemoryLimit& operator=(const MemoryLimit&) = delete;

 private:
  std::optional<std::string> old_;
};

/// `text` with its first `from` replaced by `to` (a test failure when there is none).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// The message of the InputError thrown by loading and validating a DEM case, or "".
std::string dem_error(const std::string& text, const fs::path& file = "t.yaml") {
  return test::input_error_of([&] { input::validate(input::load_case_text(text, file)); });
}

/// A 3D DEM case in a box of edge `edge` m holding one group of glass spheres of radius
/// `radius` m with the fill (or explicit positions) `group`.
std::string dem_case(const std::string& group, double edge = 10, double radius = 0.002) {
  return fmt::format(R"(time: {{step: 1.0e-5, end: 0.1}}
domain: {{min: [0, 0, 0], max: [{0}, {0}, {0}]}}
materials:
  glass: {{density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}}
contacts:
  - {{between: [glass, glass], model: hertz_mindlin, restitution: 0.5}}
particles:
  - shape: sphere
    radius: {1}
    material: glass
    {2}
)",
                     edge, radius, group);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The memory limit itself

TEST(InputLimits, MemoryLimitIsThePhysicalMemoryUnlessTheVariableSetsIt) {
  {
    MemoryLimit unset(nullptr);
    EXPECT_GT(input::physical_memory_bytes(), 1e8);
    EXPECT_EQ(input::memory_limit_bytes(), input::physical_memory_bytes());
  }
  {
    MemoryLimit limit("16G");
    EXPECT_EQ(input::memory_limit_bytes(), 16e9);
  }
  {
    MemoryLimit limit("2GiB");
    EXPECT_EQ(input::memory_limit_bytes(), 2.0 * 1024 * 1024 * 1024);
  }
  {
    MemoryLimit limit("8e9");
    EXPECT_EQ(input::memory_limit_bytes(), 8e9);
  }
  {
    MemoryLimit limit("512MB");
    EXPECT_EQ(input::memory_limit_bytes(), 512e6);
  }
  for (const char* bad : {"lots", "16Q", "-1G", "0"}) {
    MemoryLimit limit(bad);
    try {
      input::memory_limit_bytes();
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("GRAINFLOW_MEMORY_LIMIT")) << bad;
      EXPECT_THAT(e.what(), HasSubstr(fmt::format("found '{}'", bad)));
    }
  }
  EXPECT_EQ(input::bytes_text(4e11), "400 GB");
  EXPECT_EQ(input::bytes_text(1.5e6), "1.5 MB");
}

// ---------------------------------------------------------------------------------------------
// DEM fills

TEST(InputLimits, RandomFillOfABillionGrainsIsRefusedAtCount) {
  MemoryLimit limit("16G");
  // (5 mm spheres at 1e9 take 3 % of the 1000 m^3 box: the fill itself is possible)
  const std::string m = dem_error(
      dem_case("fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, lattice: random, count: 1e9}"));
  EXPECT_THAT(m, HasSubstr("t.yaml:11:"));
  EXPECT_THAT(m, HasSubstr("particles[0].fill.count: expected a case that fits in memory"));
  EXPECT_THAT(m, HasSubstr("found that 1e+09 grains need about 400 GB"));
  EXPECT_THAT(m, HasSubstr("GRAINFLOW_MEMORY_LIMIT sets is 16 GB"));
}

TEST(InputLimits, LatticeFillOfBillionsOfSitesIsRefusedAtSpacingOrRegion) {
  MemoryLimit limit("16G");
  // 10 m / 4.04 mm: ~2475^3 = 1.5e10 sites
  std::string m = dem_error(dem_case("fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}}"));
  EXPECT_THAT(m, HasSubstr("particles[0].fill.box:"));
  EXPECT_THAT(m, HasSubstr("32-bit"));
  // 1e9 sites: within the indices, beyond memory
  m = dem_error(
      dem_case("fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, lattice: cubic, spacing: 0.01}"));
  EXPECT_THAT(m, HasSubstr("particles[0].fill.spacing: expected a case that fits in memory"));
  EXPECT_THAT(m, HasSubstr("found that 1e+09 grains need about 400 GB"));
  // with a count that caps it, the count is the culprit
  m = dem_error(dem_case(
      "fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, spacing: 0.01, count: 500000000}"));
  EXPECT_THAT(m, HasSubstr("particles[0].fill.count: expected a case that fits in memory"));
  EXPECT_THAT(m, HasSubstr("found that 5e+08 grains need about 200 GB"));
  // a volume fraction lists every site of the lattice before it picks its grains
  m = dem_error(dem_case(
      "fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, spacing: 0.01, volume_fraction: 1e-3}"));
  EXPECT_THAT(m, HasSubstr("particles[0].fill.volume_fraction:"));
  EXPECT_THAT(m, HasSubstr("(and the 1e+09 lattice sites they are picked from)"));
}

TEST(InputLimits, MoreGrainsThan32BitIndicesAreRefused) {
  MemoryLimit limit("1000T");  // memory is not the limit here
  const std::string m = dem_error(dem_case(
      "fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, lattice: random, count: 3e9}", 10, 0.0005));
  EXPECT_THAT(m, HasSubstr("particles[0].fill.count: expected at most 2147483647 grains"));
  EXPECT_THAT(m, HasSubstr("found 3e+09"));
}

TEST(InputLimits, NeighbourGridOfAHugeDomainIsCounted) {
  // 10 m box, 2 mm grains (cut-off 5 mm: 2000 cells per axis, capped at 1024): with 1e8 grains
  // the grid may have 8e8 cells, so it is 512 x 1024 x 1024 cells of 16 B, 8.6 GB, next to the
  // grains' 40 GB; refused with the grains' part named first.
  {
    MemoryLimit limit("1000G");
    const auto report = input::validate(input::load_case_text(
        dem_case("fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, lattice: random, count: 1e8}"),
        "t.yaml"));
    EXPECT_TRUE(report.warnings.empty());
  }
  {
    MemoryLimit limit("8G");
    const std::string m = dem_error(
        dem_case("fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, lattice: random, count: 1e8}"));
    EXPECT_THAT(m, HasSubstr("found that 1e+08 grains need about 40 GB"));
  }
  // One grain in that box: cells beyond 8 per grain only cost memory (and the time to clear
  // them), so the grid has 2^20 cells (17 MB), not 1024^3 (17 GB).
  EXPECT_DOUBLE_EQ(input::neighbour_cells({10, 10, 10}, 0.005, 3, 1), 1048576.0);
  EXPECT_DOUBLE_EQ(input::neighbour_cells({10, 10, 10}, 0.005, 3, 1e8), 512.0 * 1024 * 1024);
  {
    MemoryLimit limit("1G");
    const auto report =
        input::validate(input::load_case_text(dem_case("positions: [[1, 1, 1]]"), "t.yaml"));
    EXPECT_TRUE(report.warnings.empty());
  }
}

// The estimate follows the real grid of a 2D run: z spans +-max(cut-off, 1 mm), so grains much
// smaller than 1 mm get many cells along z (2 disks of r = 10 um in 1 m x 1 m: 79x the memory
// of one layer, 1.3 GB measured where the estimate said 16.8 MB).
TEST(InputLimits, TwoDimensionalGridCountsItsCellsAlongZ) {
  const double cutoff = 2.5e-5;
  EXPECT_DOUBLE_EQ(input::neighbour_cells({1, 1, 0}, cutoff, 2, 1e8), 1024.0 * 1024.0 * 80.0);
  EXPECT_DOUBLE_EQ(input::neighbour_cells({1, 1, 0}, 0.01, 2, 2), 100.0 * 100.0 * 2.0);
  EXPECT_DOUBLE_EQ(input::neighbour_cells({1, 1, 1}, 0.01, 3, 2), 1.0e6);
  // Two disks alone: the grid coarsens to at most 2^20 cells.
  EXPECT_LE(input::neighbour_cells({1, 1, 0}, cutoff, 2, 2), 1048576.0);
}

// Bytes per grain by shape (measured slopes of peak RSS: polygons ~1050 B, each with its own
// shape-table entry; disks ~500 B; settled rods ~800 B; spheres ~230-390 B).
TEST(InputLimits, GrainMemoryDependsOnTheShape) {
  EXPECT_LT(input::bytes_per_grain(config::Shape::Sphere),
            input::bytes_per_grain(config::Shape::Disk));
  EXPECT_GE(input::bytes_per_grain(config::Shape::Polygon), 1053.0);
  EXPECT_GE(input::bytes_per_grain(config::Shape::Spherocylinder), 416.0 + 370.0);
}

TEST(InputLimits, PartsThatFitAloneAreRefusedTogether) {
  MemoryLimit limit("13G");
  // 3e7 grains (12 GB) and the 10 m box's neighbour grid for them (512^3 cells: 2.1 GB)
  const std::string m = dem_error(
      dem_case("fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, lattice: random, count: 3e7}"));
  EXPECT_THAT(m, HasSubstr("together, need about 14.1 GB"));
}

// A sphere in a store that also holds spherocylinders carries their columns (~130 B): 3e7
// spheres, 12 GB alone (400 B each), need 15.9 GB beside one rod, refused at their own count.
TEST(InputLimits, RoundGrainsBesideShapedOnesCountTheShapeColumns) {
  MemoryLimit limit("13G");
  const std::string spheres =
      dem_case("fill: {box: {min: [0, 0, 0], max: [10, 10, 10]}, lattice: random, count: 3e7}");
  EXPECT_THAT(dem_error(spheres), HasSubstr("together, need about 14.1 GB"));
  const std::string with_rod = spheres + R"(  - shape: spherocylinder
    radius: 0.001
    length: 0.002
    material: glass
    positions: [[5, 5, 5.5]]
)";
  const std::string m = dem_error(with_rod);
  EXPECT_THAT(m, HasSubstr("particles[0].fill.count"));
  EXPECT_THAT(m, HasSubstr("3e+07 grains need about 15.9 GB"));
}

TEST(InputLimits, CfdDemFluidCellsAreCounted) {
  MemoryLimit limit("16G");
  const std::string text = dem_case("positions: [[0.05, 0.05, 0.05]]", 0.1, 0.002) +
                           R"(fluid:
  density: 1000
  viscosity: 1.0e-3
  cells: [4096, 4096, 1]
  boundary: {zmin: {velocity_inlet: [0, 0, 0.01]}, zmax: {pressure_outlet: 0}}
coupling: {drag: gidaspow}
)";
  const std::string m = dem_error(text);
  EXPECT_THAT(m, HasSubstr("t.yaml:15:"));
  EXPECT_THAT(m, HasSubstr("fluid.cells: expected a case that fits in memory"));
  EXPECT_THAT(m, HasSubstr("found that 16777216 fluid cells need about 36.9 GB"));
}

// ---------------------------------------------------------------------------------------------
// SPH

namespace {

const char* const kSph = R"(continuum:
  method: sph
  dimension: 2
  domain: {min: [0, 0], max: [1, 1]}
  gravity: [0, -9.81]
  spacing: 0.01
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0e-3}
  time: {end: 0.1}
  blocks:
    - {box: {min: [0.1, 0.1], max: [0.5, 0.5]}}
  walls:
    - {name: floor, box: {min: [0, 0], max: [1, 0.05]}}
    - {name: post, cylinder: {center: [0.7, 0.5], radius: 0.1, thickness: 0.04}}
)";

input::ContinuumCase parse_sph(const std::string& text) {
  const auto root = input::YamlNode::parse_text(text, "case.yaml");
  return input::parse_continuum(input::YamlMap(root, {"continuum"}).at("continuum"));
}

std::string sph_error(const std::string& text) {
  return test::input_error_of([&] { parse_sph(text); });
}

}  // namespace

TEST(InputLimits, SphSpacingOfAMicronInAMetreIsRefused) {
  MemoryLimit limit("16G");
  EXPECT_EQ(sph_error(kSph), "");
  // 20 um: ~5.8e8 particles in the blocks and walls
  std::string m = sph_error(replaced(kSph, "spacing: 0.01", "spacing: 2.0e-5"));
  EXPECT_THAT(
      m,
      HasSubstr("case.yaml:6:12: error: continuum.spacing: expected a case that fits in memory"));
  EXPECT_THAT(m, HasSubstr("found that about 5."));
  EXPECT_THAT(m, HasSubstr("particles (blocks and walls at spacing 2e-05 m)"));
  EXPECT_THAT(m, HasSubstr("(the limit GRAINFLOW_MEMORY_LIMIT sets is 16 GB)"));
  // 1 um: 2.3e11 (1.6e11 in the block alone), beyond 32-bit indices
  m = sph_error(replaced(kSph, "spacing: 0.01", "spacing: 1.0e-6"));
  EXPECT_THAT(m, HasSubstr("continuum.spacing: expected at most 2147483647 particles"));
  EXPECT_THAT(m, HasSubstr("found about 2.3e+11"));
}

TEST(InputLimits, SphWallThicknessMustHoldAParticleLayer) {
  const std::string wall = "radius: 0.1, thickness: 0.04}";
  for (const char* t : {"0", "-0.01"}) {
    const std::string m =
        sph_error(replaced(kSph, wall, fmt::format("radius: 0.1, thickness: {}}}", t)));
    EXPECT_THAT(m, HasSubstr("continuum.walls[1].cylinder.thickness: expected a thickness > 0 m "
                             "(leave thickness out for a solid disk)"))
        << t;
  }
  // thinner than one spacing: gaps in the shell
  std::string m = sph_error(replaced(kSph, wall, "radius: 0.1, thickness: 0.005}"));
  EXPECT_THAT(m, HasSubstr("continuum.walls[1].cylinder.thickness: expected a wall at least one "
                           "particle spacing (0.01 m) thick"));
  // thinner than the kernel's reach 2h = 0.026 m: a warning
  const auto thin = parse_sph(replaced(kSph, wall, "radius: 0.1, thickness: 0.015}"));
  ASSERT_EQ(thin.warnings.size(), 1u);
  EXPECT_THAT(thin.warnings[0], HasSubstr("continuum.walls[1].cylinder.thickness: a wall 0.015 m "
                                          "thick is thinner than the kernel's reach 2h = 0.026 m"));
  EXPECT_TRUE(parse_sph(kSph).warnings.empty());
  // without thickness: solid
  EXPECT_EQ(parse_sph(replaced(kSph, ", thickness: 0.04}", "}")).sph.walls[1].thickness, 0.0);
  // a fluid block's annulus too must be > 0 when given
  m = sph_error(replaced(kSph, "{box: {min: [0.1, 0.1], max: [0.5, 0.5]}}",
                         "{cylinder: {center: [0.3, 0.3], radius: 0.1, thickness: 0}}"));
  EXPECT_THAT(m, HasSubstr("continuum.blocks[0].cylinder.thickness: expected a thickness > 0 m"));
}

// ---------------------------------------------------------------------------------------------
// Two-fluid

namespace {

const char* const kTwoFluid = R"(two_fluid:
  dimension: 2
  domain: {min: [0, 0], max: [0.04, 0.08]}
  cells: [8, 16]
  gravity: [0, -9.81]
  fluid: {density: 1.2, viscosity: 1.8e-5}
  solids: {closures: syamlal, restitution: 0.9, grain_diameter: 5.0e-4, grain_density: 2500}
  drag: {model: gidaspow}
  boundaries:
    y_min: {type: inlet, velocity: [0, 0.4]}
    y_max: {type: outlet}
  initial:
    regions:
      - {box: {min: [0, 0], max: [0.04, 0.03]}, solids_fraction: 0.5}
  time: {end: 1.0}
)";

std::string two_fluid_error(const std::string& text) {
  return test::input_error_of([&] {
    const auto root = input::YamlNode::parse_text(text, "case.yaml");
    input::parse_two_fluid(input::YamlMap(root, {"two_fluid"}).at("two_fluid"));
  });
}

}  // namespace

TEST(InputLimits, TwoFluidGridOfAbsurdSizeIsRefusedBeforeItIsBuilt) {
  MemoryLimit limit("16G");
  EXPECT_EQ(two_fluid_error(kTwoFluid), "");
  // (1e5 x 2e5 = 2e10 cells: an attempt to build them would throw std::bad_alloc)
  const std::string m = two_fluid_error(replaced(kTwoFluid, "cells: [8, 16]", "cells: [1e5, 1e5]"));
  EXPECT_THAT(
      m, HasSubstr("case.yaml:4:10: error: two_fluid.cells: expected a case that fits in memory"));
  EXPECT_THAT(m, HasSubstr("found that 1e+10 cells need about 42 TB"));
}

TEST(InputLimits, TwoFluidRegionOutsideTheDomainIsRefused) {
  const std::string region = "{box: {min: [0, 0], max: [0.04, 0.03]}";
  std::string m = two_fluid_error(replaced(kTwoFluid, region, "{box: {min: [5, 5], max: [6, 6]}"));
  EXPECT_THAT(m, HasSubstr("case.yaml:14:15: error: two_fluid.initial.regions[0].box: expected a "
                           "region holding at least one cell centre"));
  EXPECT_THAT(m, HasSubstr("lies outside the domain"));
  // a sliver between two rows of cell centres (5 mm cells, centres at 2.5 mm, 7.5 mm, ...)
  m = two_fluid_error(replaced(kTwoFluid, region, "{box: {min: [0, 0.003], max: [0.04, 0.007]}"));
  EXPECT_THAT(m, HasSubstr("lies between cell centres"));
  m = two_fluid_error(replaced(kTwoFluid, region, "{box: {min: [0, 0.03], max: [0.04, 0]}"));
  EXPECT_THAT(m, HasSubstr("regions[0].box: expected max > min along every axis"));
  // reaching past the domain is fine: "everything below 3 cm"
  EXPECT_EQ(two_fluid_error(replaced(kTwoFluid, region, "{box: {min: [-1, -1], max: [1, 0.03]}")),
            "");
}

// ---------------------------------------------------------------------------------------------
// STL meshes

TEST(InputLimits, AbsurdMeshScaleIsRefusedAtTheKey) {
  test::TempDir dir;
  const fs::path stl = fs::path(GF_SOURCE_DIR) / "tests" / "data" / "stl" / "unit_cube_ascii.stl";
  auto with_mesh = [&](const std::string& mesh) {
    return dem_case("positions: [[0.5, 0.5, 0.5]]", 1, 0.01) +
           fmt::format("walls:\n  - {{name: bin, material: glass, mesh: {{file: {}{}}}}}\n",
                       stl.string(), mesh);
  };
  const fs::path file = dir / "case.yaml";
  EXPECT_EQ(dem_error(with_mesh(""), file), "");
  EXPECT_EQ(dem_error(with_mesh(", scale: 2"), file), "");
  std::string m = dem_error(with_mesh(", scale: 1e200"), file);
  EXPECT_THAT(m, HasSubstr("walls[0].mesh.scale: expected a scale that gives a mesh of about the "
                           "domain's size"));
  EXPECT_THAT(m, HasSubstr("case.yaml:13:"));
  m = dem_error(with_mesh(", scale: 1e-200"), file);
  EXPECT_THAT(m, HasSubstr("walls[0].mesh.scale: expected a scale"));
  m = dem_error(with_mesh(", offset: [1e300, 0, 0]"), file);
  EXPECT_THAT(m, HasSubstr("walls[0].mesh.offset: expected a mesh near the domain"));
  // beyond doubles
  m = dem_error(with_mesh(", scale: 1e308, offset: [1e308, 0, 0]"), file);
  EXPECT_THAT(m, HasSubstr("walls[0].mesh.scale: expected a scale and offset that keep the "
                           "mesh's coordinates finite"));
}

// ---------------------------------------------------------------------------------------------
// YAML tags

TEST(InputLimits, ValuesTaggedAsStringsAreNotNumbers) {
  const std::string base = dem_case("positions: [[0.05, 0.05, 0.05]]", 0.1, 0.002);
  EXPECT_EQ(dem_error(base), "");
  std::string m = dem_error(replaced(base, "density: 2500", "density: !!str 2500"));
  EXPECT_THAT(m, HasSubstr("t.yaml:4:"));
  EXPECT_THAT(m, HasSubstr("error: materials.glass.density: expected a number > 0, found '2500' "
                           "(tagged !!str)"));
  // the number tags are numbers
  EXPECT_EQ(dem_error(replaced(base, "density: 2500", "density: !!float 2500")), "");
  EXPECT_EQ(dem_error(replaced(base, "density: 2500", "density: !!int 2500")), "");
  // an integer, a boolean, a local tag
  m = dem_error(replaced(base, "positions: [[0.05, 0.05, 0.05]]",
                         "fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}, count: !!str 5}"));
  EXPECT_THAT(m, HasSubstr("particles[0].fill.count: expected an integer >= 1, found '5' "
                           "(tagged !!str)"));
  m = dem_error(replaced(base, "domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}",
                         "domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1], periodic: [!!str true, "
                         "false, false]}"));
  EXPECT_THAT(m, HasSubstr("domain.periodic[0]: expected true or false, found 'true' (tagged "
                           "!!str)"));
  m = dem_error(replaced(base, "density: 2500", "density: !mine 2500"));
  EXPECT_THAT(m, HasSubstr("found '2500' (tagged !mine)"));
  // quoted: as before
  m = dem_error(replaced(base, "density: 2500", "density: '2500'"));
  EXPECT_THAT(m, HasSubstr("found '2500' (a quoted string)"));
}
