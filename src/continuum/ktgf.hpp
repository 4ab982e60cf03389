// SPDX-License-Identifier: GPL-3.0-or-later
// Kinetic theory of granular flow (KTGF): closures of a monodisperse granular phase for a two-fluid
// model (solids pressure, viscosities, conductivity, dissipation), dense-region frictional
// closures and the homogeneous shear and cooling states they predict. Registered value types.
//
// State: volume fraction a (alpha_s) [1], granular temperature Theta [m^2/s^2], the velocity
// variance per component (Theta = <C.C>/3, C the fluctuation velocity). The granular energy per
// unit volume is (3/2) a rho_s Theta and obeys
//   (3/2) [d(a rho_s Theta)/dt + div(a rho_s Theta u)] = sigma:grad(u) - div(q) - gamma_s,
//   sigma = -P_s I + 2 mu_s D + (lambda_s - (2/3) mu_s) tr(D) I,   q = -kappa_s grad(Theta)
// (Syamlal, Rogers & O'Brien 1993; van Wachem et al. 2001). Every viscosity here is the
// whole coefficient of that stress, as in MFIX: some codes and papers write mu_s and lambda_s per
// unit a_s and multiply the stress by a_s (the seed's eq 5 is written that way); compare totals.
//
// With eta = (1 + e) / 2 and the Chapman-Enskog dilute-gas values for hard spheres
//   mu*    = (5/96)  rho_s d sqrt(pi Theta)   = (5/16) m sqrt(Theta/pi) / d^2  (m the grain mass)
//   kappa* = (75/384) rho_s d sqrt(pi Theta)  = (15/4) mu*
// (Chapman & Cowling 1970, ch. 10; Theta in place of k T / m), the three sets are:
//   lun      Lun, Savage, Jeffrey & Chepurniy (1984): the first Sonine approximation for slightly
//            inelastic smooth spheres; at e = 1 it is Enskog's dense-gas theory.
//   syamlal  Syamlal, Rogers & O'Brien (1993, the MFIX theory guide): Lun's closures without the
//            purely streaming ("1 +") terms, i.e. their dense-gas part; mu_s and kappa_s vanish
//            like a, P_s like a^2 in the dilute limit (no Chapman-Enskog limit).
//   gidaspow Gidaspow (1994): the elastic (Enskog) closures with an e-dependent prefactor on the
//            dilute terms; at e = 1 identical to lun.
// All three share Lun's bulk viscosity and the Jenkins & Savage (1983) / Lun et al. (1984)
// dissipation gamma_s = 12 (1 - e^2) g0 rho_s a^2 Theta^(3/2) / (d sqrt(pi)). They are tabulated
// side by side in van Wachem, Schouten, van den Bleek, Krishna & Sinclair, AIChE J. 47 (2001) 1035.
//
// The radial distribution at contact g0(a) is its own small registry (RadialDistributions): it is
// a modelling choice orthogonal to the closure set (codes offer every g0 with every set), it has
// its own parameter (the packing limit of Lun-Savage), and it gets its own line in list-models.
//
// Validity: binary, instantaneous collisions of smooth spheres (no rotational energy), nearly
// elastic (first-order Chapman-Enskog: 1 - e << 1), no enduring contacts. Above a frictional
// packing limit (around 0.5-0.55) enduring contacts carry the stress: FrictionalModels add a
// frictional closure or switch to the mu(I) rheology there.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "continuum/rheology_registry.hpp"
#include "core/error.hpp"
#include "core/host_device.hpp"
#include "core/params.hpp"
#include "core/registry.hpp"

