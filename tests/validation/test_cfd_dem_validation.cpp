// SPDX-License-Identifier: GPL-3.0-or-later
// Unresolved CFD-DEM through the full coupled Simulation (case text -> parser -> Simulation ->
// fluid sub-cycling, fluid fraction, drag, exchange): a sphere settling in a closed box of
// viscous fluid against the Schiller-Naumann terminal velocity, the pressure drop over a
// fixed bed against Ergun, the minimum fluidisation velocity against Ergun's, and hindered
// settling of uniform suspensions against Richardson-Zaki. With GF_VALIDATION_OUT set, the last
// two write cfd_dem_min_fluidisation.csv and cfd_dem_hindered_settling.csv.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "coupling/cfd_dem/mapping.hpp"
#include "dump.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/validate.hpp"
#include "simulation/simulation.hpp"

using namespace gf;

namespace {

constexpr double kPiD = std::numbers::pi;

class CfdDemValidation : public ::testing::Test {};

/// Glass (material, contact law) and the start of the particle list.
constexpr const char* kGlass = R"(materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
)";
/// ... with the grains of most cases below: glass spheres of d = 2 mm.
const std::string kGlassSpheres = std::string(kGlass) + R"(  - shape: sphere
    radius: 0.001
    material: glass
)";

/// The explicit position line that completes kGlassSpheres: one grain at (0.01, 0.01, z).
std::string fmt_position(double z) {
  return "    positions: [[0.01, 0.01, " + std::to_string(z) + "]]\n";
}

/// Terminal velocity of a sphere by Schiller-Naumann: (rho_p - rho_b) V g = 3 pi mu d v f(Re),
/// f = 1 + 0.15 Re^0.687 (Re < 1000, Re with the fluid's density rho_f), solved by fixed-point
/// iteration (contracting: f grows slower than v). rho_b: the density whose weight the fluid
/// carries (rho_f with buoyancy; 0 without the pressure-gradient force).
double schiller_naumann_terminal(double d, double rho_p, double rho_f, double mu, double g,
                                 double rho_b) {
  const double v_stokes = (rho_p - rho_b) * g * d * d / (18 * mu);
  double v = v_stokes;
  for (int it = 0; it < 200; ++it) {
    const double re = rho_f * v * d / mu;
    v = v_stokes / (1 + 0.15 * std::pow(re, 0.687));
  }
  return v;
}

/// A glass sphere d = 2 mm settling in a viscous oil (rho 1000, mu 0.1 Pa s) with the given
/// coupling block, in a closed box of 3 x 3 x 10 cells of 10 d: its sinking speed after 0.1 s
/// (m/s) and the run's minimum fluid fraction.
std::pair<double, double> settle_in_oil(const std::string& coupling) {
  const std::string text = R"(time: {step: 1.0e-5, end: 0.2}
domain: {min: [0, 0, 0], max: [0.06, 0.06, 0.2]}
)" + kGlassSpheres +
                           R"(    positions: [[0.03, 0.03, 0.17]]
fluid: {density: 1000, viscosity: 0.1, cells: [3, 3, 10]}
coupling: )" + coupling + "\n";
  const auto cfg = input::load_case_text(text, "settling.yaml");
  input::validate(cfg);
  Simulation sim(cfg);
  EXPECT_NE(sim.cfd_dem(), nullptr);
  // 0.1 s = 18 tau_p: the transient exp(-t / tau_p) is gone (1e-8). Not much later: the grain
  // drags the fluid of its cell along (the self-induced velocity of unresolved CFD-DEM, which
  // grows as the column of fluid below the grain is set in motion: +2.6 % after 0.5 s here).
  const auto steps = static_cast<std::int64_t>(std::llround(0.1 / cfg.time.step));
  while (sim.step_count() < steps) sim.step();
  return {-sim.particles().v()[0].z, sim.quantity("min_fluid_fraction")};
}

TEST_F(CfdDemValidation, SphereSettlesAtTheSchillerNaumannTerminalVelocity) {
  // Stokes speed 3.3 cm/s, Re ~ 0.6 (Schiller-Naumann 10 % below Stokes, so the correlation is
  // exercised), response time tau_p = rho_p d^2 / (18 mu) = 5.6 ms.
  const auto [v, eps_min] = settle_in_oil("{drag: schiller_naumann, interval: 100}");
  const double v_sn = schiller_naumann_terminal(0.002, 2500, 1000, 0.1, 9.81, 1000);
  // Tolerance 2 %: the law's terminal value is exact for a fluid at rest; what differs is the
  // fluid velocity in the grain's cell, which the reaction force drives. The grain removes
  // 1/1900 of its cell's volume (eps = 0.9995) and its drag, spread over a cell of 10 d,
  // moves that cell's fluid along with it (the self-induced velocity, ~ d / h): measured
  // +0.8 % at 0.1 s (docs/models/cfd_dem.md). 2 % leaves room for the slow growth of this flow
  // and still catches a lost buoyancy (40 % of the weight here: rho_f / (rho_p - rho_f) = 2/3
  // of the net weight) or a wrong drag correction (Schiller-Naumann is 10 % below Stokes).
  std::printf("settling: v = %.6g m/s, Schiller-Naumann %.6g m/s (%+.2f %%)\n", v, v_sn,
              100 * (v / v_sn - 1));
  EXPECT_NEAR(v, v_sn, 0.02 * v_sn) << "v = " << v << " m/s, Schiller-Naumann " << v_sn;
  // The fluid fraction of the grain's cell: 1 - V_p / V_cell.
  const double vp = kPiD * 0.002 * 0.002 * 0.002 / 6, vc = 0.02 * 0.02 * 0.02;
  EXPECT_NEAR(eps_min, 1 - vp / vc, 1e-9);
}

