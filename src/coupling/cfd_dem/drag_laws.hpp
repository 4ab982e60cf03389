// SPDX-License-Identifier: GPL-3.0-or-later
// Drag laws of unresolved CFD-DEM: one small value type per law with its key, equation, source,
// validity and parameter schema, and a pure host/device function from plain data to the force.
//
// Every law returns the drag on one particle as F = beta (u_f - v_p), with beta >= 0 (N s/m) the
// implicit coefficient the semi-implicit momentum exchange needs. The pressure-gradient
// (buoyancy) force -V_p grad p is separate (pressure_gradient_force): the laws here are the
// "drag" of the formulation where the particle sees -V_p grad p + F_drag (model A/B discussion:
// Zhou et al., J. Fluid Mech. 661 (2010) 482). Each law is written as beta = 3 pi mu d f, f the
// drag normalised by Stokes, so that beta stays finite at zero slip (implicit coupling needs it).
//
// Reynolds numbers (say which, they differ between the sources):
//   Re   = rho_f |u_f - v_p| d / mu_f            single particle (schiller_naumann)
//   Re_e = eps rho_f |u_f - v_p| d / mu_f        superficial slip (every law in a suspension)
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "core/host_device.hpp"
#include "core/params.hpp"
#include "core/vec3.hpp"
#include "coupling/cfd_dem/shape_factors.hpp"

namespace gf::cfd_dem {

/// What every drag law reads: fluid properties, local fluid fraction, particle size and shape,
/// and the slip velocity. Plain data, filled per particle by the coupling loop.
struct DragInput {
  double rho_f = 0;     ///< fluid density, kg/m^3
  double mu_f = 0;      ///< dynamic viscosity, Pa s
  double eps = 1;       ///< fluid (void) fraction at the particle, (0, 1]
  double d_v = 0;       ///< volume-equivalent diameter, m
  Vec3 slip{};          ///< interstitial slip u_f - v_p, m/s
  double phi = 1;       ///< surface sphericity (1: sphere); holzer_sommerfeld only
  double phi_perp = 1;  ///< crosswise sphericity for this slip (1: sphere); holzer_sommerfeld
};

/// Result of a drag law.
struct DragOutput {
  Vec3 force{};     ///< drag on the particle, N (= beta * slip)
  double beta = 0;  ///< implicit coefficient, N s/m
  double re = 0;    ///< the Reynolds number the law used (see the law's equation)
};

/// Constants a law derives once from its parameters (per material), read in the particle loop.
struct DragParams {
  int law = -1;                  ///< index in DragLaws
  double switch_fraction = 0.8;  ///< gidaspow: fluid fraction below which Ergun applies
};

/// -V_p grad p, N: the pressure-gradient force (buoyancy in a hydrostatic fluid, where
/// grad p = rho_f g and this is -rho_f V_p g). volume in m^3, grad_p in Pa/m.
GF_HOST_DEVICE inline Vec3 pressure_gradient_force(double volume, const Vec3& grad_p) {
  return -volume * grad_p;
}

namespace detail {

/// C_D Re / 24 of Schiller & Naumann (1933): 1 + 0.15 Re^0.687 below Re = 1000, C_D = 0.44
/// above (Newton regime). Finite at Re = 0 (Stokes).
GF_HOST_DEVICE inline double schiller_naumann_f(double re) {
  return re < 1000.0 ? 1.0 + 0.15 * std::pow(re, 0.687) : 0.44 * re / 24.0;
}

/// Di Felice (1994): the exponent chi of the voidage function eps^(-chi):
///   chi = 3.7 - 0.65 exp(-(1.5 - log10 Re)^2 / 2).
/// log10, not the "ln": the paper's correlation is in log10 Re, as every independent
/// implementation found with the code search writes it (PhasicFlowPlus DiFeliceGrain.hpp, an
/// OpenFOAM-based DiFeliceDragForce, two Fluent UDFs); the minimum chi = 3.05 then lies at
/// Re = 10^1.5 ~ 30, between the viscous and inertial limits (chi -> 3.7 on both sides), where
/// ln would put it at e^1.5 = 4.5. (The paper itself was not accessible here.)
/// At Re = 0 the limit is chi = 3.7.
GF_HOST_DEVICE inline double di_felice_exponent(double re_e) {
  if (!(re_e > 1e-300)) return 3.7;
  const double t = 1.5 - std::log10(re_e);
  return 3.7 - 0.65 * std::exp(-0.5 * t * t);
}

GF_HOST_DEVICE inline DragOutput finish(double beta, double re, const Vec3& slip) {
  DragOutput o;
  o.beta = beta;
  o.re = re;
  o.force = beta * slip;
  return o;
}

/// Wen & Yu (1966) in Gidaspow's (1994) form, per particle (see WenYu).
GF_HOST_DEVICE inline DragOutput wen_yu(const DragInput& in) {
  const double u = norm(in.slip);
  const double re_e = in.eps * in.rho_f * u * in.d_v / in.mu_f;
  const double beta =
      3.0 * kPi * in.mu_f * in.d_v * schiller_naumann_f(re_e) * std::pow(in.eps, -2.65);
  return finish(beta, re_e, in.slip);
}

/// C_D Re_e of Hoelzer & Sommerfeld (2008) (finite at Re = 0); log is log10 there too. phi
/// slightly above 1 (round-off for a sphere) must not make (-log10 phi)^0.2 a NaN.
GF_HOST_DEVICE inline double holzer_sommerfeld_cd_re(double re, double phi, double phi_perp) {
  const double lg = phi < 1.0 ? -std::log10(phi) : 0.0;
  const double c_newton = 0.42 * std::pow(10.0, 0.4 * std::pow(lg, 0.2)) / phi_perp;
  return 8.0 / std::sqrt(phi_perp) + 16.0 / std::sqrt(phi) +
         3.0 * std::sqrt(re) / std::pow(phi, 0.75) + c_newton * re;
}

}  // namespace detail

/// Schiller & Naumann (1933): an isolated sphere in an unbounded fluid.
struct SchillerNaumann {
  static constexpr std::string_view key = "schiller_naumann";
  static constexpr std::string_view summary =
      "isolated sphere (standard drag curve fit); ignores the fluid fraction";
  static constexpr std::string_view equation =
      "F = C_D rho_f/2 (pi d^2/4) |u| u,  C_D = 24/Re (1 + 0.15 Re^0.687) (Re < 1000), 0.44 "
      "(Re >= 1000),  Re = rho_f |u| d / mu_f,  u = u_f - v_p";
  static constexpr std::string_view reference =
      "Schiller & Naumann, Z. Ver. Dtsch. Ing. 77 (1933) 318; Clift, Grace & Weber, Bubbles, "
      "Drops and Particles (1978) Table 5.2";
  static constexpr std::string_view validity =
      "single sphere: within a few per cent of the standard drag curve for Re < 800 (Clift et "
      "al.), C_D = 0.44 from 1000 to the drag crisis (Re ~ 2e5); no crowding correction";
  static constexpr std::array<ParamSpec, 0> params{};
  template <class Get>
  static void prepare(DragParams&, Get&&) {}

