// SPDX-License-Identifier: GPL-3.0-or-later
// The resting overlap under sjkr cohesion (contact::equilibrium_overlap, cohesion.hpp) against the
// closed form for hooke and a bisection written out here for hertz; the rows and warnings it gives
// `grainflow check` (io/input/validate.cpp); the polygon-cohesion error quoting the value as
// written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

#include "case_builder.hpp"
#include "contact/registry.hpp"
#include "input_error.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/validate.hpp"

using namespace gf;
using namespace gf::contact;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double inf = std::numeric_limits<double>::infinity();
const Material glass{"glass", 2500, 1e7, 0.3};
const double e_star = 1e7 / (2 * (1 - 0.3 * 0.3));

PairCoeffs hooke(double k, double kc) {
  return prepare_pair("hooke", {&glass, &glass, 1e-3},
                      {{"restitution", 0.5},
                       {"friction", 0.5},
                       {"rolling_friction", 0.0},
                       {"stiffness", k},
                       {"tangential_stiffness_ratio", 2.0 / 7.0},
                       {"cohesion_energy_density", kc}});
}
PairCoeffs hertz(double kc) {
  return prepare_pair("hertz_mindlin", {&glass, &glass, 1e-3},
                      {{"restitution", 0.5},
                       {"friction", 0.5},
                       {"rolling_friction", 0.0},
                       {"cohesion_energy_density", kc}});
}

