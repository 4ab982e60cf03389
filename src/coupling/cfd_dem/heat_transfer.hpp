// SPDX-License-Identifier: GPL-3.0-or-later
// Convective heat transfer between grains and the fluid of unresolved CFD-DEM
// (coupling.heat_transfer): one small value type per Nusselt correlation, with its key,
// equation, source and validity, listed once in HeatTransferLaws.
//
// A grain of volume-equivalent diameter d, surface A and temperature T_p in fluid at T_f receives
// Q = h A (T_f - T_p) W, with h = Nu k_f / d. The correlations differ in Nu(Re, Pr, eps):
//   Re = rho_f |u_f - v_p| d / mu_f  (single-particle slip; gunn uses eps Re, the superficial
//   slip, as in its source), Pr = c_p mu_f / k_f.
// A non-spherical grain uses its volume-equivalent d in Re and Nu and its true surface A (pi d^2
// / psi, psi its sphericity): the correlations are for spheres, and this keeps h of the
// equivalent sphere while the area that exchanges heat is the grain's own.
#pragma once

#include <cmath>
#include <span>
#include <string_view>
#include <vector>

#include "core/host_device.hpp"
#include "core/registry.hpp"

namespace gf::cfd_dem {

struct RanzMarshall {
  static constexpr std::string_view key = "ranz_marshall";
  static constexpr std::string_view summary =
      "single sphere: Nu = 2 + 0.6 Re^1/2 Pr^1/3 (no voidage dependence)";
  static constexpr std::string_view equation =
      "Nu = 2 + 0.6 Re^(1/2) Pr^(1/3),  Re = rho_f |u_f - v_p| d / mu_f";
  static constexpr std::string_view reference =
      "W. E. Ranz, W. R. Marshall, Evaporation from drops, Chem. Eng. Prog. 48 (1952) 141-146 "
      "and 173-180";
  static constexpr std::string_view validity =
      "an isolated sphere, 0 <= Re < ~200 (fitted on drops); dilute suspensions";
  GF_HOST_DEVICE static double nusselt(double re, double pr, double /*eps*/) {
    return 2.0 + 0.6 * std::sqrt(re) * std::cbrt(pr);
  }
};

struct Gunn {
  static constexpr std::string_view key = "gunn";
  static constexpr std::string_view summary =
      "fixed and fluidised beds, eps 0.35-1: Nu(eps, eps Re, Pr), Nu -> 2 for a single sphere at "
      "rest";
  static constexpr std::string_view equation =
      "Nu = (7 - 10 eps + 5 eps^2)(1 + 0.7 Re_e^0.2 Pr^(1/3)) + (1.33 - 2.4 eps + 1.2 eps^2) "
      "Re_e^0.7 Pr^(1/3),  Re_e = eps rho_f |u_f - v_p| d / mu_f";
  static constexpr std::string_view reference =
      "D. J. Gunn, Transfer of heat or mass to particles in fixed and fluidised beds, Int. J. "
      "Heat Mass Transfer 21 (1978) 467-476";
  static constexpr std::string_view validity = "0.35 <= eps <= 1, Re_e up to 1e5";
  GF_HOST_DEVICE static double nusselt(double re, double pr, double eps) {
    const double re_e = eps * re, pr3 = std::cbrt(pr);
    return (7.0 - 10.0 * eps + 5.0 * eps * eps) * (1.0 + 0.7 * std::pow(re_e, 0.2) * pr3) +
           (1.33 - 2.4 * eps + 1.2 * eps * eps) * std::pow(re_e, 0.7) * pr3;
  }
};

using HeatTransferLaws = TypeList<RanzMarshall, Gunn>;

struct HeatTransferInfo {
  std::string_view key, summary, equation, reference, validity;
};
/// Every law of HeatTransferLaws, in list order.
std::vector<HeatTransferInfo> heat_transfer_infos();
/// Index in HeatTransferLaws, or -1.
int heat_transfer_index(std::string_view key);
const HeatTransferInfo* find_heat_transfer(std::string_view key);

/// Nu of the law at index `law` (re: single-particle Reynolds number; pr: Prandtl number; eps:
/// fluid fraction at the grain).
inline double nusselt(int law, double re, double pr, double eps) {
  return dispatch_index(HeatTransferLaws{}, law,
                        [&]<class L>() { return L::nusselt(re, pr, eps); });
}

/// The grain's conductance to the fluid h A = (Nu k_f / d) A [W/K] (d: volume-equivalent
/// diameter [m], k_f [W/(m K)], A: the grain's surface [m^2], pi d^2 for a sphere).
GF_HOST_DEVICE inline double fluid_conductance(double nu, double k_f, double d, double area) {
  return nu * k_f / d * area;
}

}  // namespace gf::cfd_dem
