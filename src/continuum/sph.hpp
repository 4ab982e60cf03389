// SPDX-License-Identifier: GPL-3.0-or-later
// Weakly compressible SPH for a continuum phase (a Newtonian liquid, or grains as a mu(I)
// visco-plastic fluid) with free surfaces, solid walls made of boundary particles, and periodic
// directions; 2D and 3D.
//
// Equations (fluid particle i, neighbours j within the support 2h, r_ij = x_i - x_j,
// grad_i W_ij = W'(r) r_ij / r, V_j = m_j / rho_j; Wendland C2 kernel, continuum/sph_kernel.hpp):
//   continuity   d rho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij
//                            + delta h c0 sum_j V_j psi_ij . grad_i W_ij       (fluid j only)
//                psi_ij = 2 (rho_j - rho_i - rho0 g . (x_j - x_i) / c0^2) (x_j - x_i) / r^2
//                (density diffusion of Molteni & Colagrossi, Comput. Phys. Commun. 180 (2009)
//                861, eq. 13, less its hydrostatic part as in Fourtakas et al., Comput. Fluids 190
//                (2019) 346, so that a liquid at rest stays at rest)
//   state        p = rho0 c0^2 / gamma ((rho / rho0)^gamma - 1) + p_b   (Tait; Monaghan 1994)
//   momentum     dv_i/dt = - sum_j m_j (p_i + p_j) / (rho_i rho_j) grad_i W_ij
//                          + sum_j m_j (eta_i + eta_j) / (rho_i rho_j) r_ij . grad_i W_ij
//                                  / (r^2 + 0.01 h^2) (v_i - v_j)  + g
//                          - sum_j m_j Pi_ij grad_i W_ij   (approaching pairs, v_ij . r_ij < 0)
//                (viscous term: Morris, Fox & Zhu, J. Comput. Phys. 136 (1997) 214, eq. 8;
//                artificial viscosity Pi_ij = -alpha h c0 v_ij . r_ij / (rho_ij (r^2 + 0.01 h^2)),
//                rho_ij = (rho_i + rho_j) / 2: Monaghan, Annu. Rev. Astron. Astrophys. 30 (1992)
//                543, eq. 4.1, without its quadratic term, as in DualSPHysics)
//   viscosity    eta_i = rheology(gamma_dot_i, p_i), gamma_dot = sqrt(2 D:D), D = sym(grad v),
//                grad v_i = sum_j V_j (v_j - v_i) (x) grad_i W_ij . L_i over fluid j, with the
//                kernel-gradient correction L_i = (sum_j V_j (x_j - x_i) (x) grad_i W_ij)^-1
//                (Bonet & Lok, Comput. Methods Appl. Mech. Eng. 180 (1999) 97), exact for linear
//                velocity fields also next to walls and free surfaces.
// Walls: layers of boundary particles (at least 2h thick) whose pressure, density and velocity
// are extrapolated from the fluid each step (Adami, Hu & Adams, J. Comput. Phys. 231 (2012)
// 7057, eqs. 22-28): p_w = (sum_f p_f W_wf + (g - a_w) . sum_f rho_f (x_w - x_f) W_wf) /
// sum_f W_wf, and for no slip the mirrored velocity v_w = 2 u_w - sum_f v_f W_wf / sum_f W_wf
// in the viscous term and the velocity gradient; a free-slip wall takes no part in the viscous
// term (no shear stress: Adami et al. 2012, sec. 2.4.1). Partial (Navier) slip with slip length
// b, u_s - u_w = b dv/dn (Gomez Fino 2014, eq. 15): the mirror surface lies halfway between x_w
// and the centroid x~ = sum_f x_f W_wf / sum_f W_wf of the fluid it sees, d = |x~ - x_w| / 2
// from either; with a linear profile the fluid there moves at u_s = (d u_w + b v~) / (d + b)
// (v~ the fluid's kernel mean), and the mirrored velocity is v_w = 2 u_s - v~ (b = 0: no slip;
// b -> infinity: v_w = v~, no shear).
// Wall motion: rigid, a constant translation V and a constant rotation Omega about the centre
// c(t) = c0 + V t: x_w(t) = c(t) + R(Omega t) (x_w(0) - c0), with R(Omega t) the rotation by
// |Omega| t about Omega / |Omega| (Rodrigues' formula), evaluated from t rather than summed step
// by step (no drift, and a continued run is bit-identical); u_w = V + Omega x (x_w - c),
// a_w = Omega x (Omega x (x_w - c)) = Omega x (u_w - V). In the mirrored velocity a rotating
// wall's velocity is taken at the midpoint of x_w and the centroid x~ = sum_f x_f W_wf /
// sum_f W_wf of the fluid it sees (where Adami's mirroring puts the surface):
// v_w = 2 (u_w + Omega x (x~ - x_w) / 2) - sum_f v_f W_wf / sum_f W_wf, so that a liquid turning
// rigidly with the wall feels no viscous force from it (with u_w alone it would, and in
// Taylor-Couette flow the liquid slipped by 1.6 % of the wall speed at 20 particles across).
// Wall loads: the force is the reaction of the pair forces the wall's particles exert on the
// fluid, the torque about c(t) that of these pair forces applied at the pairs' midpoints.
// The Morris term's pair forces are not central: its stress is eta grad v, not
// eta (grad v + grad v^T), the same force density in an incompressible liquid of constant eta
// but another traction. On a rigid no-slip wall (grad v)^T n = n x Omega, so a rotating wall's
// loads add eta_w n dS x Omega per wall particle, with n dS = 2 V_w sum_f V_f W'(r_wf)
// (x_w - x_f) / r_wf (the outward normal times the particle's share of the surface: a wall
// particle sees half the kernel's support filled at a plane surface; times the lattice
// normalisation of the pressure gradient). Without it the torque on a cylinder turning in a
// Newtonian liquid lacks -2 eta Omega A (A its cross-section; 37.5 % of the Taylor-Couette torque
// at R2 = 2 R1).
// Kinetic theory (SphConfig::kinetic_theory; Gomez Fino 2014, sec. 3.2): the density is the bulk
// density a rho_s and each particle carries a granular temperature Theta;
// p = P_s(a, Theta) + max(0, Tait(rho)) [+ P_f(a)] - lambda_s div v (no tension in a gas),
// eta = the dense model's effective viscosity (mu_i_switch: the rheology above a_fric, KTGF's
// mu_s below), and (3/2) rho DTheta/Dt = mu_s (gamma_dot^2 - 2/3 div^2) + lambda_s div^2 -
// P_s div v - gamma_s + div(kappa_s grad Theta) with the kinetic theory's mu_s (frictional
// work does not feed the fluctuations: Srivastava & Sundaresan, Powder Technol. 129 (2003) 72);
// sinks implicit, sources explicit, conduction explicit or (with implicit viscosity) backward
// Euler; walls adiabatic unless Johnson-Jackson walls. Closures: continuum/ktgf.hpp.
// Johnson-Jackson walls (kinetic theory only; Johnson & Jackson, J. Fluid Mech. 176 (1987) 67,
// their wall conditions in the form with a / a_max that MFIX, Fluent and OpenFOAM use, e.g.
// OpenFOAM's JohnsonJacksonParticleSlip / JohnsonJacksonParticleTheta, after Reuge et al., Chem.
// Eng. Sci. 63 (2008) 5540): the wall's shear stress on the grains opposes their slip u_slip
// (their velocity at the wall relative to it), tau_w = -C u_slip with C = (pi sqrt(3) / 6) phi'
// (a / a_max) rho_s g0 sqrt(Theta), phi' the specularity coefficient; with eta du/dn = C u_slip
// this is Navier slip of local length b = eta / C (eta the material's viscosity at the wall),
// applied through the mirrored velocity as above, with d / (d + b) = d C / (d C + eta). The wall
// puts the granular energy flux q = C |u_slip|^2 - (sqrt(3) pi / 4) (1 - e_w^2) (a / a_max)
// rho_s g0 Theta^(3/2) [W/m^2] into the material (the slip work becomes fluctuation energy, and
// inelastic grain-wall collisions of restitution e_w dissipate some), q = kappa dTheta/dn with n
// out of the material. a, g0, Theta, eta and u_slip are the kernel means of the fluid a wall
// particle sees (u_slip tangential, (1 - d / (d + b)) (v~ - u_m) by the Navier profile), a_max the
// dense packing rho0 / rho_s; a wall particle's surface element n dS is that of the wall loads,
// and its power q dS goes to the fluid particles it sees in proportion to V_f W_wf (a heat source
// q dS W_wf / sum_f V_f W_wf [W/m^3]; the dissipation implicit like gamma_s).
// Time integration: kick-drift-kick (velocity Verlet) with the density advanced after the drift;
// the step is the smallest of the acoustic (cfl h / (c0 + |v|max)), force (0.25 sqrt(h / |a|max))
// and viscous (0.125 h^2 rho0 / eta_max) limits (Monaghan, Rep. Prog. Phys. 68 (2005) 1703,
// sec. 10; Morris et al. 1997, eq. 11).
#pragma once

