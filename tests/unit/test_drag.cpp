// SPDX-License-Identifier: GPL-3.0-or-later
// Drag laws of CFD-DEM (src/coupling/cfd_dem/drag_laws.hpp): each law against its published
// formula written out here independently (as C_D and F = C_D rho/2 A U^2, or the drag per unit
// volume K, where the code uses beta = 3 pi mu d f), limits, the registry and the Hoelzer &
// Sommerfeld law for spherocylinders.
//
// Tolerances: where the reference is the same formula in another algebraic form, 1e-12
// relative (a few ulps of pow/exp/log through ~20 operations; any wrong constant or exponent
// shows up at 1e-3 or more). The literal values were computed with Python's math module.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using namespace gf::cfd_dem;

namespace {

constexpr double kPiD = std::numbers::pi;
// Water-like fluid and a 1 mm sphere: Re = rho U d / mu = 1000 U (U in m/s).
constexpr double kRho = 1000.0, kMu = 1e-3, kD = 1e-3;

DragInput sphere(double u, double eps = 1.0) {
  DragInput in;
  in.rho_f = kRho;
  in.mu_f = kMu;
  in.eps = eps;
  in.d_v = kD;
  in.slip = {0.0, 0.0, -u};  // fluid at rest, particle moving up at u... any direction will do
  return in;
}

DragOutput eval(std::string_view key, const DragInput& in,
                const std::map<std::string, double>& params = {}) {
  const int idx = drag_index(key);
  EXPECT_GE(idx, 0) << key;
  return drag_force(idx, in, prepare_drag(key, params));
}

/// |F| along the slip (the laws return F = beta * slip, slip = (0, 0, -u)).
double magnitude(const DragOutput& o) {
  return -o.force.z;
}

double schiller_naumann_cd(double re) {
  return re < 1000 ? 24.0 / re * (1.0 + 0.15 * std::pow(re, 0.687)) : 0.44;
}

}  // namespace

// Schiller-Naumann at Re = 0.5, 20, 500, 2000 (both branches).
TEST(Drag, SchillerNaumannHandValues) {
  const double area = kPiD * kD * kD / 4;
  for (double u : {5e-4, 0.02, 0.5, 2.0}) {
    const double re = kRho * u * kD / kMu;
    const double f_ref = schiller_naumann_cd(re) * 0.5 * kRho * area * u * u;
    const auto o = eval("schiller_naumann", sphere(u));
    EXPECT_NEAR(magnitude(o) / f_ref, 1.0, 1e-12) << "Re " << re;
    EXPECT_NEAR(o.re, re, 1e-12 * re);
  }
  EXPECT_NEAR(magnitude(eval("schiller_naumann", sphere(0.02))) / 4.099069648953341e-07, 1.0,
              1e-12);
  EXPECT_NEAR(magnitude(eval("schiller_naumann", sphere(2.0))) / 6.911503837897545e-04, 1.0, 1e-12);
  // Schiller-Naumann ignores the fluid fraction (single-particle law).
  EXPECT_EQ(eval("schiller_naumann", sphere(0.5, 0.5)).beta,
            eval("schiller_naumann", sphere(0.5)).beta);
}

// Re -> 0: F -> 3 pi mu d U. At Re = 1e-4 the correction 0.15 Re^0.687 is 2.7e-4, so 1e-3
// holds with margin and would fail for a missing factor or a wrong exponent.
TEST(Drag, SchillerNaumannStokesLimit) {
  for (double u : {1e-7, 1e-8}) {
    const double stokes = 3 * kPiD * kMu * kD * u;
    EXPECT_NEAR(magnitude(eval("schiller_naumann", sphere(u))) / stokes, 1.0, 1e-3);
  }
  // At zero slip beta is the Stokes coefficient (finite: the implicit coupling needs it).
  EXPECT_NEAR(eval("schiller_naumann", sphere(0.0)).beta, 3 * kPiD * kMu * kD, 1e-18);
}

