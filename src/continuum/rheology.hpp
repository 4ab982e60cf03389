// SPDX-License-Identifier: GPL-3.0-or-later
// Rheologies of a continuum phase: apparent viscosity eta(shear rate, pressure). Small value types
// with pure inline functions (host and device), listed in continuum/rheology_registry.hpp.
//
// Every model gives the dynamic viscosity eta [Pa s] from the shear rate gamma_dot =
// sqrt(2 D:D) [1/s] (D the strain-rate tensor) and the pressure p [Pa]; the deviatoric stress is
// then tau = 2 eta D. A solver caps no value itself: each model keeps eta finite where its
// formula diverges (gamma_dot -> 0 for a yield-stress material) by its own regularisation.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include "core/error.hpp"
#include "core/host_device.hpp"
#include "core/params.hpp"

namespace gf::continuum {

/// Constants a rheology's eval reads, derived once from its parameters (prepare_rheology).
struct RheologyParams {
  int model = 0;                ///< index in Rheologies
  double viscosity = 0.0;       ///< Newtonian: eta [Pa s]
  double mu_s = 0.0;            ///< mu(I): static friction coefficient [1]
  double mu_2 = 0.0;            ///< mu(I): limiting friction coefficient at large I [1]
  double i0 = 0.0;              ///< mu(I): inertial number scale [1]
  double grain_diameter = 0.0;  ///< mu(I): d [m]
  double grain_density = 0.0;   ///< mu(I): rho_s [kg/m^3]
  double max_viscosity = 0.0;   ///< mu(I): regularisation cap eta_max [Pa s]
};

/// Newtonian fluid: constant dynamic viscosity.
struct Newtonian {
  static constexpr std::string_view key = "newtonian";
  static constexpr std::string_view summary = "Newtonian fluid: constant dynamic viscosity";
  static constexpr std::string_view equation = "tau = 2 eta D,  eta = viscosity";
  static constexpr std::string_view reference =
      "Stokes (1845); e.g. Batchelor, An Introduction to Fluid Dynamics (1967) sec. 3.3";
  static constexpr std::array<ParamSpec, 1> params{{
      {"viscosity", "Pa s", std::nullopt, 0.0, 1e12, false, ParamScope::PerMaterial,
       "dynamic viscosity eta (water at 20 C: 1.0e-3)"},
  }};
  template <class Get>
  static void prepare(RheologyParams& p, Get&& get) {
    p.viscosity = *get("viscosity");
  }
  GF_HOST_DEVICE static double eval(double /*gamma_dot*/, double /*pressure*/,
                                    const RheologyParams& p) {
    return p.viscosity;
  }
};

/// The mu(I) rheology of dense granular flows (Jop, Forterre & Pouliquen 2006): a visco-plastic
/// fluid whose shear stress is mu(I) times the pressure. Below the yield criterion (gamma_dot ->
/// 0) the apparent viscosity is capped at max_viscosity (the regularisation of Lagree, Staron &
/// Popinet 2011), so a static pile creeps at gamma_dot ~ mu_s p / eta_max.
struct MuI {
  static constexpr std::string_view key = "mu_i";
  static constexpr std::string_view summary =
      "dense granular flow: friction mu(I) of the inertial number, regularised visco-plastic";
  static constexpr std::string_view equation =
      "tau = 2 eta D,  eta = min(mu(I) p+ / gamma_dot, eta_max),  mu(I) = mu_s + (mu_2 - mu_s) / "
      "(I0 / I + 1),  I = gamma_dot d / sqrt(p+ / rho_s),  gamma_dot = sqrt(2 D:D),  p+ = "
      "max(p, 0)";
  static constexpr std::string_view reference =
      "Jop, Forterre & Pouliquen, Nature 441 (2006) 727, eqs. (1)-(3); GDR MiDi, Eur. Phys. J. "
      "E 14 (2004) 341; regularisation: Lagree, Staron & Popinet, J. Fluid Mech. 686 (2011) 378, "
      "sec. 2.2";
  static constexpr std::array<ParamSpec, 6> params{{
      {"mu_s", "1", 0.382, 0.0, 10.0, false, ParamScope::PerMaterial,
       "friction coefficient at vanishing I, tan of the angle of repose (glass beads, Jop et al. "
       "2006: tan 20.9 deg)"},
      {"mu_2", "1", 0.643, 0.0, 10.0, false, ParamScope::PerMaterial,
       "limiting friction coefficient at large I (glass beads: tan 32.76 deg); must exceed mu_s"},
      {"i0", "1", 0.279, 0.0, 100.0, true, ParamScope::PerMaterial,
       "inertial number at which mu is halfway between mu_s and mu_2 (glass beads: 0.279)"},
      {"grain_diameter", "m", std::nullopt, 0.0, 1.0, true, ParamScope::PerMaterial,
       "grain diameter d"},
      {"grain_density", "kg/m^3", std::nullopt, 0.0, 1e5, true, ParamScope::PerMaterial,
       "density of the grains' material rho_s (the continuum's density is phi rho_s)"},
      {"max_viscosity", "Pa s", std::nullopt, 0.0, 1e12, true, ParamScope::PerMaterial,
       "regularisation: cap of the apparent viscosity where gamma_dot -> 0 (a larger cap makes "
       "static regions stiffer and the viscous time step smaller)"},
  }};
  template <class Get>
  static void prepare(RheologyParams& p, Get&& get) {
    p.mu_s = get("mu_s").value_or(0.382);
    p.mu_2 = get("mu_2").value_or(0.643);
    p.i0 = get("i0").value_or(0.279);
    p.grain_diameter = *get("grain_diameter");
    p.grain_density = *get("grain_density");
    p.max_viscosity = *get("max_viscosity");
    REQUIRE(p.mu_2 > p.mu_s, "rheology 'mu_i': mu_2 = {} must exceed mu_s = {}", p.mu_2, p.mu_s);
  }
  /// mu(I) [1].
  GF_HOST_DEVICE static double friction(double inertial_number, const RheologyParams& p) {
    return p.mu_s + (p.mu_2 - p.mu_s) * inertial_number / (p.i0 + inertial_number);
  }
  /// The inertial number that realises friction mu (mu_s < mu < mu_2): I = I0 (mu - mu_s) /
  /// (mu_2 - mu), the steady-flow value on an incline of slope tan(theta) = mu.
  GF_HOST_DEVICE static double inertial_number_for(double mu, const RheologyParams& p) {
    return p.i0 * (mu - p.mu_s) / (p.mu_2 - mu);
  }
  GF_HOST_DEVICE static double eval(double gamma_dot, double pressure, const RheologyParams& p) {
    const double pp = pressure > 0.0 ? pressure : 0.0;
    if (!(gamma_dot > 0.0)) return pp > 0.0 ? p.max_viscosity : 0.0;
    // I -> infinity at p+ = 0: mu = mu_2, and eta = 0 (no pressure, no friction)
    const double mu =
        pp > 0.0 ? friction(gamma_dot * p.grain_diameter * std::sqrt(p.grain_density / pp), p)
                 : p.mu_2;
    const double eta = mu * pp / gamma_dot;
    return eta < p.max_viscosity ? eta : p.max_viscosity;
  }
};

}  // namespace gf::continuum