TEST_F(CfdDemValidation, WithoutThePressureGradientForceTheGrainFeelsNoBuoyancy) {
  // Drag only (coupling.pressure_gradient_force: false): the fluid carries the grain's whole
  // weight rho_p V g, so the terminal speed is Schiller-Naumann's for a net density of 2500
  // instead of 1500 (5.5 cm/s Stokes, Re ~ 0.9). Same 2 % as above (the same self-induced flow,
  // measured +0.8 % there); the speed with buoyancy is 38 % lower, so a force that stayed on
  // fails, as does one applied twice.
  const double v =
      settle_in_oil("{drag: schiller_naumann, interval: 100, pressure_gradient_force: false}")
          .first;
  const double v_sn = schiller_naumann_terminal(0.002, 2500, 1000, 0.1, 9.81, 0);
  std::printf("settling without buoyancy: v = %.6g m/s, Schiller-Naumann %.6g m/s (%+.2f %%)\n", v,
              v_sn, 100 * (v / v_sn - 1));
  EXPECT_NEAR(v, v_sn, 0.02 * v_sn) << "v = " << v << " m/s, Schiller-Naumann " << v_sn;
}

/// Velocity and angular velocity of a glass sphere carried by a plane Couette flow of a viscous
/// liquid (walls at z = 0 and 0.04 m sliding at -/+0.1 m/s, 4 cells across: the finite-volume
/// solution of a linear profile is exact, u = 0.1 (z / 0.02 - 1)), released at rest at height
/// z0, after 0.2 s; `option` is one more coupling key (e.g. "interpolation: cell").
struct GrainState {
  Vec3 v, omega;
};
/// That Couette flow with the particle group(s) `grains` and one more coupling key `option`.
config::Case couette_case(const std::string& grains, const std::string& option) {
  const std::string text = R"(time: {step: 1.0e-5, end: 0.2}
domain: {min: [0, 0, 0], max: [0.04, 0.04, 0.04], periodic: [true, true, false]}
gravity: [0, 0, 0]
)" + grains + R"(fluid:
  density: 1000
  viscosity: 10
  cells: [2, 2, 4]
  boundary: {zmin: {moving_wall: [-0.1, 0, 0]}, zmax: {moving_wall: [0.1, 0, 0]}}
coupling: {drag: schiller_naumann, interval: 10, )" +
                           option + "}\n";
  return input::load_case_text(text, "couette.yaml");
}

GrainState carried_by_couette(const std::string& option, double z0) {
  const auto cfg = couette_case(kGlassSpheres + fmt_position(z0), option);
  Simulation sim(cfg);
  const auto steps = static_cast<std::int64_t>(std::llround(0.2 / cfg.time.step));
  while (sim.step_count() < steps) sim.step();
  return {sim.particles().v()[0], sim.particles().omega()[0]};
}

TEST_F(CfdDemValidation, CellInterpolationReadsTheCellValueTrilinearTheProfile) {
  // The liquid is 10^4 times as viscous as water: the Couette profile is set up in
  // rho h^2 / mu = 0.16 ms, and the grain's response time rho_p d^2 / (18 mu) = 56 us is 3600
  // times shorter than the run, so the grain moves with the fluid velocity it reads. Released
  // a quarter of a cell below a cell centre (z0 = 0.0125 m; centre 0.015 m): trilinear reads
  // the profile there, 0.1 (0.0125 / 0.02 - 1) = -0.0375 m/s; cell reads the cell's centre
  // value, -0.025 m/s. The two differ by 0.0125 m/s = 33 % of the first. A grain carried at
  // the velocity it reads feels no drag and must not push the fluid: the exchange returns the
  // drag the grain feels (before it did not: the fluid received beta (v - u_cell), the
  // grain's cell was pushed off the profile by 5 % and the trilinear grain moved at -0.0391
  // m/s, +4.3 %). Measured: -0.03750 and -0.02500 m/s (2e-5 and 1e-4 relative); 1 % is
  // far below the 33 % between the two reads and the 4.3 % of an inconsistent exchange.
  const double v_tri = carried_by_couette("interpolation: trilinear", 0.0125).v.x;
  const double v_cell = carried_by_couette("interpolation: cell", 0.0125).v.x;
  std::printf("couette: trilinear %.6g m/s (profile -0.0375), cell %.6g m/s (cell -0.025)\n", v_tri,
              v_cell);
  EXPECT_NEAR(v_tri, -0.0375, 0.01 * 0.0375);
  EXPECT_NEAR(v_cell, -0.025, 0.01 * 0.025);
}