  GF_HOST_DEVICE static DragOutput eval(const DragInput& in, const DragParams&) {
    const double re = in.rho_f * norm(in.slip) * in.d_v / in.mu_f;
    return detail::finish(3.0 * kPi * in.mu_f * in.d_v * detail::schiller_naumann_f(re), re,
                          in.slip);
  }
};

/// Di Felice (1994): single-particle drag on the superficial slip times the voidage function.
struct DiFelice {
  static constexpr std::string_view key = "di_felice";
  static constexpr std::string_view summary =
      "sphere in a suspension or fixed bed: Dallavalle single-particle drag times eps^(2 - chi)";
  static constexpr std::string_view equation =
      "F = C_D0 rho_f/2 (pi d^2/4) |u| u eps^(2 - chi),  C_D0 = (0.63 + 4.8/sqrt(Re_e))^2,  "
      "chi = 3.7 - 0.65 exp(-(1.5 - log10 Re_e)^2/2),  Re_e = eps rho_f |u| d / mu_f";
  static constexpr std::string_view reference =
      "Di Felice, Int. J. Multiphase Flow 20 (1994) 153 (log10 in chi; see docs/models/drag.md); "
      "C_D0: Dallavalle, Micromeritics (1948)";
  static constexpr std::string_view validity =
      "spheres, 1e-2 < Re_e < 1e4, 0.4 < eps <= 1 (fluidized and fixed beds of the paper's "
      "data); at Re_e -> 0 C_D0 gives 0.96 of Stokes drag";
  static constexpr std::array<ParamSpec, 0> params{};
  template <class Get>
  static void prepare(DragParams&, Get&&) {}

