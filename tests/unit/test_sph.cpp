// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the continuum module: the SPH kernel, the rheologies and their registry, the
// solver's set-up checks, the `continuum:` block's reader.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <tuple>

#include "continuum/rheology_registry.hpp"
#include "continuum/sph.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "io/input/parse_continuum.hpp"
#include "io/restart/h5.hpp"
#include "simulation/continuum_case.hpp"
#include "temp_dir.hpp"

namespace gf::continuum {
namespace {

TEST(SphKernel, NormalisedAndDerivativeMatchesDifferences) {
  for (int dim : {2, 3}) {
    const WendlandC2 w(dim, 0.7);
    // integral of W over its support by the midpoint rule in r
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double r = (i + 0.5) * w.support() / n;
      const double shell = dim == 2 ? 2 * std::numbers::pi * r : 4 * std::numbers::pi * r * r;
      sum += w.value(r) * shell * w.support() / n;
    }
    EXPECT_NEAR(sum, 1.0, 1e-7) << dim << "D";
    for (double r : {0.05, 0.3, 0.9, 1.3}) {
      const double e = 1e-6;
      EXPECT_NEAR(w.derivative(r), (w.value(r + e) - w.value(r - e)) / (2 * e),
                  1e-6 * std::fabs(w.derivative(0.7)));
    }
    EXPECT_EQ(w.value(w.support()), 0.0);
    EXPECT_EQ(w.derivative(w.support() * 1.01), 0.0);
  }
}

TEST(ContinuumRheology, MuIFrictionViscosityAndCap) {
  const auto p = prepare_rheology(
      "mu_i", {{"grain_diameter", 1e-3}, {"grain_density", 2500}, {"max_viscosity", 100}});
  EXPECT_DOUBLE_EQ(p.mu_s, 0.382);  // Jop et al. (2006) defaults
  // I = gamma_dot d sqrt(rho_s / p): gamma_dot = 10, p = 25 -> I = 0.1
  const double mu = MuI::friction(0.1, p);
  EXPECT_NEAR(mu, 0.382 + (0.643 - 0.382) * 0.1 / (0.279 + 0.1), 1e-15);
  EXPECT_NEAR(apparent_viscosity(10.0, 25.0, p), mu * 25.0 / 10.0, 1e-12);
  EXPECT_NEAR(MuI::inertial_number_for(mu, p), 0.1, 1e-12);
  EXPECT_EQ(apparent_viscosity(1e-6, 250.0, p), 100.0);  // capped
  EXPECT_EQ(apparent_viscosity(0.0, 250.0, p), 100.0);
  EXPECT_EQ(apparent_viscosity(10.0, -5.0, p), 0.0);  // no pressure, no friction
  const auto n = prepare_rheology("newtonian", {{"viscosity", 1e-3}});
  EXPECT_EQ(apparent_viscosity(123.0, 4.0, n), 1e-3);
}

TEST(ContinuumRheology, RegistryRefusesBadParameters) {
  EXPECT_THROW(prepare_rheology("bingham", {}), Error);
  EXPECT_THROW(prepare_rheology("newtonian", {}), Error);  // viscosity is required
  EXPECT_THROW(prepare_rheology("newtonian", {{"viscosity", -1}}), Error);
  EXPECT_THROW(prepare_rheology("newtonian", {{"viscosity", 1}, {"mu_s", 1}}), Error);
  EXPECT_THROW(
      prepare_rheology(
          "mu_i",
          {{"grain_diameter", 1e-3}, {"grain_density", 2500}, {"max_viscosity", 1}, {"mu_s", 0.7}}),
      Error);  // mu_2 = 0.643 < mu_s
  EXPECT_NE(find_rheology("mu_i"), nullptr);
  EXPECT_EQ(rheology_infos().size(), Rheologies::size);
}

SphConfig small_tank() {
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {-0.03, -0.03, 0};
  c.domain.hi = {0.13, 0.2, 0};
  c.gravity = {0, -9.81, 0};
  c.spacing = 0.01;
  c.density = 1000;
  c.sound_speed = 20;
  c.rheology = prepare_rheology("newtonian", {{"viscosity", 1e-3}});
  c.blocks.push_back({{0, 0, 0}, {0.1, 0.1, 0}, {}, true});
  SphWall floor;
  floor.name = "floor";
  floor.lo = {-0.03, -0.03, 0};
  floor.hi = {0.13, 0, 0};
  c.walls.push_back(floor);
  return c;
}

TEST(SphSolver, BuildsLatticeWithHydrostaticStart) {
  const SphSolver s(small_tank());
  EXPECT_EQ(s.n_fluid(), 100u);
  EXPECT_EQ(s.particles().size() - s.n_fluid(), 16u * 3u);
  // bottom row (y = 0.005): p = rho g (0.1 - 0.005)
  const auto& p = s.particles();
  for (std::size_t i = 0; i < s.n_fluid(); ++i) {
    if (p.x[i].y < 0.01) {
      EXPECT_NEAR(p.p[i], 1000 * 9.81 * 0.095, 1e-9);
    }
  }
  EXPECT_NEAR(s.density_of(s.pressure_of(1003.0)), 1003.0, 1e-9);
}

TEST(SphSolver, RefusesOverlapsWallsOutsideAndShortPeriods) {
  auto c = small_tank();
  c.blocks.push_back({{0.05, 0.05, 0}, {0.1, 0.1, 0}, {}, false});
  EXPECT_THROW(SphSolver{c}, InputError);
  c = small_tank();
  c.walls[0].lo.y = -0.05;  // below domain.min
  EXPECT_THROW(SphSolver{c}, InputError);
  c = small_tank();
  c.domain.periodic[0] = true;
  c.domain.hi.x = c.domain.lo.x + 0.04;  // below 2 x 2h = 0.052
  EXPECT_THROW(SphSolver{c}, Error);
}

TEST(SphSolver, CylinderShellIsHollowAndParticlesLeavingAreRemoved) {
  auto c = small_tank();
  SphWall cyl;
  cyl.name = "post";
  cyl.shape = SphWall::Shape::Cylinder;
  cyl.center = {0.06, 0.16, 0};
  cyl.radius = 0.03;
  cyl.thickness = 0.015;
  c.walls.push_back(cyl);
  c.blocks[0].velocity = {3.0, 0, 0};  // the block runs out through x = 0.13
  SphSolver s(c);
  const auto& p = s.particles();
  std::size_t in_post = 0;
  for (std::size_t i = s.n_fluid(); i < p.size(); ++i)
    if (p.wall_index[i] == 1) {
      ++in_post;
      const double r = norm(p.x[i] - cyl.center);
      EXPECT_LE(r, 0.03 + 1e-12);
      EXPECT_GE(r, 0.015 - 1e-12);
    }
  EXPECT_GT(in_post, 10u);
  while (s.time() < 0.1) s.step();
  EXPECT_GT(s.n_removed(), 0u);
  EXPECT_EQ(s.n_fluid() + s.n_removed(), 100u);
  for (std::size_t i = 0; i < s.n_fluid(); ++i) EXPECT_LE(s.particles().x[i].x, 0.13);
}

}  // namespace
}  // namespace gf::continuum

