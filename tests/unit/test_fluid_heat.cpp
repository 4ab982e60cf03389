// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the fluid's temperature (src/fluid/fv/heat_transport): exact steady profiles
// (conduction between walls, the exchange-limited channel), the decay of a diffusing mode, the
// energy balance of the box faces and the particle source, boundedness, and bad settings.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "fluid/fv/heat_transport.hpp"
#include "fluid/fv/navier_stokes.hpp"

using namespace gf;
using namespace gf::fluid;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A column of n cells along `axis` (length len), periodic across it, 3D.
Grid column(int axis, int n, double len) {
  Grid g;
  g.n = {1, 1, 1};
  g.n[axis] = n;
  g.h = {0.01, 0.01, 0.01};
  g.h[axis] = len / n;
  g.periodic = {true, true, true};
  g.periodic[axis] = false;
  return g;
}

FluidSettings air_like(const Grid& g, int axis) {
  FluidSettings s;
  s.density = 1.2;
  s.dynamic_viscosity = 1.8e-5;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      s.boundary[box_face_index(a, side)] =
          g.periodic[a] ? BoundaryCondition::periodic() : BoundaryCondition::no_slip();
  (void)axis;
  return s;
}

HeatSettings heat(double cp, double k) {
  HeatSettings h;
  h.heat_capacity = cp;
  h.thermal_conductivity = k;
  h.boundary_temperature.fill(kNaN);
  return h;
}

}  // namespace

// Quiescent fluid between walls at 300 K and 400 K: the steady profile is linear, and the
// discrete one is exactly linear too (central differences, walls half a cell from the first
// centres): every cell centre within round-off of T(z), and the heat through both walls equal.
TEST(FluidHeat, ConductionBetweenWallsIsLinear) {
  const Grid g = column(2, 8, 0.08);
  const VolumeAveragedNS flow(g, air_like(g, 2));
  HeatSettings hs = heat(1000.0, 0.5);
  hs.boundary_temperature[box_face_index(2, 0)] = 300.0;
  hs.boundary_temperature[box_face_index(2, 1)] = 400.0;
  FluidHeat fh(flow, hs, 300.0);
  HeatStepReport r;
  for (int n = 0; n < 20; ++n) r = fh.step(10.0, flow);  // alpha t / L^2 ~ 0.4 per step
  for (int k = 0; k < 8; ++k) {
    const double z = (k + 0.5) * 0.01;
    EXPECT_NEAR(fh.temperature()[k], 300.0 + 100.0 * z / 0.08, 1e-7) << k;
  }
  // Steady: what enters at the hot wall leaves at the cold one (k dT/dz A = 0.5 * 1250 * 1e-4).
  EXPECT_NEAR(r.boundary_heat, 0.0, 1e-8);
  EXPECT_NEAR(fh.mean_temperature(flow), 350.0, 1e-7);
}

// A sine mode of wavelength L in a periodic box decays as exp(-alpha k^2 t) (alpha = k_f /
// (rho c_p)). Backward Euler with dt = 0.01 tau and central differences on 32 cells per
// wavelength: the semi-discrete decay rate is alpha (2/h sin(k h / 2))^2, 0.3 % slower than the
// exact one, and backward Euler adds about dt / (2 tau) = 0.5 % decay per tau: after one tau the
// amplitude within 1 % of exp(-1).
TEST(FluidHeat, PeriodicModeDecaysAtTheDiffusionRate) {
  Grid g = column(0, 32, 0.32);
  g.periodic = {true, true, true};
  FluidSettings fs = air_like(g, 0);
  const VolumeAveragedNS flow(g, fs);
  const double rho_c = 1.2 * 1000.0, k_f = 0.03, alpha = k_f / rho_c;
  const double kw = 2.0 * std::numbers::pi / 0.32, tau = 1.0 / (alpha * kw * kw);
  FluidHeat fh(flow, heat(1000.0, k_f), 0.0);
  std::vector<double> t0(32);
  for (int i = 0; i < 32; ++i) t0[i] = 300.0 + 10.0 * std::sin(kw * (i + 0.5) * 0.01);
  fh.set_temperature(t0);
  const double e0 = fh.energy(flow);
  for (int n = 0; n < 100; ++n) fh.step(0.01 * tau, flow);
  double amp = 0.0;
  for (int i = 0; i < 32; ++i)
    amp += 2.0 / 32.0 * (fh.temperature()[i] - 300.0) * std::sin(kw * (i + 0.5) * 0.01);
  EXPECT_NEAR(amp / 10.0, std::exp(-1.0), 0.01 * std::exp(-1.0));
  // A closed box keeps its heat, up to the solver's tolerance (relative residual 1e-12 per step).
  EXPECT_NEAR(fh.energy(flow), e0, 100 * 1e-12 * e0);
}

