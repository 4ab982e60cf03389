// SPDX-License-Identifier: GPL-3.0-or-later
// The shear-box measurements of analysis/rheology on hand-built grain sets with known answers:
// layer fluctuations with Bessel's correction, measured shear rate and volume fraction, and
// the split of the granular temperature into the fluid's part and the slip relative to it, and
// the coordination number and contact fabric from the force stage's sums.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "analysis/rheology.hpp"
#include "particles/particle_store.hpp"

using namespace gf;

namespace {

constexpr double kDensity = 2500;

// Box [0, 1]^2 x [0, 1]; measurement layer z in [0.2, 0.8), 6 layers of 0.1.
analysis::RheologyRegion region() {
  analysis::RheologyRegion r;
  r.z_lo = 0.2;
  r.z_hi = 0.8;
  r.bins = 6;
  r.area = 1.0;
  return r;
}

double layer_centre(int b) {
  return 0.25 + 0.1 * b;
}

analysis::RheologySample measure(const ParticleStore& p, const analysis::ContactSums& c = {}) {
  const double density[] = {kDensity};
  return analysis::measure_rheology(p, region(), c, density);
}

}  // namespace

// Each layer holds n equal grains, half at U_b + (d, 0, 0) and half at U_b - (d, 0, 0): the
// layer mean is U_b, every fluctuation is d, and the unbiased estimate of <v'^2> from n grains
// whose mean is taken from themselves is n / (n - 1) d^2. Grains outside the layer (z < 0.2,
// z >= 0.8) with wild velocities must not count.
TEST(Rheology, LayerFluctuationsWithBesselsCorrection) {
  ParticleStore p;
  const int n = 4;
  const double d = 0.3, r = 0.01;
  std::int64_t id = 0;
  for (int b = 0; b < 6; ++b)
    for (int k = 0; k < n; ++k) {
      const double u = 2.0 * layer_centre(b) - 1.0;  // any layer velocity
      const double sign = k % 2 == 0 ? 1.0 : -1.0;
      p.add_sphere(id++, 0, r, kDensity, {0.1 + 0.2 * k, 0.5, layer_centre(b) + 0.01 * sign},
                   {u + sign * d, 0.7, -0.2});
    }
  p.add_sphere(id++, 0, r, kDensity, {0.5, 0.5, 0.1}, {50, 50, 50});
  p.add_sphere(id++, 0, r, kDensity, {0.5, 0.5, 0.8}, {-50, 50, 50});

  const auto s = measure(p);
  const double mass = kDensity * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double bessel = static_cast<double>(n) / (n - 1);
  EXPECT_EQ(s.grains, 6 * n);
  EXPECT_NEAR(s.temperature, bessel * d * d / 3, 1e-14);
  // sigma_s = (1/V) sum m v'v': only the xx component; V = 0.6 m^3
  EXPECT_NEAR(s.streaming.a[0][0], bessel * 6 * n * mass * d * d / 0.6, 1e-12);
  EXPECT_NEAR(s.streaming.a[1][1], 0.0, 1e-14);
  EXPECT_NEAR(s.streaming.a[0][2], 0.0, 1e-14);
  EXPECT_NEAR(s.volume_fraction, 6 * n * mass / kDensity / 0.6, 1e-15);
  // No fluid field: the whole temperature is slip, none is the fluid's.
  EXPECT_EQ(s.fluid_temperature, 0.0);
  EXPECT_EQ(s.slip_temperature, s.temperature);
}

// Grains moving exactly with the simple shear u_x = gamma_dot z: the least-squares slope is the
// rate (to round-off) whatever the scatter of the grains in z.
TEST(Rheology, MeasuredShearRateOfAnExactProfile) {
  ParticleStore p;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0, 1);
  const double rate = 37.5;
  for (int i = 0; i < 200; ++i) {
    const double z = 0.2 + 0.6 * u01(rng);
    p.add_sphere(i, 0, 0.002 + 0.004 * u01(rng), kDensity, {u01(rng), u01(rng), z},
                 {rate * (z - 0.5), 0, 0});
  }
  EXPECT_NEAR(measure(p).shear_rate, rate, 1e-10 * rate);
}