/// Root of g on [lo, hi] (g(lo) < 0 < g(hi)) by bisection to 1e-14 relative.
double bisect(const std::function<double(double)>& g, double lo, double hi) {
  for (int it = 0; it < 300 && hi - lo > 1e-14 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Contact area of two spheres of radius r (pair) or a sphere on a wall, written out.
double area(double r, bool wall, double delta) {
  return wall ? pi * delta * (2 * r - delta) : pi * (r * delta - 0.25 * delta * delta);
}

std::string derived(const input::CheckReport& report, const std::string& prefix) {
  for (const auto& [k, v] : report.derived)
    if (k.rfind(prefix, 0) == 0) return v;
  return "";
}
std::string warning_with(const input::CheckReport& report, const std::string& part) {
  for (const auto& w : report.warnings)
    if (w.find(part) != std::string::npos) return w;
  return "";
}

/// Two glass spheres of radius r (apart) above a glass floor, hertz_mindlin or hooke (k = 100
/// N/m) with cohesion k_c between all.
config::Case cohesive_case(const std::string& model, double kc, double r = 1e-3) {
  auto c = test::base_case(1e-6, 1e-3, {-0.02, -0.02, 0}, {0.02, 0.02, 0.02});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  std::map<std::string, double> prm{{"restitution", 0.5}, {"cohesion_energy_density", kc}};
  if (model == "hooke") prm["stiffness"] = 100;
  test::add_contact(c, "glass", "glass", model, prm);
  test::add_spheres(c, "glass", r, {{0, 0, 0.005}, {0, 0, 0.01}});
  test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
  return c;
}

}  // namespace

// hooke: k delta = k_c A gives a pair 4 (r - k / (pi k_c)) and a wall 2 r - k / (pi k_c) where
// positive; 0 below (repulsion wins from first touch), and a pair finds no balance short of
// coincident centres for k_c >= 2 k / (pi r). The bisection stops at 1e-15 of the overlap; the
// balance, F_e - k_c A with both terms ~k delta, loses ~eps k delta / (d(F_e - k_c A)/d delta
// delta) ~ 1e-14 relative here; 1e-10 leaves room for that only.
TEST(CohesionEquilibrium, HookeMatchesTheClosedForm) {
  const double k = 100, r = 1e-3;
  for (const bool wall : {false, true}) {
    const double kc_min = wall ? k / (2 * pi * r) : k / (pi * r);  // overlap 0 below
    const double kc_max = wall ? inf : 2 * k / (pi * r);           // pulled onto each other above
    for (const double f : {1.001, 1.05, 1.2, 1.5, 1.9, 3.0, 30.0}) {
      const double kc = f * kc_min;
      if (kc >= kc_max) continue;
      const double expected = wall ? 2 * r - k / (pi * kc) : 4 * (r - k / (pi * kc));
      const double got = equilibrium_overlap<HookeNormal>(hooke(k, kc), r, wall);
      EXPECT_NEAR(got, expected, 1e-10 * expected) << (wall ? "wall " : "pair ") << f;
    }
    EXPECT_EQ(equilibrium_overlap<HookeNormal>(hooke(k, 0.0), r, wall), 0.0);
    EXPECT_EQ(equilibrium_overlap<HookeNormal>(hooke(k, 0.999 * kc_min), r, wall), 0.0);
  }
  EXPECT_EQ(equilibrium_overlap<HookeNormal>(hooke(k, 2.001 * k / (pi * r)), r, false), inf);
  EXPECT_LT(equilibrium_overlap<HookeNormal>(hooke(k, 1.999 * k / (pi * r)), r, false), 2 * r);
  // On a wall the area vanishes as the sphere goes through it: there is always a balance.
  EXPECT_LT(equilibrium_overlap<HookeNormal>(hooke(k, 1e9), r, true), 2 * r);
}

// hertz: 4/3 E* sqrt(R*) delta^(3/2) = k_c A, bisected here on the formulas written out; the
// overlap over the radius does not depend on the radius; a pair finds no balance for
// k_c >= 8 E* / (3 pi) (at coincident centres 4/3 E* r = k_c pi r / 2).
TEST(CohesionEquilibrium, HertzMatchesABisection) {
  for (const bool wall : {false, true})
    for (const double r : {1e-3, 0.25})
      for (const double kc : {1e2, 1e4, 1e5, 1e6, 4e6}) {
        const double r_eff = wall ? r : 0.5 * r;
        auto g = [&](double d) {
          return 4.0 / 3.0 * e_star * std::sqrt(r_eff) * std::pow(d, 1.5) - kc * area(r, wall, d);
        };
        const double expected = bisect(g, 1e-300, 2 * r);
        const double got = equilibrium_overlap<HertzNormal>(hertz(kc), r, wall);
        EXPECT_NEAR(got, expected, 1e-10 * expected)
            << (wall ? "wall " : "pair ") << r << " " << kc;
        EXPECT_NEAR(got / r, equilibrium_overlap<HertzNormal>(hertz(kc), 1e-3, wall) / 1e-3, 1e-12);
      }
  const double kc_max = 8 * e_star / (3 * pi);
  EXPECT_EQ(equilibrium_overlap<HertzNormal>(hertz(1.001 * kc_max), 1e-3, false), inf);
  EXPECT_LT(equilibrium_overlap<HertzNormal>(hertz(0.999 * kc_max), 1e-3, false), 2e-3);
  EXPECT_LT(equilibrium_overlap<HertzNormal>(hertz(1e3 * kc_max), 1e-3, true), 2e-3);
  EXPECT_EQ(equilibrium_overlap<HertzNormal>(hertz(0.0), 1e-3, false), 0.0);
}

// cohesion_for_overlap is the inverse: the k_c it gives rests at the overlap asked.
TEST(CohesionEquilibrium, CohesionForOverlapIsTheInverse) {
  const double r = 2e-3;
  for (const bool wall : {false, true})
    for (const double x : {0.01, 0.1, 0.5}) {
      const double kc_hertz = cohesion_for_overlap<HertzNormal>(hertz(1.0), r, wall, x * r);
      EXPECT_NEAR(equilibrium_overlap<HertzNormal>(hertz(kc_hertz), r, wall), x * r, 1e-10 * x * r);
      const double kc_hooke = cohesion_for_overlap<HookeNormal>(hooke(100, 1.0), r, wall, x * r);
      EXPECT_NEAR(equilibrium_overlap<HookeNormal>(hooke(100, kc_hooke), r, wall), x * r,
                  1e-10 * x * r);
    }
}

// check: a row per cohesive pair (grains, grains on walls) with the resting overlap / r; a
// warning above 0.1; none of it without cohesion.
TEST(CohesionCheck, RowsAndWarningForALargeCohesion) {
  const double r = 1e-3;
  {  // k_c = 1e6: hertz pair at ~0.3 r, on a wall more
    const auto report = input::validate(cohesive_case("hertz_mindlin", 1e6, r));
    const std::string pair = derived(report, "resting overlap / r under cohesion, glass-glass");
    const std::string wall =
        derived(report, "resting overlap / r under cohesion, glass grains on glass walls");
    const double x_pair = equilibrium_overlap<HertzNormal>(hertz(1e6), r, false) / r;
    const double x_wall = equilibrium_overlap<HertzNormal>(hertz(1e6), r, true) / r;
    ASSERT_GT(x_pair, 0.1);
    EXPECT_EQ(pair.rfind(fmt::format("{:.3g} (", x_pair), 0), 0u) << pair;
    EXPECT_EQ(wall.rfind(fmt::format("{:.3g} (", x_wall), 0), 0u) << wall;
    const std::string w = warning_with(report, "of glass-glass grains (hertz_mindlin)");
    EXPECT_NE(w.find(fmt::format("overlap of {:.3g} x the radius", x_pair)), std::string::npos)
        << w;
    EXPECT_NE(w.find("LIGGGHTS"), std::string::npos) << w;
    const double kc_ok = cohesion_for_overlap<HertzNormal>(hertz(1.0), r, false, 0.1 * r);
    EXPECT_NE(w.find(fmt::format("{:.3g} J/m^3 or less", kc_ok)), std::string::npos) << w;
    EXPECT_NE(warning_with(report, "glass grains on glass walls (hertz_mindlin)"), "");
  }
  {  // k_c = 1e7 > 8 E* / (3 pi): no balance for a pair
    const auto report = input::validate(cohesive_case("hertz_mindlin", 1e7, r));
    EXPECT_EQ(derived(report, "resting overlap / r under cohesion, glass-glass").rfind("none", 0),
              0u);
    EXPECT_NE(warning_with(report, "are pulled onto each other"), "");
  }
  {  // a small k_c: a row, no warning
    const auto report = input::validate(cohesive_case("hertz_mindlin", 1e3, r));
    EXPECT_NE(derived(report, "resting overlap / r under cohesion, glass-glass"), "");
    EXPECT_EQ(warning_with(report, "cohesion"), "");
  }
  {  // hooke, k_c below k / (2 pi R*): repulsion from first touch
    const auto report = input::validate(cohesive_case("hooke", 0.5 * 100 / (pi * r), r));
    EXPECT_EQ(derived(report, "resting overlap / r under cohesion, glass-glass").rfind("0 (", 0),
              0u);
    EXPECT_EQ(warning_with(report, "cohesion"), "");
  }
  {  // k_c = 0: neither row nor warning
    const auto report = input::validate(cohesive_case("hertz_mindlin", 0.0, r));
    EXPECT_EQ(derived(report, "resting overlap"), "");
    EXPECT_EQ(warning_with(report, "cohesion"), "");
  }
}

// hooke's ratio grows with the radius (k_n fixed): the largest grain is the one reported.
TEST(CohesionCheck, HookeReportsTheRadiusWithTheLargestRatio) {
  const double k = 100, kc = 1.5 * k / (pi * 1e-3);
  auto c = cohesive_case("hooke", kc, 1e-3);
  test::add_spheres(c, "glass", 1.2e-3, {{0.01, 0, 0.005}});
  const auto report = input::validate(c);
  const std::string row = derived(report, "resting overlap / r under cohesion, glass-glass");
  EXPECT_NE(
      derived(report, "resting overlap / r under cohesion, glass-glass grains (r = 0.0012 m)"), "");
  const double x = equilibrium_overlap<HookeNormal>(hooke(k, kc), 1.2e-3, false) / 1.2e-3;
  EXPECT_EQ(row.rfind(fmt::format("{:.3g} (", x), 0), 0u) << row;
}

// The polygon error quotes the value as written (1.0e4), not as the double prints (10000), from
// the file or from --set.
TEST(CohesionCheck, PolygonErrorQuotesTheValueAsWritten) {
  const std::filesystem::path file =
      std::filesystem::path(GF_SOURCE_DIR) / "tests/data/bad_cases/cohesion_polygons.yaml";
  const std::string from_file =
      test::input_error_of([&] { input::validate(input::load_case(file)); });
  EXPECT_NE(from_file.find("found '1.0e4'"), std::string::npos) << from_file;
  const std::string from_set = test::input_error_of([&] {
    input::validate(input::load_case(
        file, {input::parse_override("contacts[0].cohesion_energy_density=2.50e4")}));
  });
  EXPECT_NE(from_set.find("found '2.50e4'"), std::string::npos) << from_set;
}
