// SPDX-License-Identifier: GPL-3.0-or-later
// Contact laws against hand computations; the restitution map and its inverse.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/registry.hpp"

using namespace gf;
using namespace gf::contact;

namespace {

Material glass{"glass", 2500, 1e7, 0.3};

ContactKinematics head_on(double overlap, double vn, double r_eff, double m_eff) {
  ContactKinematics k{};
  k.overlap = overlap;
  k.normal = {0, 0, 1};
  k.v_rel = {0, 0, vn};
  k.r_eff = r_eff;
  k.m_eff = m_eff;
  return k;
}

}  // namespace

TEST(ContactLaw, EffectiveModuli) {
  // E* = E / (2 (1 - nu^2)) for equal materials; G* = E / (4 (2 - nu)(1 + nu)).
  EXPECT_NEAR(effective_modulus(glass, glass), 1e7 / (2 * 0.91), 1e-6);
  EXPECT_NEAR(effective_shear_modulus(glass, glass), 1e7 / (4 * 1.7 * 1.3), 1e-6);
}

TEST(ContactLaw, HertzElasticForceByHand) {
  const PairCoeffs c =
      prepare_pair("hertz_mindlin", {&glass, &glass, 0.005}, {{"restitution", 1.0}});
  // R* = 2.5 mm, delta = 10 um: F = 4/3 * 5.4945e6 * sqrt(2.5e-3) * (1e-5)^1.5 = 0.0115843... N
  Vec3 xi{};
  const auto r = HertzMindlin::Law::evaluate(c, head_on(1e-5, 0.0, 2.5e-3, 1e-3), 1e-6, xi);
  const double expected = 4.0 / 3.0 * (1e7 / 1.82) * std::sqrt(2.5e-3) * std::pow(1e-5, 1.5);
  EXPECT_NEAR(r.force.z, expected, 1e-12 * expected);
  EXPECT_NEAR(r.normal_force, expected, 1e-12 * expected);
  EXPECT_EQ(r.force.x, 0.0);
}

TEST(ContactLaw, HookeForceAndDampingByHand) {
  const PairCoeffs c =
      prepare_pair("hooke", {&glass, &glass, 0.005}, {{"restitution", 0.5}, {"stiffness", 1000.0}});
  EXPECT_EQ(c.stiffness, 1000.0);
  const double zeta = c.damping_ratio;
  Vec3 xi{};
  // Approaching at 0.1 m/s (v_n = -0.1): F = k delta + 2 zeta sqrt(m k) 0.1.
  const auto r = Hooke::Law::evaluate(c, head_on(1e-4, -0.1, 2.5e-3, 2e-3), 1e-6, xi);
  EXPECT_NEAR(r.normal_force, 1000 * 1e-4 + 2 * zeta * std::sqrt(2e-3 * 1000) * 0.1, 1e-14);
  // Separating fast: the dashpot would pull, the force is clamped at zero.
  const auto s = Hooke::Law::evaluate(c, head_on(1e-6, 10.0, 2.5e-3, 2e-3), 1e-6, xi);
  EXPECT_EQ(s.normal_force, 0.0);
  EXPECT_EQ(s.force.z, 0.0);
}

TEST(ContactLaw, HookeStiffnessFromMaxOverlap) {
  // m* v^2 = k delta^2 with m* of two reference grains (r = 5 mm, rho = 2500).
  const PairCoeffs c =
      prepare_pair("hooke", {&glass, &glass, 0.005},
                   {{"restitution", 0.9}, {"max_overlap", 0.01}, {"reference_velocity", 2.0}});
  const double m_eff = 0.5 * 2500 * 4.0 / 3.0 * M_PI * 1.25e-7;
  EXPECT_NEAR(c.stiffness, m_eff * 4.0 / (5e-5 * 5e-5), 1e-9 * c.stiffness);
}