  GF_HOST_DEVICE static DragOutput eval(const DragInput& in, const DragParams&) {
    const double re_e = in.eps * in.rho_f * norm(in.slip) * in.d_v / in.mu_f;
    // C_D0 Re_e = (0.63 sqrt(Re_e) + 4.8)^2; rho_f |u| d = Re_e mu_f / eps, so
    // beta = C_D0 rho_f pi d^2 |u| / 8 eps^(2-chi) = pi/8 mu_f d (C_D0 Re_e) eps^(1-chi).
    const double s = 0.63 * std::sqrt(re_e) + 4.8;
    const double chi = detail::di_felice_exponent(re_e);
    const double beta = 0.125 * kPi * in.mu_f * in.d_v * s * s * std::pow(in.eps, 1.0 - chi);
    return detail::finish(beta, re_e, in.slip);
  }
};

/// Wen & Yu (1966), as used by Gidaspow (1994) for dilute regions.
struct WenYu {
  static constexpr std::string_view key = "wen_yu";
  static constexpr std::string_view summary =
      "Schiller-Naumann on the superficial Reynolds number times eps^(-2.65) (dilute suspensions)";
  static constexpr std::string_view equation =
      "F = V_p K / (1 - eps) u = C_D rho_f/2 (pi d^2/4) |u| u eps^(-1.65),  "
      "K = 3/4 C_D eps (1 - eps) rho_f |u| / d eps^(-2.65),  C_D = 24/Re_e (1 + 0.15 Re_e^0.687) "
      "(Re_e < 1000), 0.44 above,  Re_e = eps rho_f |u| d / mu_f";
  static constexpr std::string_view reference =
      "Wen & Yu, Chem. Eng. Prog. Symp. Ser. 62 (1966) 100; Gidaspow, Multiphase Flow and "
      "Fluidization (1994) ch. 5; per-particle form: Zhu et al., Chem. Eng. Sci. 62 (2007) 3378";
  static constexpr std::string_view validity =
      "spheres, dilute (eps > 0.8 as used by Gidaspow); over-predicts drag in dense beds";
  static constexpr std::array<ParamSpec, 0> params{};
  template <class Get>
  static void prepare(DragParams&, Get&&) {}

  GF_HOST_DEVICE static DragOutput eval(const DragInput& in, const DragParams&) {
    return detail::wen_yu(in);
  }
};

/// Gidaspow (1994): Ergun below the switch fraction, Wen-Yu above. Discontinuous at the switch:
/// at eps = 0.8, Ergun / Wen-Yu = 1.153 as Re_e -> 0, 1.06 at Re_e = 10, 2.97 at Re_e = 500
/// (the Ergun inertial term); see docs/models/drag.md.
struct Gidaspow {
  static constexpr std::string_view key = "gidaspow";
  static constexpr std::string_view summary =
      "Ergun (dense, eps < switch_fraction) / Wen-Yu (dilute) switch";
  static constexpr std::string_view equation =
      "eps < eps_s: F = V_p [150 (1 - eps) mu_f / (eps d^2) + 1.75 rho_f |u| / d] u  (Ergun: "
      "K = 150 (1-eps)^2 mu_f/(eps d^2) + 1.75 (1-eps) rho_f |u|/d, F = V_p K/(1-eps) u);  "
      "eps >= eps_s: wen_yu";
  static constexpr std::string_view reference =
      "Gidaspow, Multiphase Flow and Fluidization (1994) ch. 5; Ergun, Chem. Eng. Prog. "
      "48 (1952) 89";
  static constexpr std::string_view validity =
      "spheres, fixed to bubbling beds; the switch is a jump in the force (no blending)";
  static constexpr std::array<ParamSpec, 1> params{
      ParamSpec{"switch_fraction", "1", 0.8, 0.0, 1.0, true, ParamScope::PerMaterial,
                "fluid fraction below which Ergun replaces Wen-Yu"}};
  template <class Get>
  static void prepare(DragParams& p, Get&& get) {
    p.switch_fraction = get("switch_fraction").value_or(0.8);
  }

  GF_HOST_DEVICE static DragOutput eval(const DragInput& in, const DragParams& p) {
    if (in.eps >= p.switch_fraction) return detail::wen_yu(in);
    const double u = norm(in.slip);
    const double re_e = in.eps * in.rho_f * u * in.d_v / in.mu_f;
    // V_p / d^2 * d^3-terms: V_p = pi d^3 / 6.
    const double beta = kPi * in.d_v / 6.0 *
                        (150.0 * (1.0 - in.eps) * in.mu_f / in.eps + 1.75 * in.rho_f * u * in.d_v);
    return detail::finish(beta, re_e, in.slip);
  }
};

/// Beetstra, van der Hoef & Kuipers (2007): lattice-Boltzmann fit for monodisperse random
/// arrays of spheres.
struct Beetstra {
  static constexpr std::string_view key = "beetstra";
  static constexpr std::string_view summary =
      "lattice-Boltzmann fit for random arrays of spheres, 0 <= 1 - eps <= 0.6, Re_e <= 1000";
  static constexpr std::string_view equation =
      "F = 3 pi mu_f d eps A(phi, Re_e) u,  phi = 1 - eps,  A = 10 phi/eps^2 + eps^2 (1 + 1.5 "
      "sqrt(phi)) + 0.413 Re_e / (24 eps^2) [1/eps + 3 eps phi + 8.4 Re_e^-0.343] / [1 + "
      "10^(3 phi) Re_e^(-(1 + 4 phi)/2)],  Re_e = eps rho_f |u| d / mu_f";
  static constexpr std::string_view reference =
      "Beetstra, van der Hoef & Kuipers, AIChE J. 53 (2007) 489 (monodisperse fit); "
      "normalisation F/(3 pi mu d U_s), U_s = eps |u|: van der Hoef et al., J. Fluid Mech. 528 "
      "(2005) 233";
  static constexpr std::string_view validity =
      "spheres, 0.4 <= eps <= 1, Re_e <= 1000 (the simulated range)";
  static constexpr std::array<ParamSpec, 0> params{};
  template <class Get>
  static void prepare(DragParams&, Get&&) {}

