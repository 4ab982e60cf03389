// SPDX-License-Identifier: GPL-3.0-or-later
// Layered mean velocity, fluctuation stresses, order tensor and measured shear rate.
#include "analysis/rheology.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "contact/geometry/capsule.hpp"
#include "core/error.hpp"
#include "particles/shapes.hpp"

namespace gf::analysis {

double RheologySample::pressure() const {
  const Mat3 s = total();
  return (s.a[0][0] + s.a[1][1] + s.a[2][2]) / 3;
}
double RheologySample::streaming_pressure() const {
  return (streaming.a[0][0] + streaming.a[1][1] + streaming.a[2][2]) / 3;
}
double RheologySample::collisional_pressure() const {
  return (collisional.a[0][0] + collisional.a[1][1] + collisional.a[2][2]) / 3;
}
double RheologySample::shear_stress() const {
  const Mat3 t = total();
  return 0.5 * (t.a[0][2] + t.a[2][0]);
}
double RheologySample::friction() const {
  const double p = pressure();
  return p > 0 ? std::abs(shear_stress()) / p : 0.0;
}
double RheologySample::viscosity() const {
  return shear_rate != 0 ? -shear_stress() / shear_rate : 0.0;
}
double first_normal_difference(const Mat3& s) {
  return s.a[0][0] - s.a[2][2];
}
double second_normal_difference(const Mat3& s) {
  return s.a[2][2] - s.a[1][1];
}
double RheologySample::first_normal_difference() const {
  return analysis::first_normal_difference(total());
}
double RheologySample::second_normal_difference() const {
  return analysis::second_normal_difference(total());
}

RheologySample measure_rheology(const ParticleStore& p, const RheologyRegion& region,
                                const ContactSums& contacts, std::span<const double> density) {
  REQUIRE(region.z_hi > region.z_lo && region.bins >= 1 && region.area > 0,
          "invalid rheology region");
  const std::size_t n = p.size();
  const Vec3* x = p.x();
  const Vec3* v = p.v();
  const double* m = p.mass();
  const std::int32_t* mat = p.material();
  const int f_uf = p.find_field("fluid_velocity");
  const Vec3* uf = f_uf >= 0 ? p.get<Vec3>(f_uf).data() : nullptr;
  const double h = region.z_hi - region.z_lo;
  const auto nb = static_cast<std::size_t>(region.bins);
  auto bin_of = [&](double z) {
    const auto b = static_cast<std::size_t>((z - region.z_lo) / h * region.bins);
    return std::min(b, nb - 1);
  };
  auto inside = [&](std::size_t i) { return x[i].z >= region.z_lo && x[i].z < region.z_hi; };

  // Mean (mass-weighted) velocity of each layer; sums for the least-squares slope of v_x(z).
  std::vector<Vec3> momentum(nb), fluid(nb);  // fluid: mass-weighted like the grains' mean
  std::vector<double> mass(nb, 0.0), mass2(nb, 0.0);
  std::vector<std::int64_t> members(nb, 0);
  double solid = 0, sz = 0, szz = 0, su = 0, szu = 0;
  std::int64_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!inside(i)) continue;
    const std::size_t b = bin_of(x[i].z);
    momentum[b] += m[i] * v[i];
    if (uf != nullptr) fluid[b] += m[i] * uf[i];
    mass[b] += m[i];
    mass2[b] += m[i] * m[i];
    ++members[b];
    solid += m[i] / density[static_cast<std::size_t>(mat[i])];
    const double z = x[i].z - region.z_lo;
    sz += z;
    szz += z * z;
    su += v[i].x;
    szu += z * v[i].x;
    ++count;
  }
  RheologySample s;
  s.grains = count;
  const double V = region.volume();
  s.volume_fraction = solid / V;
  if (count >= 2) {
    const double c = static_cast<double>(count);
    const double var = szz - sz * sz / c;
    if (var > 0) s.shear_rate = (szu - sz * su / c) / var;
  }
  // Fluctuations about a mean taken from the same few grains (~13 per layer in the paper's
  // box) are too small by the factor 1 - sum m^2 / M^2 (Bessel's correction for a weighted
  // mean; (n - 1)/n for equal masses, 8 % with 13 grains): the sums of each layer are divided
  // by it. A layer with a single grain says nothing about fluctuations and is left out.
  std::vector<double> unbias(nb, 0.0);
  std::int64_t counted = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    if (members[b] < 2) continue;
    momentum[b] = (1.0 / mass[b]) * momentum[b];
    fluid[b] = (1.0 / mass[b]) * fluid[b];
    unbias[b] = 1.0 / (1.0 - mass2[b] / (mass[b] * mass[b]));
    counted += members[b];
  }

  const bool shapes = p.has_shapes();
  double t_sum = 0, fluid_sum = 0, slip_sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!inside(i)) continue;
    if (shapes && static_cast<ShapeCode>(p.shape()[i]) == ShapeCode::Spherocylinder) {
      const Vec3 u = contact::capsule_axis(p.orientation()[i]);
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) s.order.a[a][b] += u[a] * u[b];
      ++s.rods;
    }
    const std::size_t b = bin_of(x[i].z);
    if (unbias[b] == 0) continue;
    const Vec3 dv = v[i] - momentum[b];
    const double w = unbias[b];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) s.streaming.a[a][c] += w * m[i] * dv[a] * dv[c];
    t_sum += w * norm2(dv);
    if (uf != nullptr) {
      const Vec3 du = uf[i] - fluid[b];
      fluid_sum += w * norm2(du);
      slip_sum += w * norm2(dv - du);
    }
  }
  // Layers left out hold no streaming stress: scale up by the grains they hold.
  if (counted > 0 && counted < count)
    s.streaming = (static_cast<double>(count) / static_cast<double>(counted)) * s.streaming;
  s.streaming = (1.0 / V) * s.streaming;
  s.collisional = (1.0 / V) * contacts.virial;
  const Mat3& nn = contacts.normals;
  const double pairs = nn.a[0][0] + nn.a[1][1] + nn.a[2][2];
  s.contacts = std::llround(pairs);
  if (pairs > 0) {
    s.fabric = (1.0 / pairs) * nn;
    const double fxx = s.fabric.a[0][0], fzz = s.fabric.a[2][2], fxz = s.fabric.a[0][2];
    s.fabric_angle = 0.5 * std::atan2(2 * fxz, fxx - fzz) * 180.0 / std::numbers::pi;
  }
  if (count > 0) s.coordination = 2.0 * pairs / static_cast<double>(count);
  const double per_grain = counted > 0 ? 1.0 / (3.0 * static_cast<double>(counted)) : 0.0;
  s.temperature = per_grain * t_sum;
  s.fluid_temperature = per_grain * fluid_sum;
  s.slip_temperature = uf != nullptr ? per_grain * slip_sum : s.temperature;
  if (s.rods > 0) {
    s.order = (1.0 / static_cast<double>(s.rods)) * s.order;
    const double sxx = s.order.a[0][0], szz_ = s.order.a[2][2], sxz = s.order.a[0][2];
    s.alignment_angle = 0.5 * std::atan2(2 * sxz, sxx - szz_) * 180.0 / std::numbers::pi;
    Eigen::Matrix3d q;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) q(a, b) = 1.5 * s.order.a[a][b] - (a == b ? 0.5 : 0.0);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(q, Eigen::EigenvaluesOnly);
    s.order_parameter = es.eigenvalues().maxCoeff();
  }
  return s;
}

