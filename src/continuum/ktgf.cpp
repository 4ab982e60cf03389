// SPDX-License-Identifier: GPL-3.0-or-later
// KTGF registries (closure sets, g0, frictional and particle-pressure models), homogeneous states.
#include "continuum/ktgf.hpp"

#include <fmt/format.h>

#include <optional>

#include "core/error.hpp"

namespace gf::continuum {

namespace {

template <class List>
std::vector<KtgfInfo> infos_of(List list) {
  std::vector<KtgfInfo> out;
  for_each_type(list, [&]<class M>() {
    out.push_back(
        {M::key, M::summary, M::equation, M::reference, std::span<const ParamSpec>(M::params)});
  });
  return out;
}

const KtgfInfo* find_in(const std::vector<KtgfInfo>& infos, std::string_view key) {
  for (const auto& d : infos)
    if (d.key == key) return &d;
  return nullptr;
}

std::string keys_of(const std::vector<KtgfInfo>& infos) {
  std::string out;
  for (const auto& d : infos) out += fmt::format("{}{}", out.empty() ? "" : ", ", d.key);
  return out;
}

/// The checks every homogeneous-state function makes of its inputs.
void require_state(std::string_view what, double a, const KtgfParams& p) {
  REQUIRE(a > 0 && a < p.packing_limit, "{}: volume fraction {} not in (0, {})", what, a,
          p.packing_limit);
  REQUIRE(p.restitution >= 0 && p.restitution < 1,
          "{}: restitution {} not in [0, 1) (e = 1 dissipates nothing: no steady or cooling "
          "state)",
          what, p.restitution);
  REQUIRE(p.diameter > 0 && p.density > 0,
          "{}: grain diameter {} m and density {} kg/m^3 must be > 0 (use prepare_ktgf)", what,
          p.diameter, p.density);
}

}  // namespace

std::vector<KtgfInfo> ktgf_closure_infos() {
  return infos_of(KtgfClosures{});
}
const KtgfInfo* find_ktgf_closure(std::string_view key) {
  static const std::vector<KtgfInfo> infos = ktgf_closure_infos();
  return find_in(infos, key);
}

std::vector<KtgfInfo> radial_distribution_infos() {
  return infos_of(RadialDistributions{});
}
const KtgfInfo* find_radial_distribution(std::string_view key) {
  static const std::vector<KtgfInfo> infos = radial_distribution_infos();
  return find_in(infos, key);
}

std::vector<KtgfInfo> frictional_model_infos() {
  return infos_of(FrictionalModels{});
}
const KtgfInfo* find_frictional_model(std::string_view key) {
  static const std::vector<KtgfInfo> infos = frictional_model_infos();
  return find_in(infos, key);
}

std::vector<KtgfInfo> particle_pressure_model_infos() {
  return infos_of(ParticlePressureModels{});
}
const KtgfInfo* find_particle_pressure_model(std::string_view key) {
  static const std::vector<KtgfInfo> infos = particle_pressure_model_infos();
  return find_in(infos, key);
}

KtgfParams prepare_ktgf(std::string_view key, const std::map<std::string, double>& params,
                        std::string_view radial) {
  const int idx = index_of_key(KtgfClosures{}, key);
  REQUIRE(idx >= 0, "unknown KTGF closure set '{}' (known: {})", key,
          keys_of(ktgf_closure_infos()));
  const int ridx = index_of_key(RadialDistributions{}, radial);
  REQUIRE(ridx >= 0, "unknown radial distribution '{}' (known: {})", radial,
          keys_of(radial_distribution_infos()));
  // One schema: the set's parameters and the radial distribution's.
  std::vector<ParamSpec> schema(find_ktgf_closure(key)->params.begin(),
                                find_ktgf_closure(key)->params.end());
  for (const auto& s : find_radial_distribution(radial)->params) schema.push_back(s);
  check_params(fmt::format("KTGF closure set '{}' with radial distribution '{}'", key, radial),
               schema, params, true);
  auto get = [&](std::string_view name) { return param_value(params, name); };
  KtgfParams p;
  dispatch_index(KtgfClosures{}, idx, [&]<class M>() { M::prepare(p, get); });
  dispatch_index(RadialDistributions{}, ridx, [&]<class R>() { R::prepare(p, get); });
  p.model = idx;
  p.radial = ridx;
  return p;
}

FrictionalParams prepare_frictional(std::string_view key,
                                    const std::map<std::string, double>& params) {
  const int idx = index_of_key(FrictionalModels{}, key);
  REQUIRE(idx >= 0, "unknown frictional model '{}' (known: {})", key,
          keys_of(frictional_model_infos()));
  check_params(fmt::format("frictional model '{}'", key), find_frictional_model(key)->params,
               params, true);
  auto get = [&](std::string_view name) { return param_value(params, name); };
  FrictionalParams f;
  dispatch_index(FrictionalModels{}, idx, [&]<class M>() { M::prepare(f, get); });
  f.model = idx;
  return f;
}

ParticlePressureParams prepare_particle_pressure(std::string_view key,
                                                 const std::map<std::string, double>& params) {
  const int idx = index_of_key(ParticlePressureModels{}, key);
  REQUIRE(idx >= 0, "unknown particle-pressure model '{}' (known: {})", key,
          keys_of(particle_pressure_model_infos()));
  check_params(fmt::format("particle-pressure model '{}'", key),
               find_particle_pressure_model(key)->params, params, true);
  auto get = [&](std::string_view name) { return param_value(params, name); };
  ParticlePressureParams p;
  dispatch_index(ParticlePressureModels{}, idx, [&]<class M>() { M::prepare(p, get); });
  p.model = idx;
  return p;
}

KtgfShearState ktgf_simple_shear(double a, double shear_rate, const KtgfParams& p) {
  require_state("ktgf_simple_shear", a, p);
  REQUIRE(std::isfinite(shear_rate), "ktgf_simple_shear: shear rate {} 1/s not finite", shear_rate);
  // mu_s = m1 sqrt(T) and gamma_s = c T^1.5 at fixed a (every set): m1 gamma_dot^2 = c T.
  const double m1 = solids_shear_viscosity(a, 1.0, p);
  const double c = collisional_dissipation(a, 1.0, p);
  KtgfShearState s;
  s.temperature = m1 / c * shear_rate * shear_rate;
  s.pressure = solids_pressure(a, s.temperature, p);
  s.viscosity = solids_shear_viscosity(a, s.temperature, p);
  s.shear_stress = s.viscosity * shear_rate;
  // |tau| / P with gamma_dot = 1 (the rate cancels; defined also for gamma_dot = 0)
  s.friction = m1 * std::sqrt(m1 / c) / solids_pressure(a, m1 / c, p);
  return s;
}

double haff_time(double a, double theta0, const KtgfParams& p) {
  require_state("haff_time", a, p);
  REQUIRE(theta0 > 0 && std::isfinite(theta0),
          "haff_time: initial granular temperature {} m^2/s^2 not > 0", theta0);
  // gamma_s = c Theta^1.5: (3/2) a rho dTheta/dt = -c Theta^1.5 => Theta^-1/2 grows at the rate
  // c / (3 a rho), so Theta = Theta0 / (1 + t/tau)^2 with tau = 3 a rho / (c sqrt(Theta0)).
  const double c = collisional_dissipation(a, 1.0, p);
  return 3.0 * a * p.density / (c * std::sqrt(theta0));
}

double haff_temperature(double a, double theta0, double t, const KtgfParams& p) {
  REQUIRE(t >= 0, "haff_temperature: time {} s < 0", t);
  const double q = 1.0 + t / haff_time(a, theta0, p);
  return theta0 / (q * q);
}

}  // namespace gf::continuum