  GF_HOST_DEVICE static DragOutput eval(const DragInput& in, const DragParams&) {
    const double e = in.eps, s = 1.0 - e;
    const double re_e = e * in.rho_f * norm(in.slip) * in.d_v / in.mu_f;
    double a = 10.0 * s / (e * e) + e * e * (1.0 + 1.5 * std::sqrt(s));
    if (re_e > 0.0) {  // the inertial term vanishes as Re_e^0.657 at Re_e -> 0
      a += 0.413 * re_e / (24.0 * e * e) * (1.0 / e + 3.0 * e * s + 8.4 * std::pow(re_e, -0.343)) /
           (1.0 + std::pow(10.0, 3.0 * s) * std::pow(re_e, -0.5 * (1.0 + 4.0 * s)));
    }
    return detail::finish(3.0 * kPi * in.mu_f * in.d_v * e * a, re_e, in.slip);
  }
};

/// Hoelzer & Sommerfeld (2008) for non-spherical particles, with Di Felice's voidage function.
struct HolzerSommerfeld {
  static constexpr std::string_view key = "holzer_sommerfeld";
  static constexpr std::string_view summary =
      "non-spherical particles (sphericity phi, crosswise sphericity phi_perp) with Di Felice's "
      "voidage correction";
  static constexpr std::string_view equation =
      "F = C_D rho_f/2 (pi d_v^2/4) |u| u eps^(2 - chi),  C_D = 8/(Re_e sqrt(phi_perp)) + "
      "16/(Re_e sqrt(phi)) + 3/(sqrt(Re_e) phi^(3/4)) + 0.42 10^(0.4 (-log10 phi)^0.2) / "
      "phi_perp,  chi as di_felice,  Re_e = eps rho_f |u| d_v / mu_f";
  static constexpr std::string_view reference =
      "Hoelzer & Sommerfeld, Powder Technol. 184 (2008) 361; voidage: Di Felice, Int. J. "
      "Multiphase Flow 20 (1994) 153";
  static constexpr std::string_view validity =
      "isolated particles of many shapes (fit to published data up to Re ~ 1e5); "
      "for spheres C_D = 24/Re + 3/sqrt(Re) + 0.42 (within 14 % of schiller_naumann for Re <= "
      "300: -13.9 % at Re = 47; +22 % at Re = 1000); the voidage correction is Di Felice's sphere "
      "fit";
  static constexpr std::array<ParamSpec, 0> params{};
  template <class Get>
  static void prepare(DragParams&, Get&&) {}

  GF_HOST_DEVICE static DragOutput eval(const DragInput& in, const DragParams&) {
    const double re_e = in.eps * in.rho_f * norm(in.slip) * in.d_v / in.mu_f;
    const double cd_re = detail::holzer_sommerfeld_cd_re(re_e, in.phi, in.phi_perp);
    const double chi = detail::di_felice_exponent(re_e);
    // As for di_felice: beta = pi/8 mu_f d_v (C_D Re_e) eps^(1 - chi).
    const double beta = 0.125 * kPi * in.mu_f * in.d_v * cd_re * std::pow(in.eps, 1.0 - chi);
    return detail::finish(beta, re_e, in.slip);
  }
};

/// Drag input for a spherocylinder (radius r, cylinder length l, unit axis): fills d_v, phi and
/// phi_perp from the incidence angle between the axis and the slip. At zero slip the direction is
/// undefined; phi_perp = phi is then used, the orientation average (Cauchy: the mean projected
/// area of a convex body is S/4). A sphere is l = 0 (phi = phi_perp = 1).
GF_HOST_DEVICE inline DragInput spherocylinder_drag_input(double rho_f, double mu_f, double eps,
                                                          double r, double l, const Vec3& axis,
                                                          const Vec3& slip) {
  DragInput in;
  in.rho_f = rho_f;
  in.mu_f = mu_f;
  in.eps = eps;
  in.slip = slip;
  in.d_v = volume_equivalent_diameter(spherocylinder_volume(r, l));
  in.phi = spherocylinder_sphericity(r, l);
  in.phi_perp = norm2(slip) > 0.0
                    ? spherocylinder_crosswise_sphericity(r, l, sin_incidence(axis, slip))
                    : in.phi;
  return in;
}

}  // namespace gf::cfd_dem