TEST(ContactLaw, CoulombCapAndHistoryRescaled) {
  PairCoeffs c =
      prepare_pair("hooke", {&glass, &glass, 0.005}, {{"restitution", 1.0}, {"stiffness", 1e4}});
  c.friction = 0.3;
  ContactKinematics k = head_on(1e-4, 0.0, 2.5e-3, 1e-3);
  k.v_rel = {1.0, 0, 0};  // sliding fast
  Vec3 xi{};
  const auto r = Hooke::Law::evaluate(c, k, 1e-3, xi);
  EXPECT_NEAR(std::hypot(r.force.x, r.force.y), 0.3 * r.normal_force, 1e-12);
  EXPECT_LT(r.force.x, 0.0);  // opposes the sliding
  // The spring alone now carries the capped force.
  EXPECT_NEAR(-c.kt_ratio * c.stiffness * xi.x, r.force.x, 1e-12);
}

TEST(ContactLaw, HistoryRotatesIntoTangentPlaneKeepingLength) {
  PairCoeffs c =
      prepare_pair("hooke", {&glass, &glass, 0.005}, {{"restitution", 1.0}, {"stiffness", 1e4}});
  c.friction = 100;
  ContactKinematics k = head_on(1e-4, 0.0, 2.5e-3, 1e-3);
  k.normal = normalized(Vec3{0.1, 0, 1});
  k.v_rel = {};
  Vec3 xi{1e-6, 0, 0};  // was tangent to the old normal (0,0,1)
  Hooke::Law::evaluate(c, k, 1e-3, xi);
  EXPECT_NEAR(dot(xi, k.normal), 0.0, 1e-20);
  EXPECT_NEAR(norm(xi), 1e-6, 1e-18);
}

TEST(ContactLaw, RollingTorqueOpposesRelativeRotation) {
  PairCoeffs c = prepare_pair("hertz_mindlin", {&glass, &glass, 0.005},
                              {{"restitution", 0.5}, {"friction", 0.5}, {"rolling_friction", 0.1}});
  ContactKinematics k = head_on(1e-5, 0.0, 2.5e-3, 1e-3);
  k.omega_rel = {0, 3.0, 0};
  Vec3 xi{};
  const auto r = HertzMindlin::Law::evaluate(c, k, 1e-6, xi);
  EXPECT_NEAR(r.rolling_torque.y, -0.1 * 2.5e-3 * r.normal_force, 1e-15);
  EXPECT_EQ(r.rolling_torque.x, 0.0);
}

class RestitutionMap : public ::testing::TestWithParam<double> {};

TEST_P(RestitutionMap, InverseIsExact) {
  const double e = GetParam();
  for (auto kind : {NormalKind::Linear, NormalKind::Hertz}) {
    const double zeta = damping_ratio_for_restitution(kind, e);
    EXPECT_NEAR(realised_restitution(kind, zeta), e, 1e-9) << "kind " << static_cast<int>(kind);
  }
}

INSTANTIATE_TEST_SUITE_P(Values, RestitutionMap, ::testing::Values(0.1, 0.3, 0.5, 0.7, 0.9, 0.99));

TEST(RestitutionMapLimits, ElasticAndLinearUnclamped) {
  EXPECT_EQ(damping_ratio_for_restitution(NormalKind::Hertz, 1.0), 0.0);
  EXPECT_NEAR(realised_restitution(NormalKind::Linear, 0.0), 1.0, 1e-6);
  EXPECT_NEAR(realised_restitution(NormalKind::Hertz, 0.0), 1.0, 1e-6);
  // Light damping: the clamp barely acts, the closed form exp(-pi z / sqrt(1 - z^2)) holds.
  const double z = 0.01;
  EXPECT_NEAR(realised_restitution(NormalKind::Linear, z),
              std::exp(-M_PI * z / std::sqrt(1 - z * z)), 2e-3);
}

TEST(Registry, ContactModelsListed) {
  const auto infos = model_infos();
  ASSERT_EQ(infos.size(), 2u);
  EXPECT_EQ(infos[0].key, "hooke");
  EXPECT_EQ(infos[1].key, "hertz_mindlin");
  EXPECT_NE(find_model("hertz_mindlin"), nullptr);
  EXPECT_EQ(find_model("nope"), nullptr);
}