// --- Hydrodynamic torque (coupling.torque: rotational) ------------------------------------------

TEST_F(CfdDemValidation, TorqueTurnsASphereWithTheFluidsRotation) {
  // A sphere in simple shear u = gamma_dot z e_x (carried_by_couette: 5 1/s) turns at half the
  // vorticity, omega_y =
  // gamma_dot / 2 = 2.5 rad/s, where the Stokes torque pi mu d^3 (curl u / 2 - omega) vanishes.
  // The fluid's rotation rate is exact on the linear profile (FluidFV.CouetteIsExact), and the
  // rotational response time rho_p d^2 / (60 mu) = 17 us is short against the run: the grain sits
  // at the fixed point, where any stable time integration is exact (the fluid's start from rest
  // has decayed to exp(-pi^2 nu t / H^2) = 4e-6 at t = 0.2 s). What moves the fixed point is the
  // grain's own volume: it lowers the fluid fraction of its cells to >= 0.999, and the
  // volume-averaged viscous stress eps mu du/dz, the same in every layer, steepens the profile
  // there by up to 1e-3 (measured: omega_y 8.6e-5 and the grain's velocity 1.8e-5 off the
  // exact values, steady from t = 0.1 s on). Tolerance 1e-3; a wrong factor (curl instead of
  // curl / 2) is off by 100 %. Without the torque no force turns the grain (no contacts): omega
  // stays 0.
  const Vec3 w = carried_by_couette("torque: rotational", 0.0125).omega;
  std::printf("couette spin: omega = (%.9g, %.9g, %.9g) rad/s (gamma_dot / 2 = 2.5)\n", w.x, w.y,
              w.z);
  EXPECT_NEAR(w.y, 2.5, 1e-3 * 2.5);
  EXPECT_NEAR(w.x, 0.0, 1e-9);
  EXPECT_NEAR(w.z, 0.0, 1e-9);
  const Vec3 w0 = carried_by_couette("torque: none", 0.0125).omega;
  EXPECT_EQ(norm(w0), 0.0);
}

TEST_F(CfdDemValidation, TorqueTurnsARodOnJefferysOrbit) {
  // A rod (glass spherocylinder, d = 2 mm, p = L / d = 4) lying along the flow in the middle of
  // the same Couette flow (gamma_dot = 5 1/s, u_x = gamma_dot (z - 0.02 m)) turns in the
  // flow-gradient plane on Jeffery's orbit: its angle phi from the flow direction obeys
  // d phi / dt = -(gamma_dot / 2) (1 - lambda cos 2 phi), lambda = (p^2 - 1) / (p^2 + 1), whose
  // solution is tan phi = -tan(psi) / p with a phase psi = omega_J t + psi_0 growing uniformly at
  // omega_J = gamma_dot / (p + 1 / p) = 1.1765 rad/s: slow while aligned, fast while across. The
  // phase psi = atan2(-p sin phi, cos phi) is read after the fluid's start from rest has decayed
  // (exp(-pi^2 nu t / H^2) = 1.5e-8 at t = 0.3 s) and again 1.5 s later, as the rod turns from
  // near the flow direction (-0.09 rad) past standing across it (-2.75 rad): the phase must have
  // grown by omega_J * 1.5 s = 1.765 rad. A rod turning with the fluid's spin only (lambda = 0)
  // gains 3.75 rad of angle; a shape factor 1 % off changes the gain by ~10 % (the aligned
  // stretch is slow by 1 - lambda). Errors: the response time I_perp / R_perp = 49 us against
  // the turning's ~1 s (measured at t = 0.2 s: omega_y 0.30912 against Jeffery's 0.30911 at
  // the same phi); the rod's 0.6 % of its cells' volume steepens the profile there (the
  // sphere's 0.1 % moved its spin by 8.6e-5 relative, test above). Measured: +2.7e-4.
  // Tolerance 1e-3 relative.
  const auto cfg = couette_case(std::string(kGlass) + R"(  - shape: spherocylinder
    radius: 0.001
    aspect_ratio: 4
    material: glass
    positions: [[0.01, 0.01, 0.02]]
    axes: [[1, 0, 0]]
)",
                                "torque: rotational");
  Simulation sim(cfg);
  const double p = 4.0, omega_j = 5.0 / (p + 1 / p);
  auto phase_at = [&](double t) {
    while (sim.step_count() < std::llround(t / cfg.time.step)) sim.step();
    const Vec3 a = cfd_dem::grain_shape(sim.particles(), 0).axis;
    const double phi = std::atan2(a.z, a.x);
    std::printf("Jeffery orbit: t = %.3f s, phi = %.6f rad\n", t, phi);
    return std::atan2(-p * std::sin(phi), std::cos(phi));
  };
  const double psi0 = phase_at(0.3), psi1 = phase_at(1.8);
  std::printf("Jeffery orbit: phase gain %.6f rad in 1.5 s (omega_J * 1.5 s = %.6f)\n", psi1 - psi0,
              1.5 * omega_j);
  EXPECT_NEAR((psi1 - psi0) / (1.5 * omega_j), 1.0, 1e-3);
}