#include <Eigen/SparseCore>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "continuum/ktgf.hpp"
#include "continuum/rheology.hpp"
#include "continuum/sph_kernel.hpp"
#include "core/domain.hpp"
#include "neighbor/cell_list.hpp"

namespace gf::continuum {

/// A region of the continuum at t = 0: lattice points of spacing dx in a box, or in a cylinder
/// (a disk in 2D) but not deeper than `thickness` below its surface (an annulus: the fluid
/// between two coaxial cylinder walls, on the same lattice when they share the centre).
struct SphBlock {
  enum class Shape { Box, Cylinder };
  Vec3 lo, hi;      ///< Box: corners [m] (Cylinder: unused by the solver)
  Vec3 velocity{};  ///< initial velocity [m/s]
  /// Start at hydrostatic pressure instead of at p = 0, so that a resting column does not first
  /// oscillate: p = rho0 |g_k| (depth below the block's top), along the axis k closest to -g.
  bool hydrostatic = false;
  Shape shape = Shape::Box;
  Vec3 center{};           ///< Cylinder: a point of the axis [m]
  Vec3 axis{0, 0, 1};      ///< Cylinder: unit axis (2D: z, a disk)
  double radius = 0.0;     ///< Cylinder [m]
  double length = 0.0;     ///< Cylinder, 3D: length along the axis, centred on `center` [m]
  double thickness = 0.0;  ///< Cylinder: annulus thickness [m] (0: solid)
  /// With kinetic theory: the block's volume fraction a, its density a rho_s (unset: the
  /// reference density rho0); ignored without kinetic theory
  std::optional<double> volume_fraction{};
};

/// A solid wall made of boundary particles: the lattice points of spacing dx inside a box, or
/// inside a cylinder (a disk in 2D) but not deeper than `thickness` below its surface. It moves
/// rigidly: a constant translation `velocity` and a constant rotation `angular_velocity` about
/// its rotation centre, which moves with `velocity` (see the file comment).
struct SphWall {
  enum class Shape { Box, Cylinder };
  std::string name;
  Shape shape = Shape::Box;
  Vec3 lo, hi;             ///< Box: corners [m]
  Vec3 center;             ///< Cylinder: a point of the axis [m]
  Vec3 axis{0, 0, 1};      ///< Cylinder: unit axis (2D: z, a disk)
  double radius = 0.0;     ///< Cylinder [m]
  double length = 0.0;     ///< Cylinder, 3D: length along the axis, centred on `center` [m]
  double thickness = 0.0;  ///< Cylinder: shell thickness [m] (0: solid)
  Vec3 velocity{};         ///< constant translation velocity of the wall [m/s]
  /// constant angular velocity of the wall about its rotation centre [rad/s] (2D: z only)
  Vec3 angular_velocity{};
  /// the point the wall rotates about, at t = 0 [m]; it moves with `velocity`. Unset: the box's
  /// centre (lo + hi) / 2 or the cylinder's `center`
  std::optional<Vec3> rotation_center;
  /// the wall's lattice is built turned by this angle about the rotation axis through the
  /// rotation centre [rad] (2D: about z, so that a box can be a blade at any angle; 3D: about
  /// angular_velocity, which must then be non-zero)
  double initial_angle = 0.0;
  /// Free slip: the wall exerts no shear stress; its particles give pressure (and artificial
  /// viscosity) but take no part in the viscous term. Default no slip (mirrored velocities).
  bool free_slip = false;
  /// Partial slip (Navier): the fluid slips along the wall at u_s - u_w = b dv/dn, slip length
  /// b [m] (Gomez Fino 2014, eq. 15, with b = b/a). 0: no slip; ignored on a free-slip wall.
  double slip_length = 0.0;
  /// The Johnson & Jackson (1987) wall of kinetic theory: partial slip with the local slip
  /// length b = mu / C, C = (pi sqrt(3) / 6) phi' (a / a_max) rho_s g0 sqrt(Theta), and the
  /// granular energy flux q = C |u_slip|^2 - (sqrt(3) pi / 4) (1 - e_w^2) (a / a_max) rho_s g0
  /// Theta^(3/2) into the material (see the file comment).
  struct JohnsonJackson {
    double specularity = 0.0;       ///< phi' in [0, 1] (0: free slip, specular reflections)
    double wall_restitution = 1.0;  ///< e_w in [0, 1], grain-wall (1: no dissipation at the wall)
  };
  /// Only with kinetic theory; excludes free_slip and slip_length (unset: not such a wall).
  std::optional<JohnsonJackson> johnson_jackson;
};

/// The granular phase by kinetic theory (KTGF) with a dense regime: the continuum's density is
/// the bulk density a rho_s of grains at volume fraction a, and each particle carries a granular
/// temperature Theta (see "Kinetic theory" in the file comment).
struct SphKineticTheory {
  KtgfParams closures;               ///< closure set, g0, restitution, grain diameter and density
  FrictionalParams dense;            ///< dense regime: mu_i_switch or schaeffer_johnson_jackson
  double initial_temperature = 0.0;  ///< Theta of the blocks at t = 0 [m^2/s^2]
  /// floor of Theta [m^2/s^2]: a gas at Theta = 0 has no viscosity to heat it by shear, and
  /// would stay cold
  double min_temperature = 1e-10;
};

struct SphConfig {
  int dimension = 2;
  Domain domain;                 ///< particles leaving it in a non-periodic direction are removed
  Vec3 gravity{};                ///< body force per unit mass [m/s^2]
  double spacing = 0.0;          ///< initial particle spacing dx [m]
  double smoothing_ratio = 1.3;  ///< h / dx
  double density = 1000.0;       ///< reference density rho0 [kg/m^3]
  double sound_speed = 0.0;      ///< artificial speed of sound c0 [m/s]
  double eos_exponent = 7.0;
  double background_pressure = 0.0;  ///< p_b [Pa]
  double density_diffusion = 0.1;    ///< delta (0: none)
  /// alpha of Monaghan's artificial viscosity (0: none); damps the acoustic noise of a weakly
  /// compressible liquid whose physical viscosity is too small to do so
  double artificial_viscosity = 0.0;
  /// Integrate the viscous term implicitly (backward Euler, after the pressure kick-drift-kick):
  /// no viscous time-step limit, for stiff materials (a mu(I) pile at rest with a large
  /// max_viscosity). First order in time for the viscous part.
  bool implicit_viscosity = false;
  RheologyParams rheology;  ///< the material's rheology (with kinetic theory: the dense one)
  std::optional<SphKineticTheory> kinetic_theory;
  double cfl = 0.2;        ///< acoustic Courant number
  double max_step = 1e30;  ///< upper bound of the time step [s]
  std::vector<SphBlock> blocks;
  std::vector<SphWall> walls;
};

/// Particle fields, fluid particles first ([0, n_fluid)), then wall particles.
struct SphParticles {
  std::vector<std::int64_t> id;
  std::vector<Vec3> x, v, a;             ///< [m], [m/s], [m/s^2]
  std::vector<double> rho, drho, p;      ///< [kg/m^3], [kg/m^3/s], [Pa]
  std::vector<double> mass;              ///< fluid: [kg]; walls: rho V0 (updated each step)
  std::vector<double> eta, gamma_dot;    ///< apparent viscosity [Pa s], shear rate [1/s]
  std::vector<Vec3> u_wall;              ///< walls: prescribed (rigid-body) velocity [m/s]
  std::vector<Vec3> v_ghost;             ///< walls: mirrored velocity for no slip [m/s]
  std::vector<std::int32_t> wall_index;  ///< walls: index in SphConfig::walls; fluid: -1
  /// granular temperature Theta, the velocity variance per component [m^2/s^2] (kinetic
  /// theory; otherwise 0)
  std::vector<double> theta;
  /// implicit viscosity: the velocity change of the particle's last viscous solve [m/s], which
  /// starts the next solve (walls and explicit viscosity: 0)
  std::vector<Vec3> dv_viscous;
  std::size_t size() const { return x.size(); }
};

/// Whole-system figures of the fluid particles at the current time.
struct SphSummary {
  std::size_t n_fluid = 0;
  double kinetic_energy = 0.0;      ///< [J] (2D: per metre of depth)
  double max_speed = 0.0;           ///< [m/s]
  Vec3 min_position, max_position;  ///< bounding box of the fluid [m]
  double max_density_error = 0.0;   ///< max |rho / rho0 - 1|
  double max_viscosity = 0.0;       ///< [Pa s]
  /// kinetic theory: mass-weighted mean granular temperature [m^2/s^2] and the range of the
  /// volume fraction rho / rho_s
  double mean_temperature = 0.0;
  double min_volume_fraction = 0.0, max_volume_fraction = 0.0;
};

/// Everything besides the case that a run's continuation needs to go on bit-identically.
struct SphState {
  SphParticles particles;
  std::vector<Vec3> x_built;  ///< positions at the last neighbour-list build
  std::size_t n_fluid = 0, n_removed = 0;
  double t = 0.0, dt_last = 0.0, a_max = 0.0, v_max = 0.0, eta_max = 0.0;
  std::int64_t steps = 0;
};

/// What the fluid exerts on each wall (SphConfig::walls order).
struct SphWallLoads {
  std::vector<Vec3> force;   ///< [N] (2D: per metre of depth)
  std::vector<Vec3> torque;  ///< about the wall's rotation centre [N m] (2D: per metre, along z)
};

class SphSolver {
 public:
  /// Builds the particles and computes the first accelerations. Throws gf::Error for a
  /// configuration that cannot run (no particles, a fluid particle closer than dx/2 to a wall
  /// particle, a wall outside the domain, a periodic length below the support).
  explicit SphSolver(const SphConfig& cfg);

