// SPDX-License-Identifier: GPL-3.0-or-later
// ParticleStore: the field table and the generic column operations.
#include "particles/particle_store.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace gf {

ParticleStore::ParticleStore() {
  constexpr unsigned RO = kRestart | kOutput | kGhost;
  add_field("id", FieldType::Int64, "1", RO);
  add_field("material", FieldType::Int32, "1", RO);
  add_field("radius", FieldType::Real, "m", RO);
  add_field("mass", FieldType::Real, "kg", kRestart | kGhost);
  add_field("inertia", FieldType::Real, "kg m^2", kRestart | kGhost);
  add_field("position", FieldType::Vec3, "m", RO);
  add_field("velocity", FieldType::Vec3, "m/s", RO);
  add_field("angular_velocity", FieldType::Vec3, "rad/s", RO);
  add_field("force", FieldType::Vec3, "N", kRestart | kOutput);
  add_field("torque", FieldType::Vec3, "N m", kRestart);
}

int ParticleStore::add_field(const std::string& name, FieldType type, const std::string& unit,
                             unsigned flags) {
  REQUIRE(find_field(name) < 0, "particle field '{}' registered twice", name);
  info_.push_back({name, type, unit, flags});
  switch (type) {
    case FieldType::Real:
      cols_.emplace_back(std::vector<double>(n_));
      break;
    case FieldType::Vec3:
      cols_.emplace_back(std::vector<Vec3>(n_));
      break;
    case FieldType::Int64:
      cols_.emplace_back(std::vector<std::int64_t>(n_));
      break;
    case FieldType::Int32:
      cols_.emplace_back(std::vector<std::int32_t>(n_));
      break;
    case FieldType::Quat:
      cols_.emplace_back(std::vector<Quat>(n_));
      break;
  }
  return static_cast<int>(info_.size()) - 1;
}

void ParticleStore::enable_shapes() {
  if (shape_field_ >= 0) return;
  constexpr unsigned RO = kRestart | kOutput | kGhost;
  shape_field_ = add_field("shape", FieldType::Int32, "1", RO);
  add_field("half_length", FieldType::Real, "m", RO);
  add_field("orientation", FieldType::Quat, "1", RO);
  add_field("angular_momentum", FieldType::Vec3, "kg m^2/s", kRestart | kGhost);
  add_field("inertia_body", FieldType::Vec3, "kg m^2", kRestart | kGhost);
  add_field("polygon", FieldType::Int32, "1", RO);
  // Fields are zero-filled; the identity quaternion and "no polygon" are not zero.
  for (auto& q : get<Quat>(shape_field_ + 2)) q = Quat{};
  for (auto& k : get<std::int32_t>(shape_field_ + 5)) k = -1;
}

void ParticleStore::enable_fixed() {
  if (fixed_field_ >= 0) return;
  fixed_field_ = add_field("fixed", FieldType::Int32, "1", kRestart | kOutput | kGhost);
}

void ParticleStore::enable_fixed_motion() {
  if (fixed_x0_field_ >= 0) return;
  fixed_x0_field_ = add_field("fixed_x0", FieldType::Vec3, "m", kRestart | kGhost);
  if (has_shapes()) {
    fixed_q0_field_ = add_field("fixed_q0", FieldType::Quat, "1", kRestart | kGhost);
    for (auto& q : get<Quat>(fixed_q0_field_)) q = Quat{};
  }
}

int ParticleStore::find_field(const std::string& name) const {
  for (std::size_t i = 0; i < info_.size(); ++i)
    if (info_[i].name == name) return static_cast<int>(i);
  return -1;
}

void ParticleStore::resize(std::size_t n) {
  for (auto& c : cols_) std::visit([n](auto& v) { v.resize(n); }, c);
  n_ = n;
}

void ParticleStore::reserve(std::size_t n) {
  for (auto& c : cols_) std::visit([n](auto& v) { v.reserve(n); }, c);
}

std::size_t ParticleStore::add_sphere(std::int64_t pid, int mat, double r, double density,
                                      const Vec3& pos, const Vec3& vel, const Vec3& w) {
  const std::size_t i = n_;
  resize(n_ + 1);
  const double m = density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  id()[i] = pid;
  material()[i] = mat;
  radius()[i] = r;
  mass()[i] = m;
  inertia()[i] = 0.4 * m * r * r;
  x()[i] = pos;
  v()[i] = vel;
  omega()[i] = w;
  if (has_shapes()) polygon()[i] = -1;
  return i;
}

void ParticleStore::permute(std::span<const std::int64_t> order) {
  REQUIRE(order.size() == n_, "permutation of {} entries for {} particles", order.size(), n_);
  // In place, cycle by cycle: a gathered copy of each column would add 24 bytes per particle
  // to the peak memory of every neighbour rebuild (issue 3 counts bytes per particle), and the
  // random reads are the same either way.
  const std::size_t words = (n_ + 63) / 64;
  for (auto& c : cols_) {
    std::visit(
        [&](auto& v) {
          done_.assign(words, 0);
          for (std::size_t start = 0; start < n_; ++start) {
            if ((done_[start >> 6] >> (start & 63)) & 1u) continue;
            auto held = v[start];
            std::size_t j = start;
            for (;;) {
              done_[j >> 6] |= std::uint64_t{1} << (j & 63);
              const auto k = static_cast<std::size_t>(order[j]);
              REQUIRE(k < n_ && (k == start || !((done_[k >> 6] >> (k & 63)) & 1u)),
                      "re-ordering of particles: the order is not a permutation");
              if (k == start) {
                v[j] = held;
                break;
              }
              v[j] = v[k];
              j = k;
            }
          }
        },
        c);
  }
}

void ParticleStore::shrink_to_fit() {
  for (auto& c : cols_) std::visit([](auto& v) { v.shrink_to_fit(); }, c);
  done_.shrink_to_fit();
}

std::size_t ParticleStore::bytes() const {
  std::size_t b = 0;
  for (const auto& c : cols_)
    std::visit(
        [&](const auto& v) {
          b += v.capacity() * sizeof(typename std::decay_t<decltype(v)>::value_type);
        },
        c);
  return b;
}

std::optional<std::size_t> first_non_finite_grain(const ParticleStore& p) {
  const Vec3* x = p.x();
  const Vec3* v = p.v();
  const Vec3* w = p.omega();
  // (one pass summing 0 * each component: a sum that is NaN holds a NaN or an infinity)
  double probe = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    probe += 0.0 * (x[i].x + x[i].y + x[i].z + v[i].x + v[i].y + v[i].z + w[i].x + w[i].y + w[i].z);
  if (probe == 0.0) return std::nullopt;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (const Vec3* a : {x, v, w})
      if (!std::isfinite(a[i].x) || !std::isfinite(a[i].y) || !std::isfinite(a[i].z)) return i;
  return std::nullopt;  // (not reached)
}

}  // namespace gf