/// |omega| of one glass grain after time t spinning in oil at rest (rho 1000, mu 0.1 Pa s, closed
/// box, no gravity); `grain` is its particle group (shape, position, axis, angular velocity).
double spin_down(const std::string& grain, double t) {
  const std::string text = R"(time: {step: 1.0e-6, end: 0.01}
domain: {min: [0, 0, 0], max: [0.03, 0.03, 0.03]}
gravity: [0, 0, 0]
)" + std::string(kGlass) + grain +
                           R"(fluid: {density: 1000, viscosity: 0.1, cells: [3, 3, 3]}
coupling: {drag: schiller_naumann, interval: 10, torque: rotational}
)";
  const auto cfg = input::load_case_text(text, "spin_down.yaml");
  Simulation sim(cfg);
  const auto steps = static_cast<std::int64_t>(std::llround(t / cfg.time.step));
  while (sim.step_count() < steps) sim.step();
  return norm(sim.particles().omega()[0]);
}

TEST_F(CfdDemValidation, TorqueSpinsDownASphereAndARodExponentially) {
  // A grain spinning in fluid at rest (Re_R = rho d^2 omega / mu = 0.4 and 0.2: Stokes) decays
  // as omega0 exp(-R t / I). The fluid gets no reaction torque, so it stays at rest (no spin to
  // read). Sphere, d = 2 mm: R / I = pi mu d^3 / (m d^2 / 10) = 60 mu / (rho_p d^2) = 600 1/s.
  // Rod across its axis (spherocylinder r = 1 mm, l = 4 mm, p = L / d = 3): R_perp from
  // Tirado & Garcia de la Torre, I_perp of the capsule from the store. The run lasts 2 time
  // constants at dt = 1/1700 of one (sphere): the integrator's error ~ dt / tau per time
  // constant, 1e-3 relative; the tolerance 5e-3 is 5 times that and far below the 2.6 % (sphere)
  // that a 1 % change of R makes after 2 time constants.
  const double rho_p = 2500, mu = 0.1, d = 0.002, w0 = 10.0;
  const double tau_sphere = rho_p * d * d / (60 * mu);
  const double t = 2 * tau_sphere;
  const double sphere = spin_down(R"(  - shape: sphere
    radius: 0.001
    material: glass
    positions: [[0.015, 0.015, 0.015]]
    angular_velocities: [[10, 0, 0]]
)",
                                  t);
  const double expected_sphere = w0 * std::exp(-t / tau_sphere);
  std::printf("spin-down sphere: %.6g rad/s after %.4g s (analytic %.6g)\n", sphere, t,
              expected_sphere);
  EXPECT_NEAR(sphere, expected_sphere, 5e-3 * expected_sphere);

  // Rod: I_perp of a capsule (cylinder r, length l; two hemispherical caps) about a transverse
  // axis through its centre.
  const double r = 0.001, l = 0.004, pi = kPiD;
  const double m_cyl = rho_p * pi * r * r * l, m_cap = rho_p * 2.0 / 3.0 * pi * r * r * r;
  const double i_cyl = m_cyl * (r * r / 4 + l * l / 12);
  const double i_caps = 2 * m_cap * (83.0 / 320.0 * r * r + std::pow(l / 2 + 3.0 * r / 8, 2));
  const double length = l + 2 * r, p = length / (2 * r);
  const double r_perp =
      pi * mu * length * length * length / (3 * (std::log(p) - 0.662 + 0.917 / p - 0.05 / (p * p)));
  const double tau_rod = (i_cyl + i_caps) / r_perp;
  const double rod = spin_down(R"(  - shape: spherocylinder
    radius: 0.001
    aspect_ratio: 3
    material: glass
    positions: [[0.015, 0.015, 0.015]]
    axes: [[1, 0, 0]]
    angular_velocities: [[0, 0, 10]]
)",
                               t);
  const double expected_rod = w0 * std::exp(-t / tau_rod);
  std::printf("spin-down rod: %.6g rad/s after %.4g s (analytic %.6g, tau %.4g s)\n", rod, t,
              expected_rod, tau_rod);
  EXPECT_NEAR(rod, expected_rod, 5e-3 * expected_rod);
}

// --- Minimum fluidisation ----------------------------------------------------------------------

/// Ergun's superficial velocity at which the bed's friction loss per length equals its buoyant
/// weight per volume: 150 mu U (1-e)^2 / (e^3 d^2) + 1.75 rho U^2 (1-e) / (e^3 d)
/// = (1-e)(rho_p - rho_f) g, the positive root of the quadratic.
double ergun_umf(double e, double d, double rho_p, double rho_f, double mu, double g) {
  const double a = 1.75 * rho_f * (1 - e) / (e * e * e * d);
  const double b = 150 * mu * (1 - e) * (1 - e) / (e * e * e * d * d);
  const double c = -(1 - e) * (rho_p - rho_f) * g;
  return (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
}

/// Mean fluid fraction of the cells lying wholly in z in [z0, z1].
double mean_cell_fraction(const CfdDemCoupling& cfd, double z0, double z1) {
  const auto& g = cfd.grid();
  const auto eps = cfd.fluid().fluid_fraction();
  double sum = 0;
  int n = 0;
  for (int k = 0; k < g.n[2]; ++k)
    if (k * g.h.z >= z0 - 1e-12 && (k + 1) * g.h.z <= z1 + 1e-12)
      for (int j = 0; j < g.n[1]; ++j)
        for (int i = 0; i < g.n[0]; ++i, ++n)
          sum += eps[static_cast<std::size_t>(g.index(i, j, k))];
  return sum / n;
}

double mean_height(const Simulation& sim) {
  double s = 0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i) s += sim.particles().x()[i].z;
  return s / static_cast<double>(sim.particles().size());
}

