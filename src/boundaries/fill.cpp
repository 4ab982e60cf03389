// SPDX-License-Identifier: GPL-3.0-or-later
// Lattice and random sequential-insertion fills.
#include "boundaries/fill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "core/error.hpp"

namespace gf {

double RadiusDistribution::sample(Rng& rng) const {
  switch (kind) {
    case Kind::Fixed:
      return value;
    case Kind::Uniform:
      return rng.uniform(min, max);
    case Kind::Normal:
      for (int k = 0; k < 100000; ++k) {
        const double r = rng.normal(mean, std);
        if (r >= min && r <= max) return r;
      }
      break;
    case Kind::Lognormal: {
      // Parameters of ln r from the mean and standard deviation of r.
      const double s2 = std::log(1 + (std * std) / (mean * mean));
      const double mu = std::log(mean) - 0.5 * s2;
      for (int k = 0; k < 100000; ++k) {
        const double r = std::exp(rng.normal(mu, std::sqrt(s2)));
        if (r >= min && r <= max) return r;
      }
      break;
    }
  }
  throw InputError("radius distribution: cut-offs leave (almost) no probability mass");
}

bool FillRegion::contains(const Vec3& p, double r, bool two_d) const {
  if (kind == Kind::Box) {
    for (int k = 0; k < (two_d ? 2 : 3); ++k)
      if (p[k] - r < min[k] || p[k] + r > max[k]) return false;
    return true;
  }
  const Vec3 d = p - center;
  if (two_d) return std::hypot(d.x, d.y) + r <= radius;  // a circle in the plane
  const double h = dot(d, axis);
  if (h - r < 0 || h + r > height) return false;
  return norm(d - h * axis) + r <= radius;
}

void FillRegion::bounds(Vec3& lo, Vec3& hi) const {
  if (kind == Kind::Box) {
    lo = min;
    hi = max;
    return;
  }
  for (int k = 0; k < 3; ++k) {
    // Extent of a disc of radius R normal to the axis, swept along the axis.
    const double e = radius * std::sqrt(std::max(0.0, 1 - axis[k] * axis[k]));
    const double a = center[k], b = center[k] + height * axis[k];
    lo[k] = std::min(a, b) - e;
    hi[k] = std::max(a, b) + e;
  }
}

namespace {

std::vector<FilledSphere> lattice_fill(const FillSpec& spec, const RadiusDistribution& rad,
                                       Rng& rng) {
  const double rmax = rad.largest();
  const Vec3 e = spec.extent.value_or(Vec3{rmax, rmax, rmax});
  const bool hcp = spec.lattice == FillSpec::Lattice::Hcp;
  const double emax = std::max({e.x, e.y, e.z});
  const double a = spec.spacing.value_or(2 * emax * 1.01);
  REQUIRE(a > 0, "lattice spacing must be positive");
  Vec3 lo, hi;
  spec.region.bounds(lo, hi);
  const std::int64_t cap = spec.count.value_or(std::numeric_limits<std::int64_t>::max());
  std::vector<Vec3> sites;
  // hcp: layers of a triangular lattice (row offset a/2, row pitch a sqrt(3)/2), ABAB stacking
  // with layer pitch a sqrt(2/3). cubic: pitch a, or 2 extent x 1.01 per axis by default.
  Vec3 pitch{a, hcp ? a * std::sqrt(3.0) / 2 : a, hcp ? a * std::sqrt(2.0 / 3.0) : a};
  if (!hcp && !spec.spacing) pitch = {2 * e.x * 1.01, 2 * e.y * 1.01, 2 * e.z * 1.01};
  const Vec3 m = hcp ? Vec3{emax, emax, emax} : e;  // margin to the region's bounds
  const Vec3 start = lo + Vec3{m.x, m.y, spec.two_d ? 0.0 : m.z};
  const double tol = 1e-12 * std::max({pitch.x, pitch.y, pitch.z});
  const std::int64_t want = spec.pick_random ? std::numeric_limits<std::int64_t>::max() : cap;
  for (int iz = 0; static_cast<std::int64_t>(sites.size()) < want; ++iz) {
    const double z = spec.two_d ? 0.0 : start.z + iz * pitch.z;
    if (spec.two_d ? iz > 0 : z + m.z > hi.z + tol) break;
    for (int iy = 0; static_cast<std::int64_t>(sites.size()) < want; ++iy) {
      double y = start.y + iy * pitch.y;
      if (hcp && (iz % 2)) y += a / (2 * std::sqrt(3.0));
      if (y + m.y > hi.y + tol) break;
      for (int ix = 0; static_cast<std::int64_t>(sites.size()) < want; ++ix) {
        double x = start.x + ix * pitch.x;
        if (hcp && (iy % 2)) x += a / 2;
        if (hcp && (iz % 2)) x += a / 2;
        if (x + m.x > hi.x + tol) break;
        const Vec3 p{x, y, z};
        if (!spec.region.contains(p, std::min({m.x, m.y, m.z}) * (1 - 1e-12), spec.two_d)) continue;
        sites.push_back(p);
      }
    }
  }
  if (spec.pick_random && static_cast<std::int64_t>(sites.size()) > cap) {
    // Partial Fisher-Yates: the first `cap` sites become a uniform random subset, then sorted
    // back into lattice order (neighbours stay close in memory).
    std::vector<std::size_t> idx(sites.size());
    for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = k;
    for (std::size_t k = 0; k < static_cast<std::size_t>(cap); ++k) {
      const auto left = static_cast<double>(idx.size() - k);
      const auto j =
          k + std::min(static_cast<std::size_t>(rng.uniform(0.0, left)), idx.size() - k - 1);
      std::swap(idx[k], idx[j]);
    }
    idx.resize(static_cast<std::size_t>(cap));
    std::sort(idx.begin(), idx.end());
    std::vector<Vec3> chosen;
    for (auto k : idx) chosen.push_back(sites[k]);
    sites.swap(chosen);
  }
  std::vector<FilledSphere> out;
  out.reserve(sites.size());
  for (const auto& p : sites) out.push_back({p, rad.sample(rng)});
  return out;
}

/// Hash grid of already placed spheres for the overlap test of random insertion.
class OverlapGrid {
 public:
  explicit OverlapGrid(double cell) : cell_(cell) {}
  void insert(const FilledSphere& s) {
    grid_[key(cell_index(s.x))].push_back(spheres_.size());
    spheres_.push_back(s);
  }
  bool overlaps(const Vec3& p, double r, double r_max) const {
    const auto c = cell_index(p);
    const int reach = static_cast<int>(std::ceil((r + r_max) / cell_));
    for (int dz = -reach; dz <= reach; ++dz)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          auto it = grid_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == grid_.end()) continue;
          for (std::size_t k : it->second) {
            const double d = r + spheres_[k].r;
            if (norm2(p - spheres_[k].x) < d * d) return true;
          }
        }
    return false;
  }