// Di Felice: C_D0 = (0.63 + 4.8/sqrt(Re_e))^2, F = C_D0 rho/2 A U^2 eps^(2 - chi),
// chi = 3.7 - 0.65 exp(-(1.5 - log10 Re_e)^2 / 2), Re_e = eps rho U d / mu.
TEST(Drag, DiFeliceHandValues) {
  const double area = kPiD * kD * kD / 4;
  struct Case {
    double u, eps, literal;
  };
  // Re_e = 10, 30, 450, 2700.
  for (const Case c :
       {Case{0.01, 1.0, 1.8116958226542693e-07}, Case{0.05, 0.6, 3.8092029598716923e-06},
        Case{1.0, 0.45, 8.568308510507186e-04}, Case{3.0, 0.9, 2.182781178688581e-03}}) {
    const double re = c.eps * kRho * c.u * kD / kMu;
    const double cd0 = std::pow(0.63 + 4.8 / std::sqrt(re), 2);
    const double chi = 3.7 - 0.65 * std::exp(-0.5 * std::pow(1.5 - std::log10(re), 2));
    const double f_ref = cd0 * 0.5 * kRho * area * c.u * c.u * std::pow(c.eps, 2 - chi);
    const auto o = eval("di_felice", sphere(c.u, c.eps));
    EXPECT_NEAR(magnitude(o) / f_ref, 1.0, 1e-12) << "Re_e " << re;
    EXPECT_NEAR(magnitude(o) / c.literal, 1.0, 1e-12) << "Re_e " << re;
    EXPECT_NEAR(o.re, re, 1e-12 * re);
  }
}

// At eps = 1 the voidage function is 1: the law is the single-particle (Dallavalle) drag.
// log10 vs ln: the exponent's minimum 3.05 sits at Re_e = 10^1.5; with ln it would be at e^1.5.
TEST(Drag, DiFeliceReducesToSingleParticleAtEpsOne) {
  const double area = kPiD * kD * kD / 4;
  for (double u : {1e-4, 0.01, 0.3, 5.0}) {
    const double re = kRho * u * kD / kMu;
    const double single = std::pow(0.63 + 4.8 / std::sqrt(re), 2) * 0.5 * kRho * area * u * u;
    EXPECT_NEAR(magnitude(eval("di_felice", sphere(u, 1.0))) / single, 1.0, 1e-12);
  }
  // The voidage factor eps^(2 - chi) with chi(10^1.5) = 3.05 exactly: F(eps)/F(1) at the same
  // superficial Re_e = eps rho U d / mu, i.e. U scaled by 1/eps.
  const double re = std::pow(10.0, 1.5), eps = 0.5;
  const double u1 = re * kMu / (kRho * kD), ue = u1 / eps;
  const double ratio =
      magnitude(eval("di_felice", sphere(ue, eps))) / magnitude(eval("di_felice", sphere(u1)));
  // F ~ C_D0(Re_e) U^2 eps^(2-chi): ratio = (1/eps)^2 eps^(2 - 3.05) = eps^-3.05.
  EXPECT_NEAR(ratio / std::pow(eps, -3.05), 1.0, 1e-12);
  // log10, not ln: at Re_e = e^1.5 (where ln would put the minimum 3.05) the exponent is
  // 3.7 - 0.65 exp(-(1.5 - 0.651442)^2 / 2) = 3.246522.
  EXPECT_DOUBLE_EQ(cfd_dem::detail::di_felice_exponent(std::pow(10.0, 1.5)), 3.05);
  EXPECT_NEAR(cfd_dem::detail::di_felice_exponent(std::exp(1.5)), 3.246522, 1e-6);
  EXPECT_DOUBLE_EQ(cfd_dem::detail::di_felice_exponent(0.0), 3.7);
  EXPECT_NEAR(cfd_dem::detail::di_felice_exponent(1e12), 3.7, 1e-12);
}

