// SPDX-License-Identifier: GPL-3.0-or-later
// The flow-around-a-cylinder benchmark of Schaefer & Turek (1996): geometry, data, references.
//
// Channel [0, 2.2] x [0, 0.41] m, cylinder centre (0.2, 0.2) m, diameter D = 0.1 m, rho = 1,
// nu = 1e-3; parabolic inflow u = 4 U_m y (H - y) / H^2; C_D = 2 F_x / (rho Ubar^2 D),
// C_L = 2 F_y / (rho Ubar^2 D) with Ubar = 2 U_m / 3; dp = p(0.15, 0.2) - p(0.25, 0.2).
// References: Schaefer & Turek, Notes Num. Fluid Mech. 52 (1996) 547; refined values of
// 2D-1 / 2D-3 from John, Int. J. Numer. Meth. Fluids 44 (2004) 777 and the FEATFLOW pages.
#pragma once

#include <functional>

#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem::schaefer_turek {

inline constexpr double kLength = 2.2, kHeight = 0.41, kDiameter = 0.1;
inline constexpr double kCx = 0.2, kCy = 0.2;
// 2D-1 (steady, U_m = 0.3, Re = 20)
inline constexpr double kCd1 = 5.57953523384, kCl1 = 0.010618948146, kDp1 = 0.11752016697;
// 2D-3 (U_m(t) = 1.5 sin(pi t / 8), t in [0, 8])
inline constexpr double kCdMax3 = 2.950921575, kTCdMax3 = 3.93625;
inline constexpr double kClMax3 = 0.47795, kTClMax3 = 5.693125, kDpEnd3 = -0.1116;

/// Mesh sizes: h_max away from the cylinder, h_body on it [m]; grading dh/ds [-].
struct MeshLevel {
  double h_max = 0.04;
  double h_body = 0.01;
  double grading = 0.25;
  double h_wake = 0.0;  ///< if > 0: size bound in the wake box [0.15, 1.2] x [0.05, 0.36]
};

/// The channel problem with inflow amplitude u_max [m/s] and time function f(t).
FlowProblem make_problem(const MeshLevel& level, double u_max,
                         std::function<double(double)> f = {});

/// C_D, C_L from a force [N/m] for mean velocity ubar [m/s].
struct Coefficients {
  double cd = 0, cl = 0, dp = 0;
};
Coefficients coefficients(const NavierStokes& ns, const BodyForce& f, double ubar);

}  // namespace gf::fem::schaefer_turek
