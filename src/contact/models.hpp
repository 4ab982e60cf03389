// SPDX-License-Identifier: GPL-3.0-or-later
// The contact models users select by key: each composes the law slots and declares its
// parameter schema, equation and reference; `prepare` derives per-pair constants once.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "contact/laws/contact_law.hpp"
#include "contact/laws/restitution_map.hpp"
#include "core/error.hpp"
#include "core/params.hpp"
#include "particles/material.hpp"

namespace gf::contact {

/// Parameter values of one `contacts:` entry, by schema name, defaults filled in.
using ParamLookup = double (*)(const void* ctx, std::string_view name);

/// What `prepare` needs besides the parameters.
struct PairContext {
  const Material* a;
  const Material* b;
  double reference_radius;  ///< largest radius among grains of the two materials (m); walls: 0
};

/// Effective modulus E* = 1 / ((1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b).
inline double effective_modulus(const Material& a, const Material& b) {
  return 1.0 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}
/// Effective shear modulus G* = 1 / (2(2 - nu_a)(1 + nu_a)/E_a + 2(2 - nu_b)(1 + nu_b)/E_b).
inline double effective_shear_modulus(const Material& a, const Material& b) {
  return 1.0 / (2 * (2 - a.poisson_ratio) * (1 + a.poisson_ratio) / a.youngs_modulus +
                2 * (2 - b.poisson_ratio) * (1 + b.poisson_ratio) / b.youngs_modulus);
}

inline constexpr ParamSpec restitution_param{
    "restitution",
    "1",
    std::nullopt,
    0.0,
    1.0,
    true,
    ParamScope::PerPair,
    "coefficient of normal restitution realised by a binary collision"};
inline constexpr ParamSpec friction_param{"friction",
                                          "1",
                                          0.5,
                                          0.0,
                                          1e3,
                                          false,
                                          ParamScope::PerPair,
                                          "Coulomb friction coefficient mu (|F_t| <= mu F_n)"};
inline constexpr ParamSpec rolling_param{
    "rolling_friction",
    "1",
    0.0,
    0.0,
    1e3,
    false,
    ParamScope::PerPair,
    "rolling resistance coefficient mu_r (torque mu_r R* F_n)"};

inline constexpr ParamSpec cohesion_param{
    "cohesion_energy_density",
    "J/m^3",
    0.0,
    0.0,
    1e12,
    false,
    ParamScope::PerPair,
    "sjkr cohesion k_c: attractive normal force k_c A while overlapping, A the contact area "
    "(0: none; docs/models/cohesion.md)"};

struct Hooke {
  using Law = ContactLaw<HookeNormal, ViscousDamping, HistoryTangential, ConstantTorqueRolling,
                         SjkrCohesion>;
  static constexpr std::string_view key = "hooke";
  static constexpr std::string_view summary =
      "linear spring-dashpot with tangential history spring, Coulomb friction, rolling resistance, "
      "optional sjkr cohesion";
  static constexpr std::string_view equation =
      "F_n = k_n delta - 2 zeta sqrt(m* k_n) v_n (>= 0);  F_t = -k_t xi - 2 zeta sqrt(m* k_t) v_t, "
      "|F_t| <= mu F_n;  cohesion (sjkr): F_n -= k_c A while delta > 0;  "
      "k_n given or k_n = m*_ref v_ref^2 / delta_max^2;  zeta from the realised restitution";
  static constexpr std::string_view reference =
      "Cundall & Strack, Geotechnique 29 (1979) 47; rolling: Ai et al., Powder Technol. 206 (2011) "
      "269, model A; cohesion: Johnson, Kendall & Roberts, Proc. R. Soc. A 324 (1971) 301, "
      "simplified as LIGGGHTS sjkr";
  static constexpr std::array<ParamSpec, 8> params{
      restitution_param,
      friction_param,
      rolling_param,
      cohesion_param,
      ParamSpec{"stiffness", "N/m", std::nullopt, 0.0, 1e20, true, ParamScope::PerPair,
                "normal spring stiffness k_n (or give max_overlap and reference_velocity)"},
      ParamSpec{"max_overlap", "1", std::nullopt, 0.0, 0.5, true, ParamScope::PerPair,
                "largest overlap, as a fraction of the reference radius, at reference_velocity"},
      ParamSpec{"reference_velocity", "m/s", std::nullopt, 0.0, 1e6, true, ParamScope::PerPair,
                "impact speed at which max_overlap is reached"},
      ParamSpec{"tangential_stiffness_ratio", "1", 2.0 / 7.0, 0.0, 10.0, true, ParamScope::PerPair,
                "k_t / k_n"},
  };
  template <class Get>
  static PairCoeffs prepare(const PairContext& ctx, Get&& get) {
    PairCoeffs c;
    const auto e = get("restitution");
    c.damping_ratio = damping_ratio_for_restitution(NormalKind::Linear, *e);
    c.friction = get("friction").value_or(0.5);
    c.rolling_friction = get("rolling_friction").value_or(0.0);
    c.cohesion = get("cohesion_energy_density").value_or(0.0);
    c.kt_ratio = get("tangential_stiffness_ratio").value_or(2.0 / 7.0);
    c.sqrt_kt_ratio = std::sqrt(c.kt_ratio);
    if (auto k = get("stiffness")) {
      c.stiffness = *k;
    } else {
      const auto dmax = get("max_overlap");
      const auto vref = get("reference_velocity");
      REQUIRE(dmax && vref,
              "hooke needs 'stiffness' or both 'max_overlap' and 'reference_velocity'");
      // Energy balance of an undamped impact of two reference grains: m* v^2 = k delta_max^2.
      const double r = ctx.reference_radius;
      const double rho = 0.5 * (ctx.a->density + ctx.b->density);
      const double m_eff = 0.5 * rho * 4.0 / 3.0 * 3.141592653589793 * r * r * r;
      const double delta = *dmax * r;
      c.stiffness = m_eff * (*vref) * (*vref) / (delta * delta);
    }
    return c;
  }
};

struct HertzMindlin {
  using Law = ContactLaw<HertzNormal, ViscousDamping, HistoryTangential, ConstantTorqueRolling,
                         SjkrCohesion>;
  static constexpr std::string_view key = "hertz_mindlin";
  static constexpr std::string_view summary =
      "Hertz normal force, Mindlin no-slip tangential stiffness with history, Coulomb friction, "
      "rolling resistance, optional sjkr cohesion";
  static constexpr std::string_view equation =
      "F_n = 4/3 E* sqrt(R*) delta^(3/2) - 2 zeta sqrt(m* S_n) v_n (>= 0), S_n = 2 E* sqrt(R* "
      "delta);  "
      "F_t = -k_t xi - 2 zeta sqrt(m* k_t) v_t, k_t = 8 G* sqrt(R* delta), |F_t| <= mu F_n;  "
      "cohesion (sjkr): F_n -= k_c A while delta > 0;  zeta from the realised restitution";
  static constexpr std::string_view reference =
      "Hertz (1882); Mindlin, J. Appl. Mech. 16 (1949) 259; Tsuji et al., Powder Technol. 71 "
      "(1992) 239; "
      "Johnson, Contact Mechanics (1985) eq. 4.22; cohesion: Johnson, Kendall & Roberts, Proc. R. "
      "Soc. A 324 (1971) 301, simplified as LIGGGHTS sjkr";
  static constexpr std::array<ParamSpec, 4> params{restitution_param, friction_param, rolling_param,
                                                   cohesion_param};
  template <class Get>
  static PairCoeffs prepare(const PairContext& ctx, Get&& get) {
    PairCoeffs c;
    c.damping_ratio = damping_ratio_for_restitution(NormalKind::Hertz, *get("restitution"));
    c.friction = get("friction").value_or(0.5);
    c.rolling_friction = get("rolling_friction").value_or(0.0);
    c.cohesion = get("cohesion_energy_density").value_or(0.0);
    c.stiffness = effective_modulus(*ctx.a, *ctx.b);
    c.shear_modulus = effective_shear_modulus(*ctx.a, *ctx.b);
    // Mindlin k_t = 8 G* sqrt(R* delta) = (4 G*/E*) S_n.
    c.kt_ratio = 4.0 * c.shear_modulus / c.stiffness;
    c.sqrt_kt_ratio = std::sqrt(c.kt_ratio);
    return c;
  }
};

}  // namespace gf::contact