struct BedRun {
  double eps = 0;   // mean fluid fraction of the bed's cells at the start
  double dp = 0;    // fluid_pressure_drop averaged over the second half of the run, Pa
  double lift = 0;  // rise of the grains' mean height over the run, m
};

constexpr double kBedHeight = 0.036;  // 18 layers of d = 2 mm

/// A bed of 6 x 6 x 18 glass spheres (d = 2 mm, cubic lattice of spacing d: 648 grains, L = 36
/// mm = 6 cells of 3 d) resting on the floor of a box periodic sideways (12 x 12 mm, 2 x 2
/// cells), water blown up at superficial velocity u from a velocity inlet to a pressure outlet
/// 60 mm up (4 free cells above the bed: room to expand). Runs t_end, averages the pressure drop
/// over the second half.
BedRun run_bed(double u, double t_end) {
  const std::string text =
      "time: {step: 1.0e-5, end: " + std::to_string(t_end) + R"(}
domain: {min: [0, 0, 0], max: [0.012, 0.012, 0.06], periodic: [true, true, false]}
)" + kGlassSpheres +
      R"(    fill: {box: {min: [0, 0, 0], max: [0.012, 0.012, 0.036]}, lattice: cubic, spacing: 0.002}
walls:
  - {name: floor, plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
fluid:
  density: 1000
  viscosity: 1.0e-3
  cells: [2, 2, 10]
  boundary: {zmin: {velocity_inlet: [0, 0, )" +
      std::to_string(u) +
      R"(]}, zmax: {pressure_outlet: 0}}
coupling: {drag: gidaspow, fluid_fraction: divided, interval: 50}
)";
  const auto cfg = input::load_case_text(text, "umf.yaml");
  input::validate(cfg);
  Simulation sim(cfg);
  EXPECT_EQ(sim.particles().size(), 648u);
  BedRun r;
  r.eps = mean_cell_fraction(*sim.cfd_dem(), 0, kBedHeight);
  const double z0 = mean_height(sim);
  const auto steps = static_cast<std::int64_t>(std::llround(t_end / cfg.time.step));
  double sum = 0;
  int n = 0;
  while (sim.step_count() < steps) {
    sim.step();
    if (2 * sim.step_count() > steps && sim.step_count() % 50 == 0) {
      sum += sim.quantity("fluid_pressure_drop");
      ++n;
    }
  }
  r.dp = sum / n;
  r.lift = mean_height(sim) - z0;
  return r;
}

TEST_F(CfdDemValidation, MinimumFluidisationVelocityFollowsErgun) {
  // Glass beads d = 2 mm in water: Ergun's U_mf = 3.3 cm/s at eps = 0.476 (Re_mf = 66, both
  // Ergun terms matter). Drag law gidaspow: below eps = 0.8 it is Ergun's equation written per
  // grain, so in the volume-averaged momentum balance of a steady uniform bed,
  // eps dp/dz = n beta u (n grains per volume, u = U / eps interstitial), it gives back Ergun's
  // pressure drop: the fixed-bed runs check the whole chain (fluid fraction, exchange source,
  // implicit drag in the fluid, pressure solution, the series quantity) against Ergun, and U_mf
  // checks that the grains' side of the exchange balances the fluid's: the bed lifts when the drag
  // plus the pressure-gradient force on the grains carry their weight, which in model A is exactly
  // when the fluid's pressure drop reaches the buoyant weight per area.
  //
  // Procedure (as in an experiment): pressure drop at three velocities below U_mf (fixed bed),
  // fitted by Ergun's form dp = a U + b U^2; plateau at 1.3 x U_mf (fluidised); U_mf where the
  // fitted fixed-bed curve meets the buoyant weight per area.
  const double d = 0.002, rho_p = 2500, rho_f = 1000, mu = 1e-3, g = 9.81;
  const double area = 0.012 * 0.012;
  // Buoyant weight per area: N V_p (rho_p - rho_f) g / A (= (1-eps)(rho_p - rho_f) g L).
  const double w = 648 * kPiD / 6 * d * d * d * (rho_p - rho_f) * g / area;
  const double eps_lattice = 1 - kPiD / 6;
  const double umf_e0 = ergun_umf(eps_lattice, d, rho_p, rho_f, mu, g);
  test::Dump dump("cfd_dem_min_fluidisation", "u,dp,w,ergun_dp,lift,eps");
  std::vector<double> us, dps;
  double eps = 0;
  for (double f : {0.5, 0.7, 0.9}) {
    // 0.1 s: the bed's elastic ringing after the impulsive start has died out (the pressure drop
    // is steady to 0.1 % from 0.07 s). Not much longer: a simple cubic stack under load is
    // metastable and buckles into a denser packing after ~0.2 s (round-off grows e-fold in 8 ms).
    const auto r = run_bed(f * umf_e0, 0.1);
    const double u = f * umf_e0, e = r.eps;
    const double ergun = kBedHeight * (150 * mu * u * (1 - e) * (1 - e) / (e * e * e * d * d) +
                                       1.75 * rho_f * u * u * (1 - e) / (e * e * e * d));
    std::printf("fixed   U = %.5f m/s: eps %.4f dp %.5g Pa (Ergun %.5g, %+.1f %%) lift %.2g mm\n",
                u, e, r.dp, ergun, 100 * (r.dp / ergun - 1), 1e3 * r.lift);
    dump.row(u, r.dp, w, ergun, r.lift, e);
    // Packed-bed pressure drop vs Ergun within 10 % (the issue's figure). The bulk of the bed is
    // Ergun's exactly (gidaspow); the grains of the top half-cell see eps and u_f interpolated
    // towards the free fluid above and drag less, a shortfall of about h / (2 L) = 8 % for this
    // bed of 6 cells (measured -7.4 to -7.8 %; 11 % for 4 cells, 15 % for 3: it scales with the
    // cell size over the bed height, so it is the surface, not the bulk).
    EXPECT_NEAR(r.dp, ergun, 0.10 * ergun) << "U = " << u;
    EXPECT_LT(std::abs(r.lift), 1e-4) << "the bed must stay put at U = " << u;
    us.push_back(u);
    dps.push_back(r.dp);
    eps = e;
  }
  // Fluidised: the bed rises and the pressure drop is its buoyant weight per area.
  const double u_fl = 1.3 * umf_e0;
  const auto fl = run_bed(u_fl, 0.15);
  std::printf("fluid.  U = %.5f m/s: dp %.5g Pa = %.4f W, lift %.3g mm\n", u_fl, fl.dp, fl.dp / w,
              1e3 * fl.lift);
  dump.row(u_fl, fl.dp, w, 0.0, fl.lift, fl.eps);
  EXPECT_GT(fl.lift, 2e-4) << "the bed must expand above U_mf";
  // Fluidised, the grains rest on nothing but the fluid: in steady state the fluid's momentum
  // balance over the box makes the pressure drop the bed's buoyant weight per area exactly
  // (model A). Tolerance 5 %: the bed is not steady (its grains collide, the pressure drop
  // fluctuates by 1 % of W per sample, 6 % at most, measured over 0.3 s) and the mean is over
  // 0.075 s of correlated samples; measured 1.002 W. (Before the fluid-fraction rate came from
  // the solid flux, the eps difference swung it by +-40 W between fluid steps.)
  EXPECT_NEAR(fl.dp, w, 0.05 * w);
  // Least-squares fit dp = a U + b U^2 through the fixed-bed points, then a U + b U^2 = W.
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (std::size_t i = 0; i < us.size(); ++i) {
    const double x1 = us[i], x2 = us[i] * us[i];
    s11 += x1 * x1, s12 += x1 * x2, s22 += x2 * x2, r1 += x1 * dps[i], r2 += x2 * dps[i];
  }
  const double det = s11 * s22 - s12 * s12;
  const double a = (r1 * s22 - r2 * s12) / det, b = (s11 * r2 - s12 * r1) / det;
  const double umf = (-a + std::sqrt(a * a + 4 * b * w)) / (2 * b);
  const double umf_e = ergun_umf(eps, d, rho_p, rho_f, mu, g);
  std::printf("U_mf = %.5f m/s, Ergun (eps = %.4f) %.5f m/s (%+.2f %%)\n", umf, eps, umf_e,
              100 * (umf / umf_e - 1));
  // Tolerance 10 % (the issue's figure). With gidaspow the bulk of the bed is Ergun's exactly;
  // what remains is the bed's top: the grains of the top half-cell see eps and u_f interpolated
  // towards the free fluid above (trilinear between cell centres), so their drag is low and the
  // model's loss falls short of Ergun by about the share of those grains, h/(2L) ~ 8 % of dp
  // here (measured -7 %; the shortfall is 15 % for a bed of 3 cells, so it is the bed surface,
  // not the bulk). Through dp ~ U^1.4 near U_mf that puts U_mf ~ 5 % above Ergun's.
  EXPECT_NEAR(umf, umf_e, 0.10 * umf_e);
  // The bed had not lifted below U_mf and has above: U_mf lies between the runs.
  EXPECT_GT(umf, us.back());
  EXPECT_LT(umf, u_fl);
}

// --- Hindered settling --------------------------------------------------------------------------

/// Settling of a uniform suspension: a simple cubic lattice of glass spheres (d = 2 mm, solid
/// fraction phi set by the spacing) in a viscous oil (rho 1000, mu 0.2 Pa s), box periodic
/// sideways, closed at top and bottom (no_slip; the fluid's volume is fixed, so the flux through
/// every horizontal plane is zero: the fluid flows back up through the suspension, as in a batch
/// settling column). Returns the mean vertical grain velocity (lab frame) of the grains in the
/// middle third of the suspension after t_end, and the mean fluid fraction of the cells there.
struct Settling {
  double v = 0, eps = 0;
};
Settling run_suspension(double phi, int per_cell, int cells_z,
                        const char* fraction = "fluid_fraction: divided") {
  const double d = 0.002;
  const double s = d * std::cbrt(kPiD / (6 * phi));  // lattice spacing
  const double h = per_cell * s;                     // cell size: per_cell^3 grains per cell
  const double lx = 2 * h, lz = cells_z * h, hs = (cells_z - 1) * h;  // one clear cell on top
  // Grain centres at (i + 1/2) s: every cell holds per_cell^3 whole grains, eps uniform.
  const double o = s / 2 - d / 2 - 1e-9;
  char buf[2048];
  std::snprintf(buf, sizeof buf, R"(time: {step: 1.0e-5, end: 0.12}
domain: {min: [0, 0, 0], max: [%.9g, %.9g, %.9g], periodic: [true, true, false]}
%s    fill: {box: {min: [%.9g, %.9g, %.9g], max: [%.9g, %.9g, %.9g]}, lattice: cubic, spacing: %.9g}
walls:
  - {name: floor, plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
fluid: {density: 1000, viscosity: 0.2, cells: [2, 2, %d]}
coupling: {drag: di_felice, interval: 25, %s}
)",
                lx, lx, lz, kGlassSpheres.c_str(), o, o, o, lx, lx, hs, s, cells_z, fraction);
  const auto cfg = input::load_case_text(buf, "hindered.yaml");
  input::validate(cfg);
  Simulation sim(cfg);
  const auto steps = static_cast<std::int64_t>(std::llround(0.12 / cfg.time.step));
  while (sim.step_count() < steps) sim.step();
  Settling r;
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    const double z = sim.particles().x()[i].z;
    if (z > hs / 3 && z < 2 * hs / 3) sum += sim.particles().v()[i].z, ++n;
  }
  r.v = -sum / n;
  r.eps = mean_cell_fraction(*sim.cfd_dem(), hs / 3 - h, 2 * hs / 3 + h);
  return r;
}