// Uniform flow through a channel (velocity inlet at 350 K, pressure outlet) over a fixed bed
// that exchanges heat at K (T_p - T) with grains at 300 K, no conduction: rho c U dT/dx =
// K (T_p - T). First-order upwind gives exactly T_i = (r T_{i-1} + K T_p) / (r + K), r = rho c U
// / h, which tends to T_p + (T_in - T_p) exp(-K x / (rho c U)) as h -> 0; at steady state the heat
// the grains take equals what the flow brings in minus what it carries out.
TEST(FluidHeat, ExchangeLimitedChannelAndItsEnergyBalance) {
  const int n = 40;
  const Grid g = column(0, n, 0.4);
  FluidSettings fs = air_like(g, 0);
  const double u_in = 0.5;
  fs.boundary[box_face_index(0, 0)] = BoundaryCondition::velocity_inlet(Vec3{u_in, 0, 0});
  fs.boundary[box_face_index(0, 1)] = BoundaryCondition::pressure_outlet(0.0);
  VolumeAveragedNS flow(g, fs);
  flow.set_velocity([&](const Vec3&) { return Vec3{u_in, 0, 0}; });
  HeatSettings hs = heat(1000.0, 0.0);
  hs.boundary_temperature[box_face_index(0, 0)] = 350.0;
  hs.convection = Convection::Upwind;
  FluidHeat fh(flow, hs, 300.0);
  const double rho_c = 1200.0, kx = 2000.0, t_p = 300.0;  // K in W/(m^3 K)
  std::vector<double> q(n, kx * t_p), k(n, kx);
  fh.set_source(q, k);
  HeatStepReport r;
  for (int s = 0; s < 400; ++s) r = fh.step(0.01, flow);  // 5 flow-through times
  const double rr = rho_c * u_in / 0.01;
  double expect = 350.0;
  for (int i = 0; i < n; ++i) {
    expect = (rr * expect + kx * t_p) / (rr + kx);
    EXPECT_NEAR(fh.temperature()[i], expect, 1e-8) << i;
    // The continuous profile, within the first-order error K h / (2 rho c U) of the upwinding.
    const double x = (i + 1) * 0.01;
    EXPECT_NEAR(fh.temperature()[i], t_p + 50.0 * std::exp(-kx * x / (rho_c * u_in)), 0.6) << i;
  }
  EXPECT_NEAR(r.boundary_heat + r.particle_heat, 0.0, 1e-7 * std::abs(r.particle_heat));
  EXPECT_LT(r.particle_heat, 0.0);  // the fluid gives heat to the colder grains
  for (double t : fh.temperature()) {
    EXPECT_LE(t, 350.0);
    EXPECT_GE(t, 300.0);
  }
}

// A hot slug carried around a periodic box by a uniform flow: implicit upwinding keeps it
// within its initial range (no over- or undershoot, whatever the Courant number C) and the box's
// heat is conserved; each Fourier mode e^{i k x} of the slug is multiplied per step by exactly
// G = 1 / (1 + C (1 - e^{-i k h})) (von Neumann), which fixes the phase (where the slug is) and
// the amplitude (how much it has spread) of the first mode after 30 steps at C = 2.5: a check of
// the whole discrete operator, periodic link included, to round-off.
TEST(FluidHeat, PeriodicAdvectionIsBoundedConservativeAndExact) {
  Grid g = column(0, 20, 0.2);
  g.periodic = {true, true, true};
  VolumeAveragedNS flow(g, air_like(g, 0));
  flow.set_velocity([](const Vec3&) { return Vec3{1.0, 0, 0}; });
  HeatSettings hs = heat(1000.0, 0.0);
  hs.convection = Convection::Upwind;
  FluidHeat fh(flow, hs, 300.0);
  std::vector<double> t0(20, 300.0);
  for (int i = 5; i < 9; ++i) t0[i] = 400.0;
  fh.set_temperature(t0);
  const auto first_mode = [](std::span<const double> t) {
    std::complex<double> m{};
    for (int i = 0; i < 20; ++i)
      m += t[i] * std::exp(std::complex<double>(0, -2 * std::numbers::pi * i / 20));
    return m;
  };
  const std::complex<double> m0 = first_mode(t0);
  const double e0 = fh.energy(flow);
  const int steps = 30;
  const double c = 2.5;
  for (int s = 0; s < steps; ++s) fh.step(0.025, flow);  // C = u dt / h = 2.5
  EXPECT_NEAR(fh.energy(flow), e0, steps * 1e-12 * e0);  // (solver tolerance per step)
  for (double t : fh.temperature()) {
    EXPECT_LE(t, 400.0 + 1e-9);
    EXPECT_GE(t, 300.0 - 1e-9);
  }
  const std::complex<double> gain =
      1.0 / (1.0 + c * (1.0 - std::exp(std::complex<double>(0, -2 * std::numbers::pi / 20))));
  const std::complex<double> expect = m0 * std::pow(gain, steps);
  const std::complex<double> got = first_mode(fh.temperature());
  EXPECT_NEAR(got.real(), expect.real(), 1e-8 * std::abs(m0));
  EXPECT_NEAR(got.imag(), expect.imag(), 1e-8 * std::abs(m0));
}

// Van Leer's face temperatures (the default) are validated against the same channel and a
// carried pulse in tests/validation/test_cfd_dem_heat_validation.cpp.

TEST(FluidHeat, RefusesAnInletWithoutTemperatureAndBadProperties) {
  const Grid g = column(0, 4, 0.4);
  FluidSettings fs = air_like(g, 0);
  fs.boundary[box_face_index(0, 0)] = BoundaryCondition::velocity_inlet(Vec3{0.1, 0, 0});
  fs.boundary[box_face_index(0, 1)] = BoundaryCondition::pressure_outlet(0.0);
  const VolumeAveragedNS flow(g, fs);
  EXPECT_THROW(FluidHeat(flow, heat(1000.0, 0.02), 300.0), Error);
  HeatSettings ok = heat(1000.0, 0.02);
  ok.boundary_temperature[box_face_index(0, 0)] = 320.0;
  EXPECT_NO_THROW(FluidHeat(flow, ok, 300.0));
  EXPECT_THROW(FluidHeat(flow, heat(0.0, 0.02), 300.0), Error);
  EXPECT_THROW(FluidHeat(flow, heat(1000.0, -1.0), 300.0), Error);
  HeatSettings central = ok;
  central.convection = Convection::Central;  // unbounded: refused
  EXPECT_THROW(FluidHeat(flow, central, 300.0), Error);
}