namespace gf::continuum {

/// Constants the KTGF closures read, derived once from their parameters (prepare_ktgf).
struct KtgfParams {
  int model = 0;               ///< index in KtgfClosures
  int radial = 0;              ///< index in RadialDistributions
  double restitution = 0.0;    ///< e, grain-grain coefficient of normal restitution [1]
  double diameter = 0.0;       ///< d, grain diameter [m]
  double density = 0.0;        ///< rho_s, density of the grains' material [kg/m^3]
  double packing_limit = 0.0;  ///< a_max where g0 diverges (1 for carnahan_starling) [1]
};

namespace ktgf_detail {
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kLn10 = 2.30258509299404568402;
inline constexpr double kSqrtPi = 1.77245385090551602730;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// mu* = (5/96) rho_s d sqrt(pi Theta), the Chapman-Enskog viscosity of a dilute hard-sphere gas.
GF_HOST_DEVICE inline double dilute_viscosity(double theta, const KtgfParams& p) {
  return 5.0 / 96.0 * p.density * p.diameter * std::sqrt(kPi * theta);
}
/// kappa* = (75/384) rho_s d sqrt(pi Theta), the Chapman-Enskog conductivity (15/4 mu*).
GF_HOST_DEVICE inline double dilute_conductivity(double theta, const KtgfParams& p) {
  return 75.0 / 384.0 * p.density * p.diameter * std::sqrt(kPi * theta);
}
/// Lun's bulk viscosity lambda_s = (4/3) a^2 rho_s d g0 (1 + e) sqrt(Theta / pi) (Lun et al.
/// 1984; the same in all three sets).
GF_HOST_DEVICE inline double lun_bulk_viscosity(double a, double theta, double g0,
                                                const KtgfParams& p) {
  return 4.0 / 3.0 * a * a * p.density * p.diameter * g0 * (1 + p.restitution) *
         std::sqrt(theta / kPi);
}
/// Collisional dissipation gamma_s = 12 (1 - e^2) g0 rho_s a^2 Theta^(3/2) / (d sqrt(pi)) [W/m^3]
/// (Jenkins & Savage 1983; Lun et al. 1984: (48/sqrt(pi)) eta (1 - eta) ..., the same number).
GF_HOST_DEVICE inline double collisional_dissipation(double a, double theta, double g0,
                                                     const KtgfParams& p) {
  const double e = p.restitution;
  return 12.0 * (1 - e * e) * g0 * p.density * a * a * theta * std::sqrt(theta) /
         (p.diameter * kSqrtPi);
}
/// The collisional shear viscosity (4/5) a^2 rho_s d g0 (1 + e) sqrt(Theta / pi) shared by
/// syamlal and gidaspow (= 768/(25 pi) eta a^2 g0 mu*, Lun's last term).
GF_HOST_DEVICE inline double collisional_shear_viscosity(double a, double theta, double g0,
                                                         const KtgfParams& p) {
  return 0.8 * a * a * p.density * p.diameter * g0 * (1 + p.restitution) * std::sqrt(theta / kPi);
}
}  // namespace ktgf_detail

// ---------------------------------------------------------------------------------------------
// Radial distribution at contact g0(a)
// ---------------------------------------------------------------------------------------------

/// Carnahan & Starling (1969), J. Chem. Phys. 51:635, via the compressibility
/// Z = 1 + 4 a g0: g0 = (1 - a/2) / (1 - a)^3 (= 1/(1-a) + 3a/(2(1-a)^2) + a^2/(2(1-a)^3), the
/// form MFIX and Fluent print). Accurate for the hard-sphere fluid up to freezing (a ~ 0.49);
/// diverges only at a = 1, so it does not know random close packing.
struct CarnahanStarling {
  static constexpr std::string_view key = "carnahan_starling";
  static constexpr std::string_view summary =
      "radial distribution at contact of the hard-sphere fluid (diverges at a = 1)";
  static constexpr std::string_view equation = "g0(a) = (1 - a/2) / (1 - a)^3";
  static constexpr std::string_view reference =
      "Carnahan & Starling, J. Chem. Phys. 51 (1969) 635 (the equation of state Z = (1 + a + a^2 "
      "- a^3) / (1 - a)^3 = 1 + 4 a g0)";
  static constexpr std::array<ParamSpec, 0> params{};
  template <class Get>
  static void prepare(KtgfParams& p, Get&& /*get*/) {
    p.packing_limit = 1.0;
  }
  GF_HOST_DEVICE static double g0(double a, const KtgfParams& /*p*/) {
    if (!(a < 1.0)) return ktgf_detail::kInf;
    const double q = 1.0 - a;
    return (1.0 - 0.5 * a) / (q * q * q);
  }
};

/// Lun & Savage (1986), Acta Mech. 63:15: g0 = (1 - a/a_max)^(-2.5 a_max), which has the exact
/// second virial coefficient (g0 = 1 + 2.5 a + ...) and diverges at the packing limit a_max.
struct LunSavage {
  static constexpr std::string_view key = "lun_savage";
  static constexpr std::string_view summary =
      "radial distribution at contact diverging at a packing limit a_max";
  static constexpr std::string_view equation =
      "g0(a) = (1 - a / a_max)^(-2.5 a_max)  (a < a_max; infinite at and above a_max)";
  static constexpr std::string_view reference = "Lun & Savage, Acta Mech. 63 (1986) 15";
  static constexpr std::array<ParamSpec, 1> params{{
      {"packing_limit", "1", 0.64, 0.0, 0.7405, true, ParamScope::PerMaterial,
       "a_max, the volume fraction where g0 diverges (random close packing of equal spheres "
       "~0.64; at most the FCC packing pi/sqrt(18) = 0.7405)"},
  }};
  template <class Get>
  static void prepare(KtgfParams& p, Get&& get) {
    p.packing_limit = get("packing_limit").value_or(0.64);
  }
  GF_HOST_DEVICE static double g0(double a, const KtgfParams& p) {
    if (!(a < p.packing_limit)) return ktgf_detail::kInf;
    return std::pow(1.0 - a / p.packing_limit, -2.5 * p.packing_limit);
  }
};

/// Ma & Ahmadi (1986), J. Chem. Phys. 84:3449: a fit to hard-sphere simulation data up to random
/// close packing, g0 = (1 + 2.5 a + 4.5904 a^2 + 4.515439 a^3) / (1 - (a/a_max)^3)^0.678021 with
/// a_max = 0.64356 (part of the fit, not a parameter). Sources print the exponent as 0.67802 or
/// 0.678021: the difference changes g0 by less than 1e-6 relative below a = 0.6.
struct MaAhmadi {
  static constexpr std::string_view key = "ma_ahmadi";
  static constexpr std::string_view summary =
      "radial distribution at contact fitted up to random close packing (a_max = 0.64356)";
  static constexpr std::string_view equation =
      "g0(a) = (1 + 2.5 a + 4.5904 a^2 + 4.515439 a^3) / (1 - (a / 0.64356)^3)^0.678021";
  static constexpr std::string_view reference = "Ma & Ahmadi, J. Chem. Phys. 84 (1986) 3449";
  static constexpr std::array<ParamSpec, 0> params{};
  static constexpr double kPackingLimit = 0.64356;
  template <class Get>
  static void prepare(KtgfParams& p, Get&& /*get*/) {
    p.packing_limit = kPackingLimit;
  }
  GF_HOST_DEVICE static double g0(double a, const KtgfParams& /*p*/) {
    if (!(a < kPackingLimit)) return ktgf_detail::kInf;
    const double r = a / kPackingLimit;
    return (1.0 + a * (2.5 + a * (4.5904 + a * 4.515439))) / std::pow(1.0 - r * r * r, 0.678021);
  }
};

using RadialDistributions = TypeList<CarnahanStarling, LunSavage, MaAhmadi>;

// ---------------------------------------------------------------------------------------------
// Closure sets. Each takes g0 = g0(a) as an argument, so that one g0 per cell serves every
// property. Units: pressure [Pa], viscosities [Pa s], conductivity [kg/(m s)] (q = -kappa
// grad Theta, q in W/m^2), dissipation [W/m^3]; a [1], Theta [m^2/s^2] (>= 0).
// ---------------------------------------------------------------------------------------------

/// The restitution, diameter and density every closure set reads.
inline constexpr std::array<ParamSpec, 3> ktgf_material_params{{
    {"restitution", "1", std::nullopt, 0.0, 1.0, false, ParamScope::PerMaterial,
     "e, coefficient of normal restitution of grain-grain collisions (the theory assumes "
     "1 - e << 1; e = 1 has no dissipation and no steady sheared state)"},
    {"grain_diameter", "m", std::nullopt, 0.0, 1.0, true, ParamScope::PerMaterial,
     "grain diameter d"},
    {"grain_density", "kg/m^3", std::nullopt, 0.0, 1e5, true, ParamScope::PerMaterial,
     "density of the grains' material rho_s (the phase's bulk density is a rho_s)"},
}};

template <class Get>
inline void prepare_ktgf_material(KtgfParams& p, Get&& get) {
  p.restitution = *get("restitution");
  p.diameter = *get("grain_diameter");
  p.density = *get("grain_density");
}

/// Lun, Savage, Jeffrey & Chepurniy (1984), J. Fluid Mech. 140:223, the part on slightly inelastic
/// smooth spheres in a general flow field (equation numbers not checked here), in the form of the
/// MFIX implementation (calc_mu_s.f, granular-energy branch with no gas: mu_b = 256 mu a^2 g0 / (5
/// pi)):
///   P_s      = rho_s a Theta (1 + 4 eta a g0)
///   mu_s     = mu* / (eta (2 - eta) g0) (1 + 8/5 eta a g0) (1 + 8/5 eta (3 eta - 2) a g0)
///              + 768/(25 pi) eta a^2 g0 mu*
///   lambda_s = (4/3) a^2 rho_s d g0 (1 + e) sqrt(Theta/pi)      (= eta mu_b)
///   kappa_s  = kappa* 8 / (eta (41 - 33 eta)) [ (1/g0) (1 + 12/5 eta a g0)
///              (1 + 12/5 eta^2 (4 eta - 3) a g0) + 64/(25 pi) (41 - 33 eta) eta^2 a^2 g0 ]
///   gamma_s  = (48/sqrt(pi)) eta (1 - eta) rho_s a^2 g0 Theta^(3/2) / d
/// Kinetic (streaming) viscosity mu*/(eta (2 - eta) g0) (1 + 8/5 eta (3 eta - 2) a g0), the rest
/// collisional (as Mahajan et al. split it; analysis/kinetic_theory.hpp). Dilute limit (a -> 0):
/// mu_s -> mu* 4 / ((1 + e)(3 - e)), kappa_s -> kappa* 8 / (eta (41 - 33 eta)): the
/// Chapman-Enskog values at e = 1.
struct Lun {
  static constexpr std::string_view key = "lun";
  static constexpr std::string_view summary =
      "KTGF closures of Lun et al. (1984): slightly inelastic smooth spheres, dilute to dense";
  static constexpr std::string_view equation =
      "eta = (1+e)/2, mu* = (5/96) rho d sqrt(pi T), kappa* = (75/384) rho d sqrt(pi T);  "
      "P = rho a T (1 + 4 eta a g0);  mu = mu* / (eta (2-eta) g0) (1 + 8/5 eta a g0) (1 + 8/5 "
      "eta (3 eta - 2) a g0) + 768/(25 pi) eta a^2 g0 mu*;  lambda = (4/3) a^2 rho d g0 (1+e) "
      "sqrt(T/pi);  kappa = kappa* 8/(eta (41 - 33 eta)) [(1/g0)(1 + 12/5 eta a g0)(1 + 12/5 "
      "eta^2 (4 eta - 3) a g0) + 64/(25 pi) (41 - 33 eta) eta^2 a^2 g0];  gamma = 12 (1-e^2) g0 "
      "rho a^2 T^1.5 / (d sqrt(pi))";
  static constexpr std::string_view reference =
      "Lun, Savage, Jeffrey & Chepurniy, J. Fluid Mech. 140 (1984) 223 (slightly inelastic "
      "particles in a general flowfield); as implemented "
      "in MFIX (calc_mu_s.f) and tabulated in van Wachem et al., AIChE J. 47 (2001) 1035";
  static constexpr std::array<ParamSpec, 3> params = ktgf_material_params;
  template <class Get>
  static void prepare(KtgfParams& p, Get&& get) {
    prepare_ktgf_material(p, get);
  }
  GF_HOST_DEVICE static double pressure(double a, double theta, double g0, const KtgfParams& p) {
    const double eta = 0.5 * (1 + p.restitution);
    return p.density * a * theta * (1 + 4 * eta * a * g0);
  }
  GF_HOST_DEVICE static double kinetic_viscosity(double a, double theta, double g0,
                                                 const KtgfParams& p) {
    const double eta = 0.5 * (1 + p.restitution);
    return ktgf_detail::dilute_viscosity(theta, p) / (eta * (2 - eta) * g0) *
           (1 + 1.6 * eta * (3 * eta - 2) * a * g0);
  }
  GF_HOST_DEVICE static double shear_viscosity(double a, double theta, double g0,
                                               const KtgfParams& p) {
    const double eta = 0.5 * (1 + p.restitution);
    return kinetic_viscosity(a, theta, g0, p) * (1 + 1.6 * eta * a * g0) +
           768.0 / (25.0 * ktgf_detail::kPi) * eta * a * a * g0 *
               ktgf_detail::dilute_viscosity(theta, p);
  }
  GF_HOST_DEVICE static double bulk_viscosity(double a, double theta, double g0,
                                              const KtgfParams& p) {
    return ktgf_detail::lun_bulk_viscosity(a, theta, g0, p);
  }
  GF_HOST_DEVICE static double conductivity(double a, double theta, double g0,
                                            const KtgfParams& p) {
    const double eta = 0.5 * (1 + p.restitution);
    const double c = 41 - 33 * eta;
    return ktgf_detail::dilute_conductivity(theta, p) * 8.0 / (eta * c) *
           ((1 + 2.4 * eta * a * g0) * (1 + 2.4 * eta * eta * (4 * eta - 3) * a * g0) / g0 +
            64.0 / (25.0 * ktgf_detail::kPi) * c * eta * eta * a * a * g0);
  }
  GF_HOST_DEVICE static double dissipation(double a, double theta, double g0, const KtgfParams& p) {
    return ktgf_detail::collisional_dissipation(a, theta, g0, p);
  }
};

/// Syamlal, Rogers & O'Brien (1993), MFIX Documentation: Theory Guide, DOE/METC-94/1004, sec. on
/// the solids stress (the algebraic-temperature model: constants K1..K4 of MFIX's calc_mu_s.f);
/// the seed's eq 4 is its kinetic viscosity. (The seed's eq 5, labelled mu_coll, is Lun's bulk
/// viscosity written per unit a_s, as its text says; the collisional shear viscosity has 4/5 a^2
/// where the bulk viscosity has 4/3 a^2.)
///   P_s      = 2 (1 + e) rho_s a^2 g0 Theta                    (collisional part only)
///   mu_s     = a rho_s d sqrt(pi Theta) / (6 (3 - e)) [1 + 2/5 (1 + e)(3e - 1) a g0]   kinetic
///              + (4/5) a^2 rho_s d g0 (1 + e) sqrt(Theta/pi)                           collisional
///   lambda_s = (4/3) a^2 rho_s d g0 (1 + e) sqrt(Theta/pi)     (Lun's)
///   kappa_s  = 15 a rho_s d sqrt(pi Theta) / (4 (41 - 33 eta)) [1 + 12/5 eta^2 (4 eta - 3) a g0
///              + 16/(15 pi) (41 - 33 eta) eta a g0]
///   gamma_s  = 12 (1 - e^2) g0 rho_s a^2 Theta^(3/2) / (d sqrt(pi))
/// Each is Lun's expression without its purely streaming term: mu_s(lun) - mu_s(syamlal) =
/// mu*/(eta (2 - eta) g0) (1 + 8/5 eta (3 eta - 2) a g0), kappa_s likewise, P_s without rho a
/// Theta. So P_s ~ a^2, mu_s, kappa_s ~ a as a -> 0 (no Chapman-Enskog limit): a dense-suspension
/// set, meant for fluidised beds. The conductivity is the one Fluent and OpenFOAM attribute to
/// this paper (its own energy balance is algebraic, with no conduction).
struct Syamlal {
  static constexpr std::string_view key = "syamlal";
  static constexpr std::string_view summary =
      "KTGF closures of Syamlal, Rogers & O'Brien (1993, MFIX): Lun's dense-gas terms only";
  static constexpr std::string_view equation =
      "eta = (1+e)/2;  P = 2 (1+e) rho a^2 g0 T;  mu = a rho d sqrt(pi T) / (6 (3-e)) [1 + 2/5 "
      "(1+e)(3e-1) a g0] + (4/5) a^2 rho d g0 (1+e) sqrt(T/pi);  lambda = (4/3) a^2 rho d g0 "
      "(1+e) sqrt(T/pi);  kappa = 15 a rho d sqrt(pi T) / (4 (41 - 33 eta)) [1 + 12/5 eta^2 (4 "
      "eta - 3) a g0 + 16/(15 pi) (41 - 33 eta) eta a g0];  gamma = 12 (1-e^2) g0 rho a^2 T^1.5 "
      "/ (d sqrt(pi))";
  static constexpr std::string_view reference =
      "Syamlal, Rogers & O'Brien, MFIX Documentation: Theory Guide, DOE/METC-94/1004 (1993); "
      "conductivity as in the Fluent Theory Guide (Syamlal-O'Brien); van Wachem et al., AIChE J. "
      "47 (2001) 1035";
  static constexpr std::array<ParamSpec, 3> params = ktgf_material_params;
  template <class Get>
  static void prepare(KtgfParams& p, Get&& get) {
    prepare_ktgf_material(p, get);
  }
  GF_HOST_DEVICE static double pressure(double a, double theta, double g0, const KtgfParams& p) {
    return 2 * (1 + p.restitution) * p.density * a * a * g0 * theta;
  }
  GF_HOST_DEVICE static double kinetic_viscosity(double a, double theta, double g0,
                                                 const KtgfParams& p) {
    const double e = p.restitution;
    return a * p.density * p.diameter * std::sqrt(ktgf_detail::kPi * theta) / (6 * (3 - e)) *
           (1 + 0.4 * (1 + e) * (3 * e - 1) * a * g0);
  }
  GF_HOST_DEVICE static double shear_viscosity(double a, double theta, double g0,
                                               const KtgfParams& p) {
    return kinetic_viscosity(a, theta, g0, p) +
           ktgf_detail::collisional_shear_viscosity(a, theta, g0, p);
  }
  GF_HOST_DEVICE static double bulk_viscosity(double a, double theta, double g0,
                                              const KtgfParams& p) {
    return ktgf_detail::lun_bulk_viscosity(a, theta, g0, p);
  }
  GF_HOST_DEVICE static double conductivity(double a, double theta, double g0,
                                            const KtgfParams& p) {
    const double eta = 0.5 * (1 + p.restitution);
    const double c = 41 - 33 * eta;
    return 15 * a * p.density * p.diameter * std::sqrt(ktgf_detail::kPi * theta) / (4 * c) *
           (1 + 2.4 * eta * eta * (4 * eta - 3) * a * g0 +
            16.0 / (15.0 * ktgf_detail::kPi) * c * eta * a * g0);
  }
  GF_HOST_DEVICE static double dissipation(double a, double theta, double g0, const KtgfParams& p) {
    return ktgf_detail::collisional_dissipation(a, theta, g0, p);
  }
};

/// Gidaspow (1994), Multiphase Flow and Fluidization: Continuum and Kinetic Theory Descriptions,
/// Academic Press, the kinetic-theory chapter (dense-gas closures of Chapman & Cowling with
/// Savage's dissipation); offered by Fluent as the 'gidaspow' viscosity and conductivity:
///   P_s      = rho_s a Theta [1 + 2 (1 + e) a g0]
///   mu_s     = 10 rho_s d sqrt(pi Theta) / (96 (1 + e) g0) [1 + 4/5 g0 a (1 + e)]^2     kinetic
///              + (4/5) a^2 rho_s d g0 (1 + e) sqrt(Theta/pi)                         collisional
///   lambda_s = (4/3) a^2 rho_s d g0 (1 + e) sqrt(Theta/pi)
///   kappa_s  = 150 rho_s d sqrt(pi Theta) / (384 (1 + e) g0) [1 + 6/5 a g0 (1 + e)]^2
///              + 2 a^2 rho_s d g0 (1 + e) sqrt(Theta/pi)
///   gamma_s  = 12 (1 - e^2) g0 rho_s a^2 Theta^(3/2) / (d sqrt(pi))
/// Dilute limit: mu_s -> 2 mu* / (1 + e), kappa_s -> 2 kappa* / (1 + e). At e = 1 mu_s and
/// kappa_s equal lun's exactly (both are Enskog's first approximation).
struct Gidaspow {
  static constexpr std::string_view key = "gidaspow";
  static constexpr std::string_view summary =
      "KTGF closures of Gidaspow (1994): Enskog dense-gas transport with an e-dependent dilute "
      "term";
  static constexpr std::string_view equation =
      "P = rho a T [1 + 2 (1+e) a g0];  mu = 10 rho d sqrt(pi T) / (96 (1+e) g0) [1 + 4/5 g0 a "
      "(1+e)]^2 + (4/5) a^2 rho d g0 (1+e) sqrt(T/pi);  lambda = (4/3) a^2 rho d g0 (1+e) "
      "sqrt(T/pi);  kappa = 150 rho d sqrt(pi T) / (384 (1+e) g0) [1 + 6/5 a g0 (1+e)]^2 + 2 a^2 "
      "rho d g0 (1+e) sqrt(T/pi);  gamma = 12 (1-e^2) g0 rho a^2 T^1.5 / (d sqrt(pi))";
  static constexpr std::string_view reference =
      "Gidaspow, Multiphase Flow and Fluidization, Academic Press (1994), kinetic-theory "
      "chapter; van Wachem et al., AIChE J. 47 (2001) 1035; Fluent Theory Guide ('gidaspow')";
  static constexpr std::array<ParamSpec, 3> params = ktgf_material_params;
  template <class Get>
  static void prepare(KtgfParams& p, Get&& get) {
    prepare_ktgf_material(p, get);
  }
  GF_HOST_DEVICE static double pressure(double a, double theta, double g0, const KtgfParams& p) {
    return p.density * a * theta * (1 + 2 * (1 + p.restitution) * a * g0);
  }
  GF_HOST_DEVICE static double kinetic_viscosity(double a, double theta, double g0,
                                                 const KtgfParams& p) {
    const double e = p.restitution;
    const double f = 1 + 0.8 * g0 * a * (1 + e);
    return 10 * p.density * p.diameter * std::sqrt(ktgf_detail::kPi * theta) / (96 * (1 + e) * g0) *
           f * f;
  }
  GF_HOST_DEVICE static double shear_viscosity(double a, double theta, double g0,
                                               const KtgfParams& p) {
    return kinetic_viscosity(a, theta, g0, p) +
           ktgf_detail::collisional_shear_viscosity(a, theta, g0, p);
  }
  GF_HOST_DEVICE static double bulk_viscosity(double a, double theta, double g0,
                                              const KtgfParams& p) {
    return ktgf_detail::lun_bulk_viscosity(a, theta, g0, p);
  }
  GF_HOST_DEVICE static double conductivity(double a, double theta, double g0,
                                            const KtgfParams& p) {
    const double e = p.restitution;
    const double f = 1 + 1.2 * a * g0 * (1 + e);
    return 150 * p.density * p.diameter * std::sqrt(ktgf_detail::kPi * theta) /
               (384 * (1 + e) * g0) * f * f +
           2 * a * a * p.density * p.diameter * g0 * (1 + e) * std::sqrt(theta / ktgf_detail::kPi);
  }
  GF_HOST_DEVICE static double dissipation(double a, double theta, double g0, const KtgfParams& p) {
    return ktgf_detail::collisional_dissipation(a, theta, g0, p);
  }
};

using KtgfClosures = TypeList<Lun, Syamlal, Gidaspow>;

// ---------------------------------------------------------------------------------------------
// Evaluation through the registries (a switch, no virtual call)
// ---------------------------------------------------------------------------------------------

/// g0(a) of the radial distribution p.radial [1]; +infinity at and above its packing limit.
GF_HOST_DEVICE inline double radial_distribution(double a, const KtgfParams& p) {
  return dispatch_index(RadialDistributions{}, p.radial, [&]<class R>() { return R::g0(a, p); });
}

/// Every closure of the set p.model at volume fraction a [1] and granular temperature theta
/// [m^2/s^2], with one evaluation of g0.
struct KtgfProperties {
  double g0 = 0;                 ///< radial distribution at contact [1]
  double pressure = 0;           ///< P_s [Pa]
  double kinetic_viscosity = 0;  ///< kinetic part of mu_s [Pa s]
  double shear_viscosity = 0;    ///< mu_s, kinetic + collisional [Pa s]
  double bulk_viscosity = 0;     ///< lambda_s [Pa s]
  double conductivity = 0;       ///< kappa_s [kg/(m s)]: q = -kappa_s grad(Theta) [W/m^2]
  double dissipation = 0;        ///< gamma_s [W/m^3]
};

GF_HOST_DEVICE inline KtgfProperties ktgf_properties(double a, double theta, const KtgfParams& p) {
  KtgfProperties r;
  r.g0 = radial_distribution(a, p);
  const double g0 = r.g0;
  dispatch_index(KtgfClosures{}, p.model, [&]<class M>() {
    r.pressure = M::pressure(a, theta, g0, p);
    r.kinetic_viscosity = M::kinetic_viscosity(a, theta, g0, p);
    r.shear_viscosity = M::shear_viscosity(a, theta, g0, p);
    r.bulk_viscosity = M::bulk_viscosity(a, theta, g0, p);
    r.conductivity = M::conductivity(a, theta, g0, p);
    r.dissipation = M::dissipation(a, theta, g0, p);
  });
  return r;
}

/// One property of the closure set p.model at volume fraction a [1] and granular temperature
/// theta [m^2/s^2] (a switch over the set, one evaluation of g0).
enum class KtgfProperty { Pressure, ShearViscosity, BulkViscosity, Conductivity, Dissipation };
GF_HOST_DEVICE inline double ktgf_property(KtgfProperty what, double a, double theta,
                                           const KtgfParams& p) {
  const double g0 = radial_distribution(a, p);
  return dispatch_index(KtgfClosures{}, p.model, [&]<class M>() {
    switch (what) {
      case KtgfProperty::Pressure:
        return M::pressure(a, theta, g0, p);
      case KtgfProperty::ShearViscosity:
        return M::shear_viscosity(a, theta, g0, p);
      case KtgfProperty::BulkViscosity:
        return M::bulk_viscosity(a, theta, g0, p);
      case KtgfProperty::Conductivity:
        return M::conductivity(a, theta, g0, p);
      case KtgfProperty::Dissipation:
        return M::dissipation(a, theta, g0, p);
    }
    return 0.0;
  });
}
/// Solids pressure P_s [Pa]; shear viscosity mu_s, kinetic + collisional [Pa s]; bulk viscosity
/// lambda_s [Pa s]; granular conductivity kappa_s [kg/(m s)]; collisional dissipation gamma_s
/// [W/m^3].
GF_HOST_DEVICE inline double solids_pressure(double a, double theta, const KtgfParams& p) {
  return ktgf_property(KtgfProperty::Pressure, a, theta, p);
}
GF_HOST_DEVICE inline double solids_shear_viscosity(double a, double theta, const KtgfParams& p) {
  return ktgf_property(KtgfProperty::ShearViscosity, a, theta, p);
}
GF_HOST_DEVICE inline double solids_bulk_viscosity(double a, double theta, const KtgfParams& p) {
  return ktgf_property(KtgfProperty::BulkViscosity, a, theta, p);
}
GF_HOST_DEVICE inline double granular_conductivity(double a, double theta, const KtgfParams& p) {
  return ktgf_property(KtgfProperty::Conductivity, a, theta, p);
}
GF_HOST_DEVICE inline double collisional_dissipation(double a, double theta, const KtgfParams& p) {
  return ktgf_property(KtgfProperty::Dissipation, a, theta, p);
}

// ---------------------------------------------------------------------------------------------
// Dense regions: frictional closures and the regime switch
// ---------------------------------------------------------------------------------------------

/// Constants of a frictional model (prepare_frictional).
struct FrictionalParams {
  int model = 0;                  ///< index in FrictionalModels
  double sin_friction_angle = 0;  ///< sin(phi), Schaeffer [1]
  double fr = 0;                  ///< Fr, Johnson-Jackson [Pa]
  double exponent_n = 0;          ///< n, Johnson-Jackson [1]
  double exponent_p = 0;          ///< p, Johnson-Jackson [1]
  double min_fraction = 0;        ///< a_min: frictional pressure from here [1]
  double max_fraction = 0;        ///< a_max: frictional pressure diverges here [1]
  double max_viscosity = 0;       ///< cap of the frictional viscosity [Pa s]
  double frictional_limit = 0;    ///< a_fric: mu(I) above, KTGF below [1]
};

enum class FlowRegime {
  Kinetic,     ///< KTGF alone
  Frictional,  ///< a frictional closure applied (added to KTGF or replacing it)
};

/// The effective shear viscosity of a dense-region model and where it came from.
struct DenseViscosity {
  double viscosity = 0;             ///< effective shear viscosity the momentum balance uses [Pa s]
  double kinetic_viscosity = 0;     ///< KTGF mu_s(a, Theta) [Pa s] (always evaluated)
  double frictional_viscosity = 0;  ///< the frictional model's part [Pa s]; 0 in Kinetic regime
  FlowRegime regime = FlowRegime::Kinetic;
};

/// Johnson & Jackson (1987) frictional normal stress P_f = Fr (a - a_min)^n / (a_max - a)^p for
/// a > a_min (0 below, +infinity at and above a_max) [Pa]; seed eq 7.
GF_HOST_DEVICE inline double johnson_jackson_pressure(double a, const FrictionalParams& f) {
  if (!(a > f.min_fraction)) return 0.0;
  if (!(a < f.max_fraction)) return ktgf_detail::kInf;
  return f.fr * std::pow(a - f.min_fraction, f.exponent_n) /
         std::pow(f.max_fraction - a, f.exponent_p);
}

/// Schaeffer (1987) frictional viscosity mu_f = P_f sin(phi) / (2 sqrt(I_2D)) [Pa s] (seed eq 6),
/// with 2 sqrt(I_2D) = gamma_dot = sqrt(2 D':D') [1/s] (D' the deviator of the strain rate; the
/// rheologies' gamma_dot for tr D = 0; in simple shear u_x = gamma_dot y the shear stress is then
/// P_f sin(phi)). Capped at f.max_viscosity where gamma_dot -> 0 (MFIX caps at 1000 poise).
GF_HOST_DEVICE inline double schaeffer_viscosity(double frictional_pressure, double gamma_dot,
                                                 const FrictionalParams& f) {
  if (!(frictional_pressure > 0.0)) return 0.0;
  if (!(gamma_dot > 0.0)) return f.max_viscosity;
  const double mu = frictional_pressure * f.sin_friction_angle / gamma_dot;
  return mu < f.max_viscosity ? mu : f.max_viscosity;
}

/// Schaeffer's extension of KTGF (seed eq 3): mu = mu_kin + mu_col + mu_fric with Schaeffer's
/// viscosity of the Johnson-Jackson pressure, which is non-zero above a_min.
struct SchaefferJohnsonJackson {
  static constexpr std::string_view key = "schaeffer_johnson_jackson";
  static constexpr std::string_view summary =
      "dense KTGF: Schaeffer frictional viscosity of the Johnson-Jackson frictional pressure, "
      "added to the kinetic-theory viscosity";
  static constexpr std::string_view equation =
      "mu = mu_s(a, T) + mu_f,  mu_f = min(P_f sin(phi) / gamma_dot, mu_max),  P_f = Fr (a - "
      "a_min)^n / (a_max - a)^p for a > a_min (0 below),  gamma_dot = 2 sqrt(I_2D) = sqrt(2 "
      "D':D');  the caller adds P_f (johnson_jackson_pressure) to the solids pressure";
  static constexpr std::string_view reference =
      "Schaeffer, J. Differ. Equations 66 (1987) 19; Johnson & Jackson, J. Fluid Mech. 176 "
      "(1987) 67; sum of seed (Gomez Fino 2014) eqs 3, 6, 7";
  static constexpr std::array<ParamSpec, 7> params{{
      {"friction_angle", "deg", 28.5, 0.0, 90.0, true, ParamScope::PerMaterial,
       "phi, angle of internal friction (28.5 deg: a value often used for glass beads)"},
      {"fr", "Pa", 0.05, 0.0, 1e12, false, ParamScope::PerMaterial,
       "Fr, scale of the Johnson-Jackson frictional pressure"},
      {"exponent_n", "1", 2.0, 0.0, 100.0, false, ParamScope::PerMaterial,
       "n, exponent of (a - a_min)"},
      {"exponent_p", "1", 5.0, 0.0, 100.0, false, ParamScope::PerMaterial,
       "p, exponent of 1 / (a_max - a)"},
      {"min_fraction", "1", 0.5, 0.0, 1.0, false, ParamScope::PerMaterial,
       "a_min, volume fraction where the frictional pressure sets in"},
      {"max_fraction", "1", 0.64, 0.0, 1.0, true, ParamScope::PerMaterial,
       "a_max, volume fraction where the frictional pressure diverges; above a_min"},
      {"max_viscosity", "Pa s", 100.0, 0.0, 1e12, true, ParamScope::PerMaterial,
       "cap of the frictional viscosity where gamma_dot -> 0 (MFIX: 1000 poise = 100 Pa s)"},
  }};
  template <class Get>
  static void prepare(FrictionalParams& f, Get&& get) {
    f.sin_friction_angle = std::sin(get("friction_angle").value_or(28.5) * ktgf_detail::kPi / 180);
    f.fr = get("fr").value_or(0.05);
    f.exponent_n = get("exponent_n").value_or(2.0);
    f.exponent_p = get("exponent_p").value_or(5.0);
    f.min_fraction = get("min_fraction").value_or(0.5);
    f.max_fraction = get("max_fraction").value_or(0.64);
    f.max_viscosity = get("max_viscosity").value_or(100.0);
    REQUIRE(f.min_fraction < f.max_fraction,
            "frictional model 'schaeffer_johnson_jackson': min_fraction = {} must be below "
            "max_fraction = {}",
            f.min_fraction, f.max_fraction);
  }
  GF_HOST_DEVICE static DenseViscosity viscosity(double a, double theta, double gamma_dot,
                                                 double /*pressure*/, const KtgfParams& k,
                                                 const FrictionalParams& f,
                                                 const RheologyParams& /*dense*/) {
    DenseViscosity r;
    r.kinetic_viscosity = solids_shear_viscosity(a, theta, k);
    if (a > f.min_fraction) {
      r.frictional_viscosity = schaeffer_viscosity(johnson_jackson_pressure(a, f), gamma_dot, f);
      r.regime = FlowRegime::Frictional;
    }
    r.viscosity = r.kinetic_viscosity + r.frictional_viscosity;
    return r;
  }
};

/// The regime switch of the seed (Gomez Fino 2014, sec. 3.2, with eqs 8-11): above the frictional
/// packing limit a_fric the shear viscosity is the dense rheology's apparent viscosity
/// eta(gamma_dot, P) (mu(I) P / gamma_dot for 'mu_i', capped as MuI caps it), below it the KTGF
/// viscosity alone. The pressure is the caller's (the seed uses its eq 14, P0 ln((a_M - a_m) /
/// (a_M - a))). The KTGF viscosity is reported in both regimes: Fluent adds a frictional
/// viscosity to it (seed eq 3), so kinetic_viscosity + frictional_viscosity is that variant.
struct MuISwitch {
  static constexpr std::string_view key = "mu_i_switch";
  static constexpr std::string_view summary =
      "dense regions by the mu(I) rheology: its viscosity above a frictional packing limit, "
      "KTGF alone below";
  static constexpr std::string_view equation =
      "mu = eta_rheology(gamma_dot, P) = min(mu(I) P / gamma_dot, eta_max) for a > a_fric,  mu = "
      "mu_s(a, T) (KTGF) for a <= a_fric,  mu(I) = mu_s + (mu_2 - mu_s) / (I0 / I + 1),  I = "
      "gamma_dot d / sqrt(P / rho_s)";
  static constexpr std::string_view reference =
      "Gomez Fino, MSc thesis, Chalmers (2014), sec. 3.2 and eqs 8-11; Jop, Forterre & "
      "Pouliquen, Nature 441 (2006) 727";
  static constexpr std::array<ParamSpec, 1> params{{
      {"frictional_limit", "1", 0.55, 0.0, 1.0, true, ParamScope::PerMaterial,
       "a_fric, frictional packing limit: the rheology's viscosity above it (0.55 in the seed; "
       "0.4 was tried without improvement)"},
  }};
  template <class Get>
  static void prepare(FrictionalParams& f, Get&& get) {
    f.frictional_limit = get("frictional_limit").value_or(0.55);
    REQUIRE(f.frictional_limit < 1.0, "frictional model 'mu_i_switch': frictional_limit = {} >= 1",
            f.frictional_limit);
  }
  GF_HOST_DEVICE static DenseViscosity viscosity(double a, double theta, double gamma_dot,
                                                 double pressure, const KtgfParams& k,
                                                 const FrictionalParams& f,
                                                 const RheologyParams& dense) {
    DenseViscosity r;
    r.kinetic_viscosity = solids_shear_viscosity(a, theta, k);
    if (a > f.frictional_limit) {
      r.frictional_viscosity = apparent_viscosity(gamma_dot, pressure, dense);
      r.viscosity = r.frictional_viscosity;
      r.regime = FlowRegime::Frictional;
    } else {
      r.viscosity = r.kinetic_viscosity;
    }
    return r;
  }
};

using FrictionalModels = TypeList<SchaefferJohnsonJackson, MuISwitch>;

// ---------------------------------------------------------------------------------------------
// Particle pressure below the dense regime: the solids elastic modulus
// ---------------------------------------------------------------------------------------------

/// Constants of a particle-pressure model (prepare_particle_pressure).
struct ParticlePressureParams {
  int model = 0;               ///< index in ParticlePressureModels
  double log10_modulus = 0.0;  ///< b of G = 10^(b - c eps) [Pa]: log10 of G at eps = 0
  double exponent = 0.0;       ///< c of G = 10^(b - c eps) [1]
};

/// Gidaspow & Ettehadieh's (1983) solids elastic modulus: a particle pressure whose slope is
/// G(eps) = dP_e/da = 10^(b - c eps) Pa, eps = 1 - a the fluid fraction. Where grains barely
/// fluctuate (liquid fluidisation: Theta ~ 0) the kinetic pressure vanishes and nothing else
/// resists a disturbance of the volume fraction below the frictional limit; the modulus gives
/// voidage waves a restoring force (Gidaspow 1994, ch. 2, "model B"; Bouillard, Lyczkowski &
/// Gidaspow 1989 use it in the equivalent form exp(-20.17 (eps - 0.62))). Its size: 4.1 Pa at
/// a = 0.45, 84 Pa at a = 0.6, 5e-4 Pa at a = 0 (c = 8.76, b = 5.43).
struct GidaspowEttehadieh {
  static constexpr std::string_view key = "gidaspow_ettehadieh";
  static constexpr std::string_view summary =
      "particle pressure of the solids elastic modulus G(eps) = 10^(b - c eps) Pa, added to the "
      "solids pressure (resists voidage disturbances where Theta ~ 0: liquid fluidisation)";
  static constexpr std::string_view equation =
      "dP_e/da = G(eps) = 10^(b - c eps) Pa, eps = 1 - a;  P_e(a) = int_0^a G da' = 10^(b - c) "
      "(10^(c a) - 1) / (c ln 10)";
  static constexpr std::string_view reference =
      "Gidaspow & Ettehadieh, Ind. Eng. Chem. Fundam. 22 (1983) 193; Gidaspow, Multiphase Flow "
      "and Fluidization (Academic Press, 1994), ch. 2";
  static constexpr std::array<ParamSpec, 2> params{{
      {"exponent", "1", 8.76, 0.0, 1000.0, true, ParamScope::PerMaterial,
       "c of G = 10^(b - c eps) Pa (8.76: Gidaspow & Ettehadieh's fit)"},
      {"log10_modulus", "1", 5.43, -100.0, 100.0, false, ParamScope::PerMaterial,
       "b of G = 10^(b - c eps) Pa: log10 of G [Pa] at eps = 0 (5.43: Gidaspow & Ettehadieh)"},
  }};
  template <class Get>
  static void prepare(ParticlePressureParams& p, Get&& get) {
    p.exponent = get("exponent").value_or(8.76);
    p.log10_modulus = get("log10_modulus").value_or(5.43);
  }
  /// P_e(a) [Pa].
  GF_HOST_DEVICE static double pressure(double a, const ParticlePressureParams& p) {
    const double c = p.exponent * ktgf_detail::kLn10;
    // 10^(b - c) (10^(c a) - 1) / (c ln 10) = 10^(b - c) expm1(c ln10 a) / (c ln 10)
    return std::exp((p.log10_modulus - p.exponent) * ktgf_detail::kLn10) * std::expm1(c * a) / c;
  }
};

using ParticlePressureModels = TypeList<GidaspowEttehadieh>;

/// The particle pressure P_e [Pa] of model p.model at volume fraction a [1] (a >= 0).
GF_HOST_DEVICE inline double particle_pressure(double a, const ParticlePressureParams& p) {
  return dispatch_index(ParticlePressureModels{}, p.model,
                        [&]<class M>() { return M::pressure(a, p); });
}

/// The effective shear viscosity [Pa s] of the frictional model f.model at volume fraction a [1],
/// granular temperature theta [m^2/s^2], shear rate gamma_dot = sqrt(2 D':D') [1/s] and pressure
/// [Pa] (read by mu_i_switch only), with the KTGF set k and the dense rheology `dense` (read by
/// mu_i_switch only; prepare_rheology("mu_i", ...)), and which regime applied.
GF_HOST_DEVICE inline DenseViscosity effective_shear_viscosity(double a, double theta,
                                                               double gamma_dot, double pressure,
                                                               const KtgfParams& k,
                                                               const FrictionalParams& f,
                                                               const RheologyParams& dense) {
  return dispatch_index(FrictionalModels{}, f.model, [&]<class M>() {
    return M::viscosity(a, theta, gamma_dot, pressure, k, f, dense);
  });
}

// ---------------------------------------------------------------------------------------------
// Registry functions (ktgf.cpp)
// ---------------------------------------------------------------------------------------------

/// Description of a registered KTGF model, for the command line, the docs and input validation.
struct KtgfInfo {
  std::string_view key, summary, equation, reference;
  std::span<const ParamSpec> params;
};

/// Every closure set of KtgfClosures, in list order; nullptr for an unknown key.
std::vector<KtgfInfo> ktgf_closure_infos();
const KtgfInfo* find_ktgf_closure(std::string_view key);
/// Every radial distribution of RadialDistributions; nullptr for an unknown key.
std::vector<KtgfInfo> radial_distribution_infos();
const KtgfInfo* find_radial_distribution(std::string_view key);
/// Every model of FrictionalModels; nullptr for an unknown key.
std::vector<KtgfInfo> frictional_model_infos();
const KtgfInfo* find_frictional_model(std::string_view key);

/// Every model of ParticlePressureModels; nullptr for an unknown key.
std::vector<KtgfInfo> particle_pressure_model_infos();
const KtgfInfo* find_particle_pressure_model(std::string_view key);

/// Checks the parameters of closure set `key` with radial distribution `radial` against their
/// joint schema (unknown set or g0, unknown parameter name, value out of range, missing required
/// value: gf::Error naming them) and derives the constants; defaults fill what is not given.
KtgfParams prepare_ktgf(std::string_view key, const std::map<std::string, double>& params,
                        std::string_view radial = CarnahanStarling::key);

/// The same for frictional model `key` (a_min >= a_max is an error too).
FrictionalParams prepare_frictional(std::string_view key,
                                    const std::map<std::string, double>& params = {});
/// The same for particle-pressure model `key`.
ParticlePressureParams prepare_particle_pressure(std::string_view key,
                                                 const std::map<std::string, double>& params = {});

// ---------------------------------------------------------------------------------------------
// Homogeneous states
// ---------------------------------------------------------------------------------------------

/// Steady homogeneous simple shear u_x = gamma_dot y of the set p at volume fraction a: viscous
/// heating balances dissipation, mu_s(a, T) gamma_dot^2 = gamma_s(a, T). Every set has mu_s ~
/// sqrt(T) and gamma_s ~ T^(3/2) at fixed a, so T = [mu_s(a, 1) / gamma_s(a, 1)] gamma_dot^2 in
/// closed form. Stresses tension-positive: shear_stress = sigma_xy = mu_s gamma_dot (the sign of
/// gamma_dot); pressure P_s > 0.
struct KtgfShearState {
  double temperature = 0;   ///< Theta [m^2/s^2]
  double pressure = 0;      ///< P_s [Pa]
  double viscosity = 0;     ///< mu_s [Pa s]
  double shear_stress = 0;  ///< mu_s gamma_dot [Pa]
  double friction = 0;      ///< |shear_stress| / P_s [1], independent of gamma_dot
};

/// Requires 0 < a < the packing limit, 0 <= e < 1 (e = 1 has no steady state), finite shear_rate
/// [1/s].
KtgfShearState ktgf_simple_shear(double a, double shear_rate, const KtgfParams& p);

/// Homogeneous cooling (Haff 1983): (3/2) a rho_s dTheta/dt = -gamma_s(a, Theta) = -c Theta^(3/2)
/// gives Theta(t) = Theta0 / (1 + t / tau)^2 with tau = 3 a rho_s / (c sqrt(Theta0)) [s]
/// (= d sqrt(pi) / (4 (1 - e^2) g0 a sqrt(Theta0)) for these sets). Requires 0 < a < the packing
/// limit, 0 <= e < 1, Theta0 > 0 [m^2/s^2].
double haff_time(double a, double theta0, const KtgfParams& p);
/// Theta(t) [m^2/s^2] of the homogeneous cooling from Theta0 at t = 0, t >= 0 [s].
double haff_temperature(double a, double theta0, double t, const KtgfParams& p);

}  // namespace gf::continuum