/// Batch settling speed of a uniform suspension under di_felice in model A, written out here
/// independently of the drag registry: in a closed column the fluid flows back up,
/// eps u_f + (1 - eps) v = 0, so the slip is v / eps; the fluid's pressure gradient carries the
/// mixture's weight, so a grain's drag balances eps V_p (rho_p - rho_f) g (its weight less the
/// -V_p grad p force). With beta = pi/8 mu d (0.63 sqrt(Re_e) + 4.8)^2 eps^(1 - chi) and
/// Re_e = eps rho_f (v / eps) d / mu: v = eps^2 V_p (rho_p - rho_f) g / beta, solved by
/// fixed-point iteration (contracting: beta grows slower than v).
double di_felice_batch_speed(double eps, double d, double rho_p, double rho_f, double mu,
                             double g) {
  const double vp = kPiD * d * d * d / 6;
  double v = 0.01;
  for (int it = 0; it < 200; ++it) {
    const double re = rho_f * v * d / mu;
    const double chi = 3.7 - 0.65 * std::exp(-0.5 * std::pow(1.5 - std::log10(re), 2));
    const double s = 0.63 * std::sqrt(re) + 4.8;
    const double beta = kPiD / 8 * mu * d * s * s * std::pow(eps, 1 - chi);
    v = eps * eps * vp * (rho_p - rho_f) * g / beta;
  }
  return v;
}