// Wen-Yu in Gidaspow's form: K = 3/4 C_D eps (1-eps) rho U / d eps^-2.65, F = V_p K / (1-eps) U.
TEST(Drag, WenYuHandValues) {
  const double vp = kPiD * kD * kD * kD / 6;
  struct Case {
    double u, eps, literal;
  };
  // Re_e = 9, 255, 1900 (the last on the Newton branch).
  for (const Case c :
       {Case{0.01, 0.9, 2.0916676468073642e-07}, Case{0.3, 0.85, 3.371352190812221e-05},
        Case{2.0, 0.95, 7.521918175414339e-04}}) {
    const double re = c.eps * kRho * c.u * kD / kMu;
    const double k = 0.75 * schiller_naumann_cd(re) * c.eps * (1 - c.eps) * kRho * c.u / kD *
                     std::pow(c.eps, -2.65);
    const double f_ref = vp * k / (1 - c.eps) * c.u;
    EXPECT_NEAR(magnitude(eval("wen_yu", sphere(c.u, c.eps))) / f_ref, 1.0, 1e-12);
    EXPECT_NEAR(magnitude(eval("wen_yu", sphere(c.u, c.eps))) / c.literal, 1.0, 1e-12);
  }
  // eps = 1: Schiller-Naumann exactly.
  EXPECT_NEAR(eval("wen_yu", sphere(0.3)).beta / eval("schiller_naumann", sphere(0.3)).beta, 1.0,
              1e-14);
}

// Gidaspow: Ergun below the switch (K = 150 (1-eps)^2 mu/(eps d^2) + 1.75 (1-eps) rho U/d),
// Wen-Yu above.
TEST(Drag, GidaspowErgunBranchHandValues) {
  const double vp = kPiD * kD * kD * kD / 6;
  struct Case {
    double u, eps, literal;
  };
  for (const Case c : {Case{0.01, 0.5, 8.770279491271506e-07}, Case{0.3, 0.7, 9.25647835432707e-05},
                       Case{2.0, 0.6, 3.769911184307752e-03}}) {
    const double k = 150 * (1 - c.eps) * (1 - c.eps) * kMu / (c.eps * kD * kD) +
                     1.75 * (1 - c.eps) * kRho * c.u / kD;
    const double f_ref = vp * k / (1 - c.eps) * c.u;
    EXPECT_NEAR(magnitude(eval("gidaspow", sphere(c.u, c.eps))) / f_ref, 1.0, 1e-12);
    EXPECT_NEAR(magnitude(eval("gidaspow", sphere(c.u, c.eps))) / c.literal, 1.0, 1e-12);
  }
  for (double eps : {0.8, 0.9, 1.0})
    EXPECT_EQ(eval("gidaspow", sphere(0.3, eps)).beta, eval("wen_yu", sphere(0.3, eps)).beta);
}

// The switch at eps = 0.8 is a jump (Gidaspow's law is not blended). Stated and checked: each
// branch is continuous up to the switch, and Ergun / Wen-Yu at the switch is
// (150 * 0.2 / (0.8 * 6) / 3) * 0.8^2.65 = 1.1533 as Re_e -> 0 (2.97 at Re_e = 500).
TEST(Drag, GidaspowSwitchJumpAsStated) {
  const double below = 0.8 * (1 - 1e-12), at = 0.8;
  const double u = 1e-9;  // Re_e = 8e-7: Wen-Yu's inertial correction is ~1e-5
  const double jump =
      eval("gidaspow", sphere(u, below)).beta / eval("gidaspow", sphere(u, at)).beta;
  EXPECT_NEAR(jump, 150 * 0.2 / (0.8 * 6) / 3 * std::pow(0.8, 2.65), 5e-5);
  EXPECT_NEAR(
      eval("gidaspow", sphere(0.625, below)).beta / eval("gidaspow", sphere(0.625, at)).beta,
      2.9680120241872796, 1e-9);
  // A moved switch moves the jump.
  EXPECT_EQ(eval("gidaspow", sphere(0.3, 0.75), {{"switch_fraction", 0.7}}).beta,
            eval("wen_yu", sphere(0.3, 0.75)).beta);
  // Continuity within the branches: the force changes by O(delta eps).
  for (double e : {0.8 + 1e-9, 0.8 - 2e-9}) {
    const double a = eval("gidaspow", sphere(0.3, e)).beta;
    const double b = eval("gidaspow", sphere(0.3, e + 1e-9)).beta;
    EXPECT_NEAR(a / b, 1.0, 1e-7);
  }
}