 private:
  std::array<std::int64_t, 3> cell_index(const Vec3& p) const {
    return {static_cast<std::int64_t>(std::floor(p.x / cell_)),
            static_cast<std::int64_t>(std::floor(p.y / cell_)),
            static_cast<std::int64_t>(std::floor(p.z / cell_))};
  }
  static std::int64_t key(const std::array<std::int64_t, 3>& c) {
    return (c[0] & 0x1fffff) | ((c[1] & 0x1fffff) << 21) | ((c[2] & 0x1fffff) << 42);
  }
  double cell_;
  std::vector<FilledSphere> spheres_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid_;
};

std::vector<FilledSphere> random_fill(const FillSpec& spec, const RadiusDistribution& rad, Rng& rng,
                                      const std::vector<FilledSphere>& existing) {
  REQUIRE(spec.count.has_value(), "a random fill needs a count");
  const std::int64_t target = *spec.count;
  const std::int64_t attempts =
      spec.max_attempts > 0 ? spec.max_attempts : 1000 * std::max<std::int64_t>(target, 1);
  double r_max = rad.largest();
  for (const auto& s : existing) r_max = std::max(r_max, s.r);
  OverlapGrid grid(2 * r_max);
  for (const auto& s : existing) grid.insert(s);
  Vec3 lo, hi;
  spec.region.bounds(lo, hi);
  std::vector<FilledSphere> out;
  std::int64_t tries = 0;
  while (static_cast<std::int64_t>(out.size()) < target && tries < attempts) {
    ++tries;
    const double r = rad.sample(rng);
    const Vec3 p{rng.uniform(lo.x + r, hi.x - r), rng.uniform(lo.y + r, hi.y - r),
                 spec.two_d ? 0.0 : rng.uniform(lo.z + r, hi.z - r)};
    if (!spec.region.contains(p, r, spec.two_d) || grid.overlaps(p, r, r_max)) continue;
    grid.insert({p, r});
    out.push_back({p, r});
  }
  if (static_cast<std::int64_t>(out.size()) < target)
    throw InputError(fmt::format(
        "random fill placed only {} of {} spheres in {} attempts: the region is too small "
        "for a loose random packing (enlarge it, reduce count, or use a lattice)",
        out.size(), target, attempts));
  return out;
}

}  // namespace

std::vector<FilledSphere> generate_fill(const FillSpec& spec, const RadiusDistribution& radius,
                                        Rng& rng, const std::vector<FilledSphere>& existing) {
  if (spec.lattice == FillSpec::Lattice::Random) return random_fill(spec, radius, rng, existing);
  return lattice_fill(spec, radius, rng);
}

}  // namespace gf