  /// One time step of the stable size (capped by max_step and by `until` - time() if > 0).
  void step(double until = 0.0);

  double time() const { return t_; }
  double last_step() const { return dt_last_; }
  std::int64_t steps() const { return steps_; }
  /// The next step's size [s].
  double stable_step() const;
  /// BiCGSTAB iterations of the last implicit viscous solve (last component).
  int viscous_iterations() const { return last_viscous_iterations_; }
  /// Mean BiCGSTAB iterations per velocity component of this run's implicit viscous solves
  /// (since the start or the restore; 0 without any).
  double mean_viscous_iterations() const {
    return viscous_solves_ > 0 ? static_cast<double>(viscous_iterations_total_) /
                                     static_cast<double>(viscous_solves_)
                               : 0.0;
  }
  /// Largest fluid speed [m/s] (infinite once the run has diverged).
  double max_speed() const { return v_max_; }
  std::size_t n_fluid() const { return n_fluid_; }
  std::size_t n_removed() const { return n_removed_; }
  const SphParticles& particles() const { return p_; }
  const SphConfig& config() const { return cfg_; }
  const WendlandC2& kernel() const { return w_; }
  double pressure_of(double rho) const;
  double density_of(double pressure) const;
  SphSummary summary() const;
  /// The state a checkpoint holds.
  SphState state() const;
  /// Continues from `state` (a checkpoint of a run of the same case): the neighbour list is
  /// rebuilt from the positions it was built at, so the run goes on bit-identically. A state
  /// with another number of wall particles (another case) throws gf::InputError.
  void restore(const SphState& state);
  /// Force [N] and torque [N m] of the fluid on each wall (SphConfig::walls order) at the
  /// current state, in one pass over the wall particles (2D: per metre of depth, the torque
  /// along z). The force is the reaction of the pair forces the wall's particles exert on the
  /// fluid (a rotating wall: plus its surface term), the torque is about the wall's rotation
  /// centre c(t) (also for a wall that does not turn); see the file comment.
  SphWallLoads wall_loads() const;
  std::vector<Vec3> wall_forces() const { return wall_loads().force; }
  std::vector<Vec3> wall_torques() const { return wall_loads().torque; }
  /// Rotation centre c(t) = c0 + V t of wall `wall` (SphConfig::walls order) at the current
  /// time [m] (unwrapped: it may lie outside a periodic domain).
  Vec3 wall_center(std::size_t wall) const;