// Beetstra et al. (2007), normalised F = F_d / (3 pi mu d eps U), at phi = 0.1, 0.3, 0.5 and
// Re_e = 0.9, 70, 500.
TEST(Drag, BeetstraHandValues) {
  struct Case {
    double u, eps, literal;
  };
  for (const Case c :
       {Case{0.001, 0.9, 2.1121531385533016e-08}, Case{0.1, 0.7, 1.0689624250400174e-05},
        Case{1.0, 0.5, 7.026072299174709e-04}, Case{1.0, 1.0, 2.9016680311327154e-04}}) {
    const double phi = 1 - c.eps;
    const double re = c.eps * kRho * c.u * kD / kMu;
    const double a =
        10 * phi / std::pow(1 - phi, 2) + std::pow(1 - phi, 2) * (1 + 1.5 * std::sqrt(phi));
    const double b = 0.413 * re / (24 * std::pow(1 - phi, 2)) *
                     (1 / (1 - phi) + 3 * phi * (1 - phi) + 8.4 * std::pow(re, -0.343)) /
                     (1 + std::pow(10, 3 * phi) * std::pow(re, -(1 + 4 * phi) / 2));
    const double f_ref = 3 * kPiD * kMu * kD * (c.eps * c.u) * (a + b);
    EXPECT_NEAR(magnitude(eval("beetstra", sphere(c.u, c.eps))) / f_ref, 1.0, 1e-12);
    EXPECT_NEAR(magnitude(eval("beetstra", sphere(c.u, c.eps))) / c.literal, 1.0, 1e-12);
  }
  // Stokes limit of a single sphere, and the low-Re dense limit 10 phi/eps^2 + eps^2(1+1.5 sqrt
  // phi) (the inertial term vanishes as Re^0.657): finite at zero slip.
  EXPECT_NEAR(eval("beetstra", sphere(0.0)).beta, 3 * kPiD * kMu * kD, 1e-18);
  const double phi = 0.4, e = 0.6;
  EXPECT_NEAR(
      eval("beetstra", sphere(0.0, e)).beta /
          (3 * kPiD * kMu * kD * e * (10 * phi / (e * e) + e * e * (1 + 1.5 * std::sqrt(phi)))),
      1.0, 1e-14);
}

// F = beta (u_f - v_p) for every law, any direction, and beta at zero slip is the limit of
// small slips (the implicit coupling uses beta; an inconsistent beta would bias it).
TEST(Drag, BetaConsistentWithForce) {
  for (const auto& info : drag_infos()) {
    for (double eps : {0.45, 0.7, 0.85, 1.0}) {
      for (double u : {1e-3, 0.05, 0.8}) {
        DragInput in = sphere(u, eps);
        in.slip = Vec3{0.3, -0.4, 0.866} * u;
        const auto o = eval(info.key, in);
        EXPECT_GT(o.beta, 0.0) << info.key;
        for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(o.force[a], o.beta * in.slip[a]) << info.key;
        // Opposite slip: opposite force, same beta.
        in.slip = -in.slip;
        EXPECT_DOUBLE_EQ(eval(info.key, in).beta, o.beta) << info.key;
      }
      const double b0 = eval(info.key, sphere(0.0, eps)).beta;
      const double b_small = eval(info.key, sphere(1e-12, eps)).beta;
      EXPECT_TRUE(std::isfinite(b0)) << info.key;
      EXPECT_NEAR(b_small / b0, 1.0, 1e-4) << info.key << " eps " << eps;
    }
  }
}