const std::vector<std::string>& rheology_columns() {
  static const std::vector<std::string> cols{"volume_fraction",
                                             "shear_rate",
                                             "granular_temperature",
                                             "fluid_temperature",
                                             "slip_temperature",
                                             "pressure",
                                             "pressure_streaming",
                                             "pressure_collisional",
                                             "sigma_xx",
                                             "sigma_yy",
                                             "sigma_zz",
                                             "sigma_xy",
                                             "sigma_xz",
                                             "sigma_yz",
                                             "sigma_s_xz",
                                             "sigma_c_xz",
                                             "friction",
                                             "viscosity",
                                             "N1",
                                             "N2",
                                             "N1_collisional",
                                             "N2_collisional",
                                             "S_xx",
                                             "S_yy",
                                             "S_zz",
                                             "S_xz",
                                             "alignment_angle",
                                             "order_parameter",
                                             "grains",
                                             "coordination_number",
                                             "F_xx",
                                             "F_yy",
                                             "F_zz",
                                             "F_xz",
                                             "fabric_angle"};
  return cols;
}

std::vector<double> rheology_values(const RheologySample& s) {
  const Mat3 t = s.total();
  // Shear components as the symmetric part (the collisional virial of non-spherical grains
  // has a small antisymmetric part that averages out at steady state).
  auto sym = [&](int a, int b) { return 0.5 * (t.a[a][b] + t.a[b][a]); };
  return {s.volume_fraction,
          s.shear_rate,
          s.temperature,
          s.fluid_temperature,
          s.slip_temperature,
          s.pressure(),
          s.streaming_pressure(),
          s.collisional_pressure(),
          t.a[0][0],
          t.a[1][1],
          t.a[2][2],
          sym(0, 1),
          sym(0, 2),
          sym(1, 2),
          0.5 * (s.streaming.a[0][2] + s.streaming.a[2][0]),
          0.5 * (s.collisional.a[0][2] + s.collisional.a[2][0]),
          s.friction(),
          s.viscosity(),
          s.first_normal_difference(),
          s.second_normal_difference(),
          first_normal_difference(s.collisional),
          second_normal_difference(s.collisional),
          s.order.a[0][0],
          s.order.a[1][1],
          s.order.a[2][2],
          s.order.a[0][2],
          s.alignment_angle,
          s.order_parameter,
          static_cast<double>(s.grains),
          s.coordination,
          s.fabric.a[0][0],
          s.fabric.a[1][1],
          s.fabric.a[2][2],
          s.fabric.a[0][2],
          s.fabric_angle};
}

}  // namespace gf::analysis
