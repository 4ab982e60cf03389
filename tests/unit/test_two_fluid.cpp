// SPDX-License-Identifier: GPL-3.0-or-later
// Two-fluid model: closures against their sources, the algebraic temperature's balance, solids
// volume conservation (2D and 3D, substeps), the shared-pressure mixture continuity, and the
// settings' errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "continuum/two_fluid.hpp"
#include "core/error.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"

using namespace gf;
using namespace gf::continuum;
using ::testing::HasSubstr;

namespace {

constexpr double kPi = 3.14159265358979323846;

TwoFluidSettings air_beads(const char* closures = "syamlal") {
  TwoFluidSettings s;
  s.fluid.density = 1.2;
  s.fluid.dynamic_viscosity = 1.8e-5;
  s.fluid.gravity = {0.0, -9.81, 0.0};
  s.ktgf = prepare_ktgf(closures,
                        {{"restitution", 0.9}, {"grain_diameter", 5e-4}, {"grain_density", 2500.0}},
                        "lun_savage");
  if (std::string(closures) != "syamlal") s.temperature = GranularTemperature::Transport;
  s.dense = prepare_frictional("schaeffer_johnson_jackson");
  s.drag = cfd_dem::prepare_drag("gidaspow");
  return s;
}

fluid::Grid box(int dim, int n, double h) {
  fluid::Grid g;
  g.dimension = dim;
  g.n = {n, n, dim == 3 ? n : 1};
  g.h = {h, h, h};
  g.periodic = {true, false, dim == 3};
  return g;
}

void periodic_x(TwoFluidSettings& s, int dim) {
  s.fluid.boundary[0] = s.fluid.boundary[1] = fluid::BoundaryCondition::periodic();
  if (dim == 3) s.fluid.boundary[4] = s.fluid.boundary[5] = fluid::BoundaryCondition::periodic();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const gf::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// beta = a beta_p / V_p with the registry's per-grain coefficient, and the pressure and its
// slope from the KTGF set plus the Johnson-Jackson frictional pressure.
TEST(TwoFluid, ClosuresAreTheRegistryModels) {
  TwoFluidSettings s = air_beads();
  s.fluid.gravity = {};
  periodic_x(s, 2);
  TwoFluidModel m(box(2, 4, 2e-3), s);
  const double a = 0.55, theta = 1e-3, slip = 0.3;
  const auto c = m.closures(a, theta, 10.0, slip);
  cfd_dem::DragInput in;
  in.rho_f = 1.2;
  in.mu_f = 1.8e-5;
  in.eps = 1 - a;
  in.d_v = 5e-4;
  in.slip = {0, slip, 0};
  const double vp = kPi * 1.25e-10 / 6.0;
  EXPECT_NEAR(c.beta, a * cfd_dem::drag_force(s.drag.law, in, s.drag).beta / vp, 1e-9 * c.beta);
  // Ergun's form of Gidaspow below eps = 0.8, per unit volume.
  const double ergun = 150 * a * a * 1.8e-5 / ((1 - a) * 2.5e-7) + 1.75 * a * 1.2 * slip / 5e-4;
  EXPECT_NEAR(c.beta, ergun, 1e-9 * ergun);
  const double p = solids_pressure(a, theta, s.ktgf) + johnson_jackson_pressure(a, s.dense);
  EXPECT_NEAR(c.pressure, p, 1e-12 * p);
  EXPECT_DOUBLE_EQ(c.kinetic_pressure, solids_pressure(a, theta, s.ktgf));
  const double h = 1e-6;
  const auto pp = [&](double x) {
    return solids_pressure(x, theta, s.ktgf) + johnson_jackson_pressure(x, s.dense);
  };
  EXPECT_NEAR(c.pressure_slope, (pp(a + h) - pp(a - h)) / (2 * h), 1e-5 * c.pressure_slope);
  // Schaeffer's frictional viscosity (P_f sin(phi) / gamma_dot) added to the kinetic one.
  const double mu = solids_shear_viscosity(a, theta, s.ktgf) +
                    johnson_jackson_pressure(a, s.dense) * s.dense.sin_friction_angle / 10.0;
  EXPECT_NEAR(c.viscosity, mu, 1e-12 * mu);
}

// Gidaspow & Ettehadieh's particle pressure: its slope is the modulus G = 10^(b - c (1 - a)) Pa
// (4.1 Pa at a = 0.45 with the published b = 5.43, c = 8.76: the eq.'s own numbers), its value the
// integral of G from 0 (trapezoidal rule on 2e5 intervals: 1e-9), and the two-fluid model adds it
// to the solids pressure but not to the kinetic pressure (it is no fluctuation energy).
TEST(TwoFluid, ParticlePressureIsTheElasticModulusIntegral) {
  const auto pe = prepare_particle_pressure("gidaspow_ettehadieh");
  const auto modulus = [](double a) { return std::pow(10.0, 5.43 - 8.76 * (1.0 - a)); };
  EXPECT_NEAR(modulus(0.45), 4.09, 0.01);
  for (const double a : {0.05, 0.3, 0.45, 0.6}) {
    const int n = 200000;
    double integral = 0.5 * (modulus(0.0) + modulus(a));
    for (int i = 1; i < n; ++i) integral += modulus(a * i / n);
    integral *= a / n;
    EXPECT_NEAR(particle_pressure(a, pe), integral, 1e-9 * integral) << a;
    const double h = 1e-6;
    EXPECT_NEAR((particle_pressure(a + h, pe) - particle_pressure(a - h, pe)) / (2 * h), modulus(a),
                1e-6 * modulus(a))
        << a;
  }
  EXPECT_EQ(particle_pressure(0.0, pe), 0.0);
  TwoFluidSettings s = air_beads();
  s.frictional = false;
  periodic_x(s, 2);
  const double a = 0.45, theta = 1e-4;
  const auto without = TwoFluidModel(box(2, 4, 2e-3), s).closures(a, theta, 0.0, 0.0);
  s.particle_pressure = pe;
  const auto with = TwoFluidModel(box(2, 4, 2e-3), s).closures(a, theta, 0.0, 0.0);
  EXPECT_NEAR(with.pressure - without.pressure, particle_pressure(a, pe), 1e-12);
  EXPECT_DOUBLE_EQ(with.kinetic_pressure, without.kinetic_pressure);
  EXPECT_NEAR(with.pressure_slope - without.pressure_slope, modulus(a), 1e-5 * modulus(a));
  EXPECT_THROW(prepare_particle_pressure("elastic"), Error);
  EXPECT_THROW(prepare_particle_pressure("gidaspow_ettehadieh", {{"exponent", -1.0}}), Error);
}

// The algebraic temperature balances production and dissipation, for shear, compression and
// expansion, with and without gas damping; in pure shear it is ktgf_simple_shear's.
TEST(TwoFluid, AlgebraicTemperatureBalance) {
  TwoFluidSettings s = air_beads();
  periodic_x(s, 2);
  TwoFluidModel m(box(2, 4, 2e-3), s);
  const double a = 0.3, gd = 40.0;
  EXPECT_NEAR(m.algebraic_temperature(a, 0.0, 0.5 * gd * gd, 0.0),
              ktgf_simple_shear(a, gd, s.ktgf).temperature, 1e-12);
  for (const double tr : {-5.0, 0.0, 5.0})
    for (const double beta : {0.0, 300.0}) {
      const double dev = 0.5 * gd * gd;
      const double th = m.algebraic_temperature(a, tr, dev, beta);
      const KtgfProperties p = ktgf_properties(a, th, s.ktgf);
      const double production =
          -p.pressure * tr + 2 * p.shear_viscosity * dev + p.bulk_viscosity * tr * tr;
      const double sink = p.dissipation + 3 * beta * th;
      EXPECT_NEAR(production / sink, 1.0, 1e-10) << "tr " << tr << " beta " << beta;
    }
  // No production: the floor.
  EXPECT_EQ(m.algebraic_temperature(a, 0.0, 0.0, 0.0), s.min_temperature);
  EXPECT_EQ(m.algebraic_temperature(0.0, 0.0, 100.0, 0.0), s.min_temperature);
}

// A random suspension settling in a closed box (2D with a direct solver, 3D with conjugate
// gradients), algebraic and transported temperature: the solids volume is conserved to round-off,
// fractions stay in [0, a_max], and nothing is clipped.
TEST(TwoFluid, SolidsVolumeIsConserved) {
  for (const int dim : {2, 3})
    for (const char* closures : {"syamlal", "lun", "gidaspow"}) {
      TwoFluidSettings s = air_beads(closures);
      periodic_x(s, dim);
      const fluid::Grid g = box(dim, dim == 2 ? 10 : 6, 5e-3);
      TwoFluidModel m(g, s);
      std::mt19937 rng(7);
      std::uniform_real_distribution<double> u(0.0, 0.5);
      std::vector<double> a0(static_cast<std::size_t>(g.cell_count()));
      for (double& v : a0) v = u(rng);
      std::size_t k = 0;
      m.set_solids([&](const Vec3&) { return a0[k++]; }, 1e-4);
      const double v0 = m.solids_volume();
      double clipped = 0.0;
      for (int i = 0; i < 60; ++i) {
        const auto r = m.step(std::min(0.9 * m.stable_dt(), 1e-3));
        clipped += std::abs(r.clipped_volume);
      }
      EXPECT_NEAR(m.solids_volume() / v0, 1.0, 1e-12) << dim << "D " << closures;
      EXPECT_LT(clipped, 1e-14 * v0);
      double lo = 1, hi = 0;
      for (double a : m.solids_fraction()) {
        lo = std::min(lo, a);
        hi = std::max(hi, a);
      }
      EXPECT_GE(lo, 0.0);
      EXPECT_LE(hi, m.packing_fraction());
      EXPECT_NEAR(m.time(), 60 * 1e-3, 0.06);  // advanced (steps may be shorter than 1e-3)
      for (double th : m.granular_temperature()) EXPECT_TRUE(std::isfinite(th) && th > 0);
    }
}

// The shared pressure correction makes the mixture's volume flux divergence-free in a closed
// box: with the fluid and solids fluxes eps u_f + F, net zero through every horizontal plane.
TEST(TwoFluid, MixtureFluxIsDivergenceFree) {
  TwoFluidSettings s = air_beads();
  periodic_x(s, 2);
  const fluid::Grid g = box(2, 8, 5e-3);
  TwoFluidModel m(g, s);
  m.set_solids([](const Vec3& x) { return x.y > 0.02 ? 0.4 : 0.05; });
  for (int i = 0; i < 20; ++i) m.step(5e-4);
  // Through the plane between rows 3 and 4: the fluid's flow rate plus the solids' (their
  // fluxes per unit area times the face areas) vanish up to the pressure solver's tolerance.
  const double fluid_rate = m.fluid().flow_rate(1, 4);
  double solids_rate = 0.0;
  for (int i = 0; i < g.n[0]; ++i)
    solids_rate += m.solids_face_flux(1)[g.face_index(1, i, 4, 0)] * g.h.x * g.h.z;
  EXPECT_GT(std::abs(fluid_rate), 1e-9);  // the suspension is moving
  EXPECT_LT(std::abs(fluid_rate + solids_rate), 1e-8 * std::abs(fluid_rate));
}

// A step far above the stable one is split into substeps and still conserves the solids.
TEST(TwoFluid, LargeStepIsSubdivided) {
  TwoFluidSettings s = air_beads();
  periodic_x(s, 2);
  s.fluid.max_courant = 100.0;
  TwoFluidModel m(box(2, 8, 2e-3), s);
  m.set_solids([](const Vec3& x) { return x.y > 0.008 ? 0.3 : 0.0; });
  for (int i = 0; i < 20; ++i) m.step(1e-3);  // to speed up the free fall
  const double v0 = m.solids_volume();
  const auto r = m.step(50 * m.stable_dt());
  EXPECT_GT(r.substeps, 1);
  EXPECT_LE(r.solids_courant, s.max_courant);
  // What clipping added is accounted for, and it is small.
  EXPECT_NEAR((m.solids_volume() - r.clipped_volume) / v0, 1.0, 1e-12);
  EXPECT_LT(std::abs(r.clipped_volume), 1e-3 * v0);
}

TEST(TwoFluid, SettingsErrors) {
  const fluid::Grid g = box(2, 4, 1e-3);
  auto with = [&](const std::function<void(TwoFluidSettings&)>& edit) {
    TwoFluidSettings s = air_beads();
    periodic_x(s, 2);
    edit(s);
    return error_of([&] { TwoFluidModel m(g, s); });
  };
  EXPECT_EQ(with([](TwoFluidSettings&) {}), "");
  EXPECT_THAT(with([](TwoFluidSettings& s) { s.ktgf.restitution = 1.0; }),
              HasSubstr("restitution in [0, 1)"));
  EXPECT_THAT(with([](TwoFluidSettings& s) { s.drag = {}; }), HasSubstr("no drag law"));
  EXPECT_THAT(with([](TwoFluidSettings& s) {
                s.ktgf = prepare_ktgf(
                    "lun",
                    {{"restitution", 0.9}, {"grain_diameter", 5e-4}, {"grain_density", 2500.0}});
                s.temperature = GranularTemperature::Algebraic;
              }),
              HasSubstr("algebraic granular temperature needs the 'syamlal' closures"));
  EXPECT_THAT(with([](TwoFluidSettings& s) { s.specularity = 1.5; }),
              HasSubstr("specularity coefficient 1.5"));
  EXPECT_THAT(with([](TwoFluidSettings& s) { s.wall_restitution = -0.1; }),
              HasSubstr("wall restitution"));
  EXPECT_THAT(with([](TwoFluidSettings& s) { s.max_fraction = 0.7; }),
              HasSubstr("max_fraction 0.7"));
  EXPECT_THAT(with([](TwoFluidSettings& s) { s.dense = prepare_frictional("mu_i_switch"); }),
              HasSubstr("needs the 'mu_i' rheology"));
  EXPECT_THAT(with([](TwoFluidSettings& s) {
                s.fluid.boundary[0] = s.fluid.boundary[1] = fluid::BoundaryCondition::no_slip();
              }),
              HasSubstr("periodic"));
  // Initial fractions beyond the cap.
  TwoFluidSettings s = air_beads();
  periodic_x(s, 2);
  TwoFluidModel m(g, s);
  EXPECT_THAT(error_of([&] { m.set_solids([](const Vec3&) { return 0.7; }); }),
              HasSubstr("initial volume fraction 0.7"));
  EXPECT_THAT(error_of([&] { m.step(-1.0); }), HasSubstr("must be > 0"));
}