// Grains of unequal masses whose velocity fluctuations are those of the fluid at them (a
// streak of the fluid carries them): all of T is the fluid's, the slip temperature is zero.
// Grains in a fluid uniform over each layer: T_f = 0 and all of T is slip. Both hold for any
// layer means of grains and fluid and any mass weights.
TEST(Rheology, TemperatureSplitsIntoFluidAndSlip) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const bool carried : {true, false}) {
    ParticleStore p;
    const int f = p.add_field("fluid_velocity", FieldType::Vec3, "m/s", 0);
    for (int i = 0; i < 300; ++i) {
      const double z = 0.2 + 0.3 * (u(rng) + 1);
      const double b = std::floor((z - 0.2) / 0.1);  // the layer: constant means over it
      const Vec3 layer{3 * b, -b, 0.5 * b};
      const Vec3 fluid_mean{2 * b + 1, 0.1, -b};
      const Vec3 fluct{0.2 * u(rng), 0.1 * u(rng), 0.05 * u(rng)};
      p.add_sphere(i, 0, 0.003 * (1.5 + u(rng)), kDensity, {0.5 + 0.4 * u(rng), 0.5, z},
                   layer + fluct);
      p.get<Vec3>(f)[i] = carried ? fluid_mean + fluct : fluid_mean;
    }
    const auto s = measure(p);
    ASSERT_GT(s.temperature, 1e-4);
    if (carried) {
      EXPECT_NEAR(s.slip_temperature, 0.0, 1e-14);
      EXPECT_NEAR(s.fluid_temperature / s.temperature, 1.0, 1e-12);
    } else {
      EXPECT_NEAR(s.fluid_temperature, 0.0, 1e-14);
      EXPECT_NEAR(s.slip_temperature / s.temperature, 1.0, 1e-12);
    }
  }
}

// Three pairs counted in the layer, two with the normal along the compressive axis of simple
// shear (1, 0, -1)/sqrt 2 and one along y, among ten grains: Z = 2 x 3 / 10, F = sum nn / 3 with
// F_xx = F_yy = F_zz = 1/3, F_xz = -1/3, and its major axis in the x-z plane at -45 degrees.
// The virial passes through unchanged (divided by the layer's volume).
TEST(Rheology, CoordinationAndFabricFromTheContactSums) {
  ParticleStore p;
  for (int k = 0; k < 10; ++k)
    p.add_sphere(k, 0, 0.01, kDensity, {0.05 + 0.1 * k, 0.5, 0.3 + 0.04 * k}, {0, 0, 0});
  p.add_sphere(10, 0, 0.01, kDensity, {0.5, 0.5, 0.9}, {0, 0, 0});  // outside the layer
  analysis::ContactSums c;
  const double h = 1 / std::sqrt(2.0);
  const Vec3 normals[] = {{h, 0, -h}, {-h, 0, h}, {0, 1, 0}};
  for (const Vec3& n : normals) c.normals = c.normals + outer(n, n);
  c.virial.a[0][2] = -0.06;
  const auto s = measure(p, c);
  EXPECT_EQ(s.grains, 10);
  EXPECT_EQ(s.contacts, 3);
  EXPECT_NEAR(s.coordination, 0.6, 1e-15);
  EXPECT_NEAR(s.fabric.a[0][0], 1.0 / 3, 1e-15);
  EXPECT_NEAR(s.fabric.a[1][1], 1.0 / 3, 1e-15);
  EXPECT_NEAR(s.fabric.a[2][2], 1.0 / 3, 1e-15);
  EXPECT_NEAR(s.fabric.a[0][2], -1.0 / 3, 1e-15);
  EXPECT_NEAR(s.fabric_angle, -45.0, 1e-12);
  EXPECT_NEAR(s.collisional.a[0][2], -0.06 / region().volume(), 1e-15);

  // No contacts: a zero fabric and Z = 0, not 0/0.
  const auto none = measure(p);
  EXPECT_EQ(none.contacts, 0);
  EXPECT_EQ(none.coordination, 0.0);
  EXPECT_EQ(none.fabric_angle, 0.0);
  EXPECT_FALSE(std::isnan(none.fabric.a[0][0]));
}