 private:
  void build_particles();
  /// Wall particles' positions (if `positions`) and velocities at time t [s] from their
  /// positions at t = 0 (rigid motion).
  void move_walls(double t, bool positions);
  /// What the fluid exerts on one wall particle: force [N] and moment about the particle [N m]
  /// (2D: per metre of depth).
  struct WallLoad {
    Vec3 force, moment;
  };
  /// Per wall particle (index - n_fluid_).
  std::vector<WallLoad> wall_particle_loads() const;
  void build_neighbours();
  void continuity_and_strain(double dt);
  void extrapolate_walls();
  void momentum();
  /// Acceleration of fluid particle i from neighbour j (pressure, viscous, artificial viscous).
  Vec3 pair_acceleration(std::size_t i, std::size_t j, bool viscous) const;
  /// k_ij >= 0 of the Morris term dv_i/dt = sum_j k_ij (v_j - v_i) [1/s], for r = |r_ij| and
  /// dw = W'(r).
  double viscous_coefficient(std::size_t i, std::size_t j, double r, double dw) const;
  /// The same for a diffusion (1 / rho) div(q grad f) ~ sum_j k_ij (f_j - f_i) with
  /// coefficients q_i, q_j (eta: the viscous term; kappa: heat conduction).
  double laplacian_coefficient(std::size_t i, std::size_t j, double r, double dw, double q_i,
                               double q_j) const;
  /// Kinetic theory: the volume fraction rho / rho_s the closures are evaluated at (kept
  /// below the radial distribution's packing limit).
  double volume_fraction_for_closures(double rho) const;
  void implicit_viscous_step(double dt);
  /// Kinetic theory: a fluid particle's closures at its density, at unit granular temperature.
  /// Every closure set scales at fixed a as P_s ~ Theta, mu_s, lambda_s, kappa_s ~ sqrt(Theta) and
  /// gamma_s ~ Theta^(3/2) (for hard spheres sqrt(Theta) is the only velocity scale; the same
  /// scaling ktgf_simple_shear uses), so that one evaluation per particle and step serves both the
  /// temperature balance at the old Theta and the state at the new one.
  struct KtClosures {
    double a = 0.0;                ///< the volume fraction they are evaluated at [1]
    double g0 = 0.0;               ///< radial distribution at contact [1]
    double pressure = 0.0;         ///< P_s / Theta [kg/m^3]
    double shear_viscosity = 0.0;  ///< mu_s / sqrt(Theta) [kg/m^2]
    double bulk_viscosity = 0.0;   ///< lambda_s / sqrt(Theta) [kg/m^2]
    double conductivity = 0.0;     ///< kappa_s / sqrt(Theta) [kg/m^2]
    double dissipation = 0.0;      ///< gamma_s / Theta^(3/2) [kg/m^4]
    double sound_speed = 0.0;      ///< the granular gas's sound speed / sqrt(Theta) [1]
  };
  KtClosures kinetic_theory_closures(double rho) const;
  /// Kinetic theory: pressure, viscosity and conductivity of fluid particle i from its closures
  /// (kt_closures_[i]), temperature, shear rate and velocity divergence.
  void kinetic_theory_state(std::size_t i);
  /// Kinetic theory: the granular energy balance of fluid particle i over dt without
  /// conduction, linearised: Theta_new diag = rhs (+ dt (2/3) (1 / rho) div(kappa grad Theta)).
  struct TemperatureBalance {
    double rhs, diag;
  };
  TemperatureBalance temperature_balance(std::size_t i, double dt) const;
  /// Kinetic theory with Johnson-Jackson walls: each such wall particle's granular energy flux
  /// (jj_heat_) from the current state, and each fluid particle's share (jj_source_, jj_sink_).
  void johnson_jackson_heat();
  /// Johnson-Jackson wall `wall`: the fraction s = d / (d + b) = d C / (d C + eta) of the wall's
  /// velocity at the mirror surface, from the kernel sums over the fluid the wall particle sees:
  /// sum_ag = sum_f a g0 sqrt(Theta) W, eta = its mean viscosity, dist = d [m].
  double johnson_jackson_grip(std::size_t wall, double sum_ag, double sum_w, double eta,
                              double dist) const;
  /// Kinetic theory with implicit viscosity: the balance with backward-Euler conduction.
  void implicit_conduction_step(double dt);
  /// Kinetic theory: the time-step limits (sound speed, diffusivities) from the fluid particles'
  /// closures, temperatures, viscosities and conductivities.
  void update_kinetic_theory_limits();
  /// Kinetic theory: every fluid particle's closures and conductivity from its density and
  /// temperature, then the limits: at set-up and after a restore (a step computes them as it
  /// updates the particles, in the same way, so that a continued run stays bit-identical).
  void refresh_kinetic_theory();
  /// Removes fluid particles outside the domain's non-periodic bounds; true if any was.
  bool remove_escaped();
  bool moved_beyond_skin() const;
  void update_max_speed();
  double skin() const { return 0.1 * w_.support(); }