TEST_F(CfdDemValidation, HinderedSettlingFollowsRichardsonZaki) {
  // Stokes speed 1.6 cm/s, Re_t = 0.16, tau_p = rho_p d^2 / (18 mu) = 2.8 ms (shorter in the
  // suspension): 0.12 s is > 40 tau_p, and the grains have fallen < 1.5 mm, so the middle third
  // of the suspension is far from the sediment at the floor and the clear layer on top.
  const double d = 0.002, rho_p = 2500, rho_f = 1000, mu = 0.2, g = 9.81;
  const double vt = schiller_naumann_terminal(d, rho_p, rho_f, mu, g, rho_f);
  const double re_t = rho_f * vt * d / mu;
  // Richardson-Zaki exponent at Re_t (Rowe 1987): (4.7 - n) / (n - 2.35) = 0.175 Re_t^0.75.
  const double k = 0.175 * std::pow(re_t, 0.75);
  const double n_rz = (4.7 + 2.35 * k) / (1 + k);
  test::Dump dump("cfd_dem_hindered_settling", "phi,eps,v,vt,rz,n,df,scheme");
  struct Case {
    double phi;
    int per_cell, cells_z;
  };
  // The default deposit (divided, flux rate), and the continuous ones with their exact time
  // derivative as the rate (scheme 1: trilinear, 2: smoothed).
  const char* schemes[] = {"fluid_fraction: divided",
                           "fluid_fraction: trilinear, fluid_fraction_rate: derivative",
                           "fluid_fraction: smoothed, fluid_fraction_rate: derivative"};
  for (int scheme = 0; scheme < 3; ++scheme) {
    for (const Case c : {Case{0.05, 2, 6}, Case{0.1, 2, 6}, Case{0.2, 3, 5}}) {
      const auto r = run_suspension(c.phi, c.per_cell, c.cells_z, schemes[scheme]);
      const double rz = vt * std::pow(r.eps, n_rz);
      const double df = di_felice_batch_speed(r.eps, d, rho_p, rho_f, mu, g);
      std::printf(
          "%s phi %.2f: eps %.4f v = %.5g m/s, RZ v_t eps^%.3f = %.5g m/s (%+.1f %%), "
          "di_felice batch %.5g m/s (%+.1f %%)\n",
          schemes[scheme] + 16, c.phi, r.eps, r.v, n_rz, rz, 100 * (r.v / rz - 1), df,
          100 * (r.v / df - 1));
      dump.row(c.phi, r.eps, r.v, vt, rz, n_rz, df, scheme);
      // Against the model's own batch speed, 3 %: measured +0.1/+0.1/+0.6 % at phi
      // 0.05/0.1/0.2 with the divided deposit, +0.1/+0.1/-0.2 % trilinear and +0.1/0.0/-0.1 %
      // smoothed, both with the derivative rate (after
      // 0.06 s it was -1.6 % at phi = 0.2: the transient decays slowly in the densest case).
      // What remains is the discretisation (eps interpolated to the grains from 2-3 grains per
      // cell edge, the lattice 1-2 cells from the clear layer and the sediment). A coupling
      // that loses the return flow (slip v instead of v / eps, as the eps difference did on
      // this lattice: +4/+10/+26 %) is off by a factor 1/eps or more (+5 % at phi = 0.05,
      // +25 % at 0.2), one that loses the pressure-gradient force by 1/eps as well.
      EXPECT_NEAR(r.v, df, 0.03 * df) << "phi = " << c.phi << " " << schemes[scheme];
      // Against Richardson-Zaki, 8 %: di_felice and RZ are different fits of the same data
      // and differ by <= 1.1 % here (the batch speed above against v_t eps^n at eps
      // 0.8-0.95), RZ's own scatter about its fit is ~5 %, plus the 3 % above.
      EXPECT_NEAR(r.v, rz, 0.08 * rz) << "phi = " << c.phi << " " << schemes[scheme];
    }
  }
}