// Hoelzer & Sommerfeld for a spherocylinder of total length L = 4 d (the test):
// d = 2r, cylinder l = L - 2r = 6r. Independently: V = pi r^2 l + 4/3 pi r^3 = 22/3 pi r^3,
// d_v = (6V/pi)^(1/3) = 44^(1/3) r, S = 4 pi r^2 + 2 pi r l = 16 pi r^2,
// phi = pi d_v^2 / S = 44^(2/3) / 16 = 0.77896,
// phi_perp(theta) = (pi d_v^2 / 4) / (pi r^2 + 2 r l sin theta) = (pi 44^(2/3) / 4) / (pi + 12 sin
// theta) for r = 1.
TEST(DragHolzerSommerfeld, SpherocylinderAspectFourAgainstFormula) {
  const double r = 0.5e-3, l = 6 * r;  // d = 1 mm, L = 4 mm
  const double dv = std::cbrt(44.0) * r;
  const double phi = std::pow(44.0, 2.0 / 3.0) / 16.0;
  EXPECT_NEAR(phi, 0.7789599605462187, 1e-15);
  EXPECT_NEAR(spherocylinder_sphericity(r, l), phi, 1e-14);
  EXPECT_NEAR(volume_equivalent_diameter(spherocylinder_volume(r, l)), dv, 1e-15);
  const double literal_cd[4][5] = {{238.2914183788759, 26.522122863488256, 3.653553777712433,
                                    0.8317534783173013, 0.3804094949540821},
                                   {270.7453329959923, 30.185773511371536, 4.438178028672403,
                                    1.32847508958494, 0.8483408422524876},
                                   {287.84240596628274, 32.20166778341063, 4.945954430886363,
                                    1.6854397048163876, 1.190224278785684},
                                   {293.39732799449064, 32.869232197393, 5.124783083446191,
                                    1.8153947812339604, 1.3152919975890314}};
  const double angles[4] = {0, 30, 60, 90};
  const double res[5] = {0.1, 1, 10, 100, 1000};
  const Vec3 slip_dir{0, 0, 1};
  for (int a = 0; a < 4; ++a) {
    const double th = angles[a] * kPiD / 180;
    const double phi_perp = (kPiD * std::pow(44.0, 2.0 / 3.0) / 4) / (kPiD + 12 * std::sin(th));
    const Vec3 axis{std::sin(th), 0, std::cos(th)};
    for (int k = 0; k < 5; ++k) {
      const double re = res[k];
      const double u = re * kMu / (kRho * dv);
      const double cd = 8 / (re * std::sqrt(phi_perp)) + 16 / (re * std::sqrt(phi)) +
                        3 / (std::sqrt(re) * std::pow(phi, 0.75)) +
                        0.42 * std::pow(10, 0.4 * std::pow(-std::log10(phi), 0.2)) / phi_perp;
      EXPECT_NEAR(cd / literal_cd[a][k], 1.0, 1e-12) << angles[a] << " deg, Re " << re;
      const double f_ref = cd * 0.5 * kRho * kPiD * dv * dv / 4 * u * u;
      const DragInput in = spherocylinder_drag_input(kRho, kMu, 1.0, r, l, axis, u * slip_dir);
      EXPECT_NEAR(in.phi_perp, phi_perp, 1e-13);
      const auto o = eval("holzer_sommerfeld", in);
      EXPECT_NEAR(o.force.z / f_ref, 1.0, 1e-12) << angles[a] << " deg, Re " << re;
      EXPECT_NEAR(o.re, re, 1e-12 * re);
    }
  }
  // Broadside drag exceeds end-on drag at every Re (larger projected area).
  for (double re : res) {
    const double u = re * kMu / (kRho * dv);
    const auto end_on = eval("holzer_sommerfeld",
                             spherocylinder_drag_input(kRho, kMu, 1, r, l, {0, 0, 1}, {0, 0, u}));
    const auto broad = eval("holzer_sommerfeld",
                            spherocylinder_drag_input(kRho, kMu, 1, r, l, {1, 0, 0}, {0, 0, u}));
    EXPECT_GT(broad.beta, end_on.beta);
  }
}