  SphConfig cfg_;
  WendlandC2 w_;
  double volume0_ = 0.0;  ///< dx^d
  /// 2d / (2 sum_j V (f_i - f_j) r_ij . grad W / (r^2 + 0.01 h^2)) for f = |x - x_i|^2 over the
  /// initial lattice: scales the viscous sum so that it is exact for a quadratic velocity field
  /// in the interior (the sum alone is 1-4 % low for h / dx = 1.3-2, mostly from the 0.01 h^2)
  double laplacian_scale_ = 1.0;
  /// d / tr(sum_j V (x_j - x_i) (x) grad_i W_ij) over the initial lattice: scales the pressure
  /// gradient and the velocity divergence so that they are exact for linear fields in the
  /// interior (the sum alone is 2.6 % low at h / dx = 1.3: a resting column's pressure would be
  /// 2.6 % high, and a mu(I) flow, whose shear stress must be mu(I) p, 20 % slow)
  double gradient_scale_ = 1.0;
  double b_eos_ = 0.0;  ///< rho0 c0^2 / gamma
  SphParticles p_;
  std::size_t n_fluid_ = 0, n_removed_ = 0;
  /// A wall's rigid motion: centre at t = 0 [m], translation [m/s], rotation axis (unit) and
  /// rate [rad/s].
  struct WallMotion {
    Vec3 c0, velocity, omega, axis;
    double rate = 0.0;
    bool translates = false, rotates = false;
  };
  std::vector<WallMotion> wall_motion_;  ///< per wall (SphConfig::walls order)
  std::vector<Vec3> wall_x0_;            ///< per wall particle (index - n_fluid_): x at t = 0
  std::vector<char> free_slip_;          ///< per wall (SphConfig::walls order)
  std::vector<double> slip_length_;      ///< per wall: Navier slip length b [m] (0: no slip)
  /// per wall: the Johnson-Jackson constants (pi sqrt(3) / 6) phi' rho_s / a_max and
  /// (sqrt(3) pi / 4) (1 - e_w^2) rho_s / a_max [kg/m^3] (0 for other walls), whether it is one
  std::vector<double> jj_shear_, jj_dissipation_;
  std::vector<char> jj_wall_;
  bool any_jj_ = false;
  /// Johnson-Jackson walls: what a wall particle's surface element puts into the fluid it sees
  struct JjHeat {
    double production = 0.0, dissipation = 0.0;  ///< q dS / sum_f V_f W_wf, each part [W]
  };
  std::vector<JjHeat> jj_heat_;  ///< per wall particle (index - n_fluid_)
  /// per fluid particle: the Johnson-Jackson walls' heat source and sink [W/m^3]
  std::vector<double> jj_source_, jj_sink_;
  /// Whether neighbour j shears fluid particle i through the viscous term: a fluid particle or
  /// a particle of a no-slip wall.
  bool viscous_partner(std::size_t j) const {
    return j < n_fluid_ || !free_slip_[static_cast<std::size_t>(p_.wall_index[j])];
  }
  CellList cells_;
  Domain cell_domain_;
  std::vector<std::int64_t> nbr_start_;
  std::vector<std::int32_t> nbr_;
  std::vector<Vec3> x_built_;     ///< positions at the last neighbour-list build
  std::vector<double> inv_wsum_;  ///< per wall particle: 1 / sum_f W_wf (0: no fluid near)
  /// per wall particle: the wall velocity its mirrored velocity is built on, v_w = 2 u - v~
  /// [m/s] (u_wall, or a rotating wall's at the midpoint towards the fluid's centroid)
  std::vector<Vec3> u_mirror_;
  /// per wall particle: the weight s of the fluid's mean velocity in its mirrored velocity
  /// v_w = 2 u_m - s sum_f v_f W_wf / sum_f W_wf (1 without slip; see extrapolate_walls)
  std::vector<double> mirror_weight_;
  // Kinetic theory, per fluid particle (recomputed every step from the state: not in SphState)
  std::vector<double> div_v_;                   ///< velocity divergence [1/s]
  std::vector<double> heat_;                    ///< (1 / rho) div(kappa grad Theta) [W/kg]
  std::vector<double> theta_rhs_, theta_diag_;  ///< the temperature balance (implicit conduction)
  std::vector<double> conductivity_;            ///< kappa_s [kg/(m s)]
  std::vector<KtClosures> kt_closures_;         ///< at the particle's density (see KtClosures)
  double kt_sound_max_ = 0.0;                   ///< largest sound speed of the granular gas [m/s]
  double kt_diffusivity_max_ = 0.0;  ///< largest of eta / rho and kappa / (3/2 rho) [m^2/s]
  int last_viscous_iterations_ = 0;
  std::int64_t viscous_iterations_total_ = 0, viscous_solves_ = 0;
  std::vector<std::vector<Eigen::Triplet<double>>> visc_rows_;  ///< implicit step, per row
  std::vector<Eigen::Triplet<double>> visc_triplets_;
  double t_ = 0.0, dt_last_ = 0.0;
  std::int64_t steps_ = 0;
  double a_max_ = 0.0, v_max_ = 0.0, eta_max_ = 0.0;
};

}  // namespace gf::continuum