// --- A dense suspension in water: the flux rate's explicit loop -------------------------------

/// Peak fluid kinetic energy over its initial value for the shipped water shear box at phi = 0.4,
/// 100 1/s, one fluid step every 25 DEM steps of 1e-6 s, over 3000 DEM steps (120 fluid steps).
double water_box_energy_growth(const std::string& relaxation, const char* derivative_of = nullptr) {
  std::vector<input::Override> sets = {{"particles[0].fill.volume_fraction", "0.4"},
                                       {"time.step", "1.0e-6"},
                                       {"coupling.interval", "25"},
                                       {"coupling.rate_relaxation", relaxation}};
  if (derivative_of) {  // that deposit, with its time derivative as the rate
    sets.push_back({"coupling.fluid_fraction", derivative_of});
    sets.push_back({"coupling.fluid_fraction_rate", "derivative"});
  }
  const auto cfg = input::load_case(
      std::string(GF_SOURCE_DIR) + "/cases/cfd_dem/shear_box_rods_water/case.yaml", sets);
  Simulation sim(cfg);
  const double e0 = sim.quantity("fluid_kinetic_energy");
  double peak = e0;
  while (sim.step_count() < 3000) {
    sim.step();
    if (sim.step_count() % 25 == 0) peak = std::max(peak, sim.quantity("fluid_kinetic_energy"));
  }
  return peak / e0;
}

TEST_F(CfdDemValidation, DenseSuspensionInWaterStaysStable) {
  // d(eps)/dt from the grains' flux is felt by the fluid at once, and its pressure by the grains
  // over the next interval: with rods in water at phi = 0.4 (added mass of the returning fluid
  // comparable to the rods' mass) the unrelaxed loop diverges, the fluid's energy growing ~4x
  // per 0.2 ms (here: past the Courant limit within ~2000 steps, an error). The shear drives the
  // fluid at a steady rate, so its energy must stay near the start (Couette profile): within
  // 10 % over 3 ms (measured: 1.00x with the default relaxation 0.3).
  const double growth = water_box_energy_growth("0.3");
  std::printf("water box phi 0.4: peak fluid energy %.4f x the initial\n", growth);
  EXPECT_LT(growth, 1.1);
  // The continuous deposits' derivative rate follows the grains' velocities at once as well,
  // and the same relaxation keeps it stable (measured: 1.025x trilinear, 1.041x smoothed).
  for (const char* scheme : {"trilinear", "smoothed"}) {
    const double g = water_box_energy_growth("0.3", scheme);
    std::printf("%s, derivative: peak fluid energy %.4f x the initial\n", scheme, g);
    EXPECT_LT(g, 1.1) << scheme;
  }
  // Unrelaxed, the same run fails: the check is sensitive to the loop.
  bool failed = false;
  try {
    failed = water_box_energy_growth("1") > 1.1;
  } catch (const Error&) {
    failed = true;  // the fluid refuses a step above its Courant limit
  }
  EXPECT_TRUE(failed) << "without relaxation the loop should diverge";
}

}  // namespace