// The voidage correction of the shape law is Di Felice's: F(eps) = F_HS(Re_e) eps^(2 - chi).
TEST(DragHolzerSommerfeld, DiFeliceVoidageCorrection) {
  const double r = 0.5e-3, l = 6 * r, eps = 0.6, u = 0.05;
  const Vec3 axis = normalized(Vec3{1, 1, 0});
  const DragInput in = spherocylinder_drag_input(kRho, kMu, eps, r, l, axis, {0, 0, u});
  const double re = eps * kRho * u * in.d_v / kMu;
  const double cd = 8 / (re * std::sqrt(in.phi_perp)) + 16 / (re * std::sqrt(in.phi)) +
                    3 / (std::sqrt(re) * std::pow(in.phi, 0.75)) +
                    0.42 * std::pow(10, 0.4 * std::pow(-std::log10(in.phi), 0.2)) / in.phi_perp;
  const double chi = 3.7 - 0.65 * std::exp(-0.5 * std::pow(1.5 - std::log10(re), 2));
  const double f_ref =
      cd * 0.5 * kRho * kPiD * in.d_v * in.d_v / 4 * u * u * std::pow(eps, 2 - chi);
  EXPECT_NEAR(eval("holzer_sommerfeld", in).force.z / f_ref, 1.0, 1e-12);
  // Zero slip: phi_perp falls back to phi (orientation average), beta finite.
  const DragInput still = spherocylinder_drag_input(kRho, kMu, eps, r, l, axis, {0, 0, 0});
  EXPECT_DOUBLE_EQ(still.phi_perp, still.phi);
  EXPECT_TRUE(std::isfinite(eval("holzer_sommerfeld", still).beta));
}

// A sphere (l = 0): phi = phi_perp = 1 and C_D = 24/Re + 3/sqrt(Re) + 0.42. Against
// Schiller-Naumann: the two fits of the standard curve differ by at most 14 % for
// 0.1 <= Re <= 300 (largest, -13.9 %, at Re = 47; +1 % at Re = 0.1), so 14 % is the stated
// closeness; at Re = 1000 HS is 22 % above (0.539 vs 0.44). Stokes limit exact (24/Re).
TEST(DragHolzerSommerfeld, SphereReducesToSphereDrag) {
  const double r = 0.5e-3;
  const DragInput probe = spherocylinder_drag_input(kRho, kMu, 1, r, 0, {0, 0, 1}, {0, 0, 1});
  EXPECT_NEAR(probe.phi, 1.0, 1e-14);
  EXPECT_NEAR(probe.phi_perp, 1.0, 1e-14);
  double worst = 0;
  for (double lre = -1; lre <= std::log10(300.0) + 1e-9; lre += 0.01) {
    const double re = std::pow(10, lre), u = re * kMu / (kRho * 2 * r);
    const auto o = eval("holzer_sommerfeld",
                        spherocylinder_drag_input(kRho, kMu, 1, r, 0, {0, 0, 1}, {0, 0, u}));
    const double dev = o.beta / eval("schiller_naumann", sphere(u)).beta - 1;
    EXPECT_TRUE(std::isfinite(dev));
    worst = std::max(worst, std::abs(dev));
  }
  EXPECT_LT(worst, 0.14);
  EXPECT_GT(worst, 0.13);  // the stated figure, not a looser one
  const double u0 = 1e-12;
  EXPECT_NEAR(eval("holzer_sommerfeld",
                   spherocylinder_drag_input(kRho, kMu, 1, r, 0, {0, 0, 1}, {0, 0, u0}))
                      .beta /
                  (3 * kPiD * kMu * 2 * r),
              1.0, 1e-5);
}

// Exact projected area: end-on a disk pi r^2, broadside pi r^2 + 2 r l; the mean over random
// directions is S/4 (Cauchy), checked by quadrature over the angle (sin theta uniform in cos).
TEST(DragHolzerSommerfeld, ProjectedAreaOfSpherocylinder) {
  const double r = 0.3, l = 1.7;
  EXPECT_DOUBLE_EQ(spherocylinder_projected_area(r, l, 0), kPiD * r * r);
  EXPECT_DOUBLE_EQ(spherocylinder_projected_area(r, l, 1), kPiD * r * r + 2 * r * l);
  const int n = 20000;
  double mean = 0;
  for (int k = 0; k < n; ++k) {
    const double c = -1 + (k + 0.5) * 2.0 / n;
    mean += spherocylinder_projected_area(r, l, std::sqrt(1 - c * c)) / n;
  }
  EXPECT_NEAR(mean / (spherocylinder_surface(r, l) / 4), 1.0, 1e-7);
  EXPECT_NEAR(sin_incidence({0, 0, 1}, {1, 0, 1}), std::sqrt(0.5), 1e-15);
}