namespace gf::input {
namespace {

const char* kContinuumBlock = R"(continuum:
  method: sph
  dimension: 2
  domain: {min: [0, 0], max: [1, 1]}
  gravity: [0, -9.81]
  spacing: 0.05
  density: 1500
  rheology: {model: mu_i, grain_diameter: 1.0e-3, grain_density: 2500, max_viscosity: 100}
  time: {end: 0.1, viscous: implicit}
  blocks:
    - {box: {min: [0.1, 0.1], max: [0.3, 0.3]}, hydrostatic: true}
  walls:
    - {name: floor, box: {min: [0, 0], max: [1, 0.1]}}
)";

ContinuumCase parse_text(const std::string& text) {
  const auto root = YamlNode::parse_text(text, "case.yaml");
  return parse_continuum(YamlMap(root, {"continuum"}).at("continuum"));
}

std::string error_of(const std::string& text) {
  try {
    parse_text(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ContinuumInput, ReadsTheBlockWithDefaults) {
  const auto c = parse_text(kContinuumBlock);
  EXPECT_EQ(c.rheology, "mu_i");
  EXPECT_TRUE(c.sph.implicit_viscosity);
  EXPECT_DOUBLE_EQ(c.sph.smoothing_ratio, 1.3);
  EXPECT_DOUBLE_EQ(c.sph.rheology.mu_s, 0.382);
  // c0 = 10 sqrt(2 g H), H = 0.2 m the block's height along gravity
  EXPECT_NEAR(c.sph.sound_speed, 10 * std::sqrt(2 * 9.81 * 0.2), 1e-12);
  ASSERT_EQ(c.sph.walls.size(), 1u);
  EXPECT_EQ(c.sph.walls[0].name, "floor");
}

TEST(ContinuumInput, ErrorsNameLineKeyAndExpectation) {
  std::string text = kContinuumBlock;
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  EXPECT_THAT(error_of(with("spacing:", "spacng:")),
              ::testing::HasSubstr("case.yaml:6:3: error: continuum.spacng: unknown key"));
  EXPECT_THAT(error_of(with("max_viscosity: 100", "max_viscosity: -1")),
              ::testing::HasSubstr("continuum.rheology.max_viscosity: expected a number"));
  EXPECT_THAT(error_of(with(", max_viscosity: 100", "")),
              ::testing::HasSubstr("rheology 'mu_i' needs 'max_viscosity'"));
  EXPECT_THAT(error_of(with("model: mu_i", "model: bingham")),
              ::testing::HasSubstr("expected a rheology: newtonian, mu_i"));
  EXPECT_THAT(error_of(with("viscous: implicit", "viscous: sometimes")),
              ::testing::HasSubstr("continuum.time.viscous"));
  EXPECT_THAT(error_of(with("max: [1, 1]}", "max: [1, 1, 1]}")),
              ::testing::HasSubstr("expected 2 components in a 2D case"));
}

}  // namespace
}  // namespace gf::input

namespace gf {
namespace {

// A continuum run continued from a checkpoint ends bit-identically to one that ran straight
// through, in a new folder and with --append in its own (series and ParaView files as the
// straight run's), explicit and implicit viscosity.
TEST(ContinuumRestart, ContinuesBitIdentically) {
  for (const bool implicit : {false, true}) {
    test::TempDir tmp;
    std::string text = R"(continuum:
  method: sph
  dimension: 2
  domain: {min: [-0.02, -0.02], max: [0.3, 0.15]}
  gravity: [0, -9.81]
  spacing: 0.005
  density: 1500
  rheology: {model: mu_i, grain_diameter: 1.0e-3, grain_density: 2500, max_viscosity: 200}
  time: {end: 1.0, viscous: VISCOUS}
  blocks:
    - {box: {min: [0, 0], max: [0.05, 0.05]}, hydrostatic: true}
  walls:
    - {name: floor, box: {min: [-0.02, -0.02], max: [0.3, 0]}}
    - {name: left, box: {min: [-0.02, 0], max: [0, 0.1]}}
  output: {vtk_every: 0.002, series_every: 0.0005, checkpoint_every: 0.003}
)";
    text.replace(text.find("VISCOUS"), 7, implicit ? "implicit" : "explicit");
    auto c = input::parse_text(text);
    c.name = "restart";
    c.file = "case.yaml";
    RunOptions straight;
    straight.output = tmp.path() / "straight";
    straight.steps = 120;
    ASSERT_EQ(run_continuum_case(c, {}, straight), 0);
    RunOptions first = straight;
    first.output = tmp.path() / "split";
    first.steps = 50;
    ASSERT_EQ(run_continuum_case(c, {}, first), 0);
    RunOptions fresh;
    fresh.output = tmp.path() / "fresh";
    fresh.restart = tmp.path() / "split" / "sph_checkpoint_final.h5";
    fresh.steps = 70;
    ASSERT_EQ(run_continuum_case(c, {}, fresh), 0);
    RunOptions append = fresh;
    append.output = tmp.path() / "split";
    append.append = true;
    ASSERT_EQ(run_continuum_case(c, {}, append), 0);
    auto state = [](const std::filesystem::path& f) {
      auto h = io::h5::File::open_read(f);
      return std::make_tuple(h.read_vec3("particles/x"), h.read_vec3("particles/v"),
                             h.read_double("particles/rho"), h.read_int_attribute("/", "steps"),
                             h.read_double_attribute("/", "time"));
    };
    const auto ref = state(tmp.path() / "straight" / "sph_checkpoint_final.h5");
    EXPECT_EQ(std::get<3>(ref), 120);
    EXPECT_TRUE(state(tmp.path() / "fresh" / "sph_checkpoint_final.h5") == ref) << implicit;
    EXPECT_TRUE(state(tmp.path() / "split" / "sph_checkpoint_final.h5") == ref) << implicit;
    EXPECT_EQ(read_text_file(tmp.path() / "split" / "sph_series.csv"),
              read_text_file(tmp.path() / "straight" / "sph_series.csv"));
    EXPECT_EQ(read_text_file(tmp.path() / "split" / "sph_particles.pvd"),
              read_text_file(tmp.path() / "straight" / "sph_particles.pvd"));
    // a checkpoint of another case is refused with a clear error
    auto other = c;
    other.sph.walls.pop_back();
    auto elsewhere = fresh;
    elsewhere.output = tmp.path() / "other";
    EXPECT_THROW(run_continuum_case(other, {}, elsewhere), InputError);
    EXPECT_FALSE(std::filesystem::exists(tmp.path() / "other"));  // nothing written
  }
}

}  // namespace
}  // namespace gf