TEST(Drag, PressureGradientForceIsBuoyancyInHydrostaticFluid) {
  const Vec3 g{0, 0, -9.81};
  const double v = 1e-9, rho = 1000;
  const Vec3 f = pressure_gradient_force(v, rho * g);  // grad p = rho_f g at rest
  EXPECT_DOUBLE_EQ(f.z, rho * v * 9.81);
  EXPECT_EQ(f.x, 0.0);
}

TEST(DragRegistry, KeysInfosAndDispatch) {
  const auto infos = drag_infos();
  ASSERT_EQ(infos.size(), DragLaws::size);
  const char* keys[] = {"schiller_naumann", "di_felice", "wen_yu",
                        "gidaspow",         "beetstra",  "holzer_sommerfeld"};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(infos[i].key, keys[i]);
    EXPECT_EQ(drag_index(keys[i]), i);
    ASSERT_NE(find_drag(keys[i]), nullptr);
    EXPECT_FALSE(infos[i].equation.empty());
    EXPECT_FALSE(infos[i].reference.empty());
    EXPECT_FALSE(infos[i].validity.empty());
    EXPECT_EQ(prepare_drag(keys[i]).law, i);
  }
  EXPECT_EQ(drag_index("stokes"), -1);
  EXPECT_EQ(find_drag("stokes"), nullptr);
  EXPECT_THROW(prepare_drag("stokes"), Error);
  EXPECT_THROW(prepare_drag("gidaspow", {{"switch_fraction", 1.5}}), Error);
  EXPECT_THROW(prepare_drag("gidaspow", {{"switch_fraction", 0.0}}), Error);
  EXPECT_THROW(prepare_drag("di_felice", {{"switch_fraction", 0.5}}), Error);
  EXPECT_EQ(prepare_drag("gidaspow", {{"switch_fraction", 0.7}}).switch_fraction, 0.7);
  // Dispatch equals the direct call.
  const DragInput in = sphere(0.2, 0.7);
  const DragParams p = prepare_drag("beetstra");
  EXPECT_EQ(drag_force(p.law, in, p).beta, Beetstra::eval(in, p).beta);
  ASSERT_EQ(find_drag("gidaspow")->params.size(), 1u);
  EXPECT_EQ(find_drag("gidaspow")->params[0].name, "switch_fraction");
}

// A drag law's parameters given in the case file reach the coupled run: Gidaspow with its
// Ergun/Wen-Yu switch at fluid fraction 1e-9 is Wen-Yu everywhere, so the bubbling bed's grains
// move bit for bit as with `drag: wen_yu`; the default switch (0.8) puts the dense bed on Ergun.
TEST(CoupledDrag, CaseParametersReachTheGrains) {
  std::ifstream in(std::string(GF_SOURCE_DIR) + "/cases/cfd_dem/fluidized_bed/case.yaml");
  std::stringstream text;
  text << in.rdbuf();
  const std::string base = text.str();
  auto run = [&](const std::string& drag) {
    std::string t = base;
    const std::string from = "drag: di_felice";
    t.replace(t.find(from), from.size(), "drag: " + drag);
    Simulation sim(input::load_case_text(t, "case.yaml"));
    for (int s = 0; s < 60; ++s) sim.step();  // two fluid steps (interval 25)
    const auto& p = sim.particles();
    return std::vector<Vec3>(p.v(), p.v() + p.size());
  };
  const auto wen_yu = run("wen_yu");
  EXPECT_EQ(run("{model: gidaspow, switch_fraction: 1.0e-9}"), wen_yu);
  const auto ergun = run("{model: gidaspow}");
  double max_dv = 0;
  for (std::size_t i = 0; i < ergun.size(); ++i)
    max_dv = std::max(max_dv, norm(ergun[i] - wen_yu[i]));
  EXPECT_GT(max_dv, 1e-4);  // m/s after 0.6 ms: the laws differ by tens of per cent at eps ~ 0.5
}
