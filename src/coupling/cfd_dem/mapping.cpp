// SPDX-License-Identifier: GPL-3.0-or-later
// Footprints of particles on the fluid grid, deterministic deposits and interpolation.
#include "coupling/cfd_dem/mapping.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/quaternion.hpp"
#include "coupling/cfd_dem/shape_factors.hpp"
#include "coupling/cfd_dem/stencil.hpp"
#include "particles/particle_store.hpp"

namespace gf::cfd_dem {

namespace {

constexpr int kShells = 3, kBands = 4, kSectors = 4;
constexpr int kSpherePoints = kShells * kBands * kSectors;
constexpr int kRings = 2, kDiskSectors = 4, kDiskPoints = kRings * kDiskSectors;
constexpr int kDiskVariants = 8;  // slab j uses variant j % 8 (turned sectors)
constexpr int kMaxSlabs = 64;
constexpr double kGolden = 0.6180339887498949;  // fractional turn between neighbouring layers

double frac(double v) {
  return v - std::floor(v);
}

/// Mean over [phi0, phi1] of (cos, sin): the azimuthal part of a sector's centroid.
Vec3 sector_mean(double phi0, double phi1) {
  const double d = phi1 - phi0;
  return {(std::sin(phi1) - std::sin(phi0)) / d, (std::cos(phi0) - std::cos(phi1)) / d, 0.0};
}

std::array<Vec3, kSpherePoints> make_sphere_points() {
  std::array<Vec3, kSpherePoints> pts{};
  // Antiderivative of sqrt(1 - mu^2): the in-plane radius of the unit sphere at height mu.
  auto ring = [](double mu) { return 0.5 * (mu * std::sqrt(1.0 - mu * mu) + std::asin(mu)); };
  int q = 0;
  for (int k = 0; k < kShells; ++k) {
    // Shells of equal volume: r^3 in [k/3, (k+1)/3]. Radial centroid: int r^3 dr / int r^2 dr.
    const double r0 = std::cbrt(double(k) / kShells), r1 = std::cbrt(double(k + 1) / kShells);
    const double rbar = 0.75 * (std::pow(r1, 4) - std::pow(r0, 4)) / (r1 * r1 * r1 - r0 * r0 * r0);
    for (int b = 0; b < kBands; ++b) {
      // Bands of equal area: mu = cos(theta) uniform in [-1, 1] (Archimedes).
      const double mu0 = -1.0 + 2.0 * b / kBands, mu1 = -1.0 + 2.0 * (b + 1) / kBands;
      const double zc = 0.5 * (mu0 + mu1);
      const double sc = (ring(mu1) - ring(mu0)) / (mu1 - mu0);
      const double off = frac((k * kBands + b) * kGolden);
      for (int s = 0; s < kSectors; ++s) {
        const double phi0 = 2.0 * kPi * (s + off) / kSectors;
        const Vec3 m = sector_mean(phi0, phi0 + 2.0 * kPi / kSectors);
        pts[q++] = rbar * Vec3{sc * m.x, sc * m.y, zc};
      }
    }
  }
  return pts;
}

using DiskSet = std::array<Vec3, kDiskPoints>;  // (x, y) on the unit disk, z = 0

std::array<DiskSet, kDiskVariants> make_disk_points() {
  std::array<DiskSet, kDiskVariants> out{};
  for (int v = 0; v < kDiskVariants; ++v) {
    int q = 0;
    for (int k = 0; k < kRings; ++k) {
      // Rings of equal area: rho^2 in [k/2, (k+1)/2]; centroid int rho^2 / int rho.
      const double r0 = std::sqrt(double(k) / kRings), r1 = std::sqrt(double(k + 1) / kRings);
      const double rbar = 2.0 / 3.0 * (r1 * r1 * r1 - r0 * r0 * r0) / (r1 * r1 - r0 * r0);
      const double off = frac((v * kRings + k) * kGolden);
      for (int s = 0; s < kDiskSectors; ++s) {
        const double phi0 = 2.0 * kPi * (s + off) / kDiskSectors;
        out[v][q++] = rbar * sector_mean(phi0, phi0 + 2.0 * kPi / kDiskSectors);
      }
    }
  }
  return out;
}

const std::array<Vec3, kSpherePoints>& sphere_points() {
  static const auto pts = make_sphere_points();
  return pts;
}

/// The set used for spheres: turned by a fixed rotation so that no two points share an x, y or
/// z coordinate (the bands of the construction share z). Chosen by a search over rotations for
/// the largest smallest gap between projections on the three axes: 0.0016 r (a sphere moving
/// along an axis by less than that moves at most one point across a face).
const std::array<Vec3, kSpherePoints>& sphere_points_turned() {
  static const auto pts = [] {
    auto q = sphere_points();
    const Quat turn = quat_from_axis_angle(normalized(Vec3{1.0, 0.7, 0.759}), 0.5);
    for (auto& v : q) v = rotate(turn, v);
    return q;
  }();
  return pts;
}

/// Order in which a slab's 8 thin sub-slabs take the disk points (ring * 4 + sector): each
/// next point on the other ring and a different sector, so that neighbours are far apart.
constexpr int kDiskOrder[kDiskPoints] = {0, 6, 2, 4, 1, 7, 3, 5};
const std::array<DiskSet, kDiskVariants>& disk_points() {
  static const auto pts = make_disk_points();
  return pts;
}

/// Orthonormal e1, e2 completing the unit vector u (Duff et al., J. Comput. Graph. Tech. 6
/// (2017) 1: branch on the sign of u.z only, continuous elsewhere).
void complete_basis(const Vec3& u, Vec3& e1, Vec3& e2) {
  const double sign = std::copysign(1.0, u.z);
  const double a = -1.0 / (sign + u.z);
  const double b = u.x * u.y * a;
  e1 = {1.0 + sign * u.x * u.x * a, sign * b, -sign * u.x};
  e2 = {b, sign + u.y * u.y * a, -u.y};
}

/// The time derivatives of complete_basis's e1, e2 for an axis u turning at du/dt (the same
/// branch on the sign of u.z).
void basis_rates(const Vec3& u, const Vec3& du, Vec3& de1, Vec3& de2) {
  const double sign = std::copysign(1.0, u.z);
  const double a = -1.0 / (sign + u.z);
  const double da = a * a * du.z;  // d/dt of -1 / (sign + u.z)
  const double db = (du.x * u.y + u.x * du.y) * a + u.x * u.y * da;
  de1 = {sign * (2.0 * u.x * du.x * a + u.x * u.x * da), sign * db, -sign * du.x};
  de2 = {db, 2.0 * u.y * du.y * a + u.y * u.y * da, -du.y};
}

constexpr std::size_t kBlock = 8192;  // particles per footprint block (> 4096: threaded)
constexpr std::int64_t kMinParallelShares = 1 << 15;

/// The cell of sample points within `reach` of a centre c: when reach is below the cell size
/// along every axis, a point lies in c's cell or a neighbour, found by comparing with the faces
/// of c's cell (cheaper than cell_containing's divisions, 48+ times per grain); otherwise, and
/// for points off the grid, the result is cell_containing's (folded: wrapped or clamped).
class NearCell {
 public:
  NearCell(const fluid::Grid& g, const Vec3& c, double reach) : g_(g) {
    near_ = true;
    for (int a = 0; a < 3; ++a) {
      i_[a] = g.cell_of(a, c[a]);
      lo_[a] = g.lo[a] + i_[a] * g.h[a];
      hi_[a] = lo_[a] + g.h[a];
      if (!(reach < g.h[a]) && (a < 2 || g.dimension == 3)) near_ = false;
    }
  }
  std::int64_t operator()(const Vec3& x) const {
    if (!near_) return cell_containing(g_, x);
    int d[3];
    for (int a = 0; a < 3; ++a)
      d[a] = static_cast<int>(x[a] >= hi_[a]) - static_cast<int>(x[a] < lo_[a]);
    return cell_at(d[0], d[1], d[2]);
  }
  /// Whether the face comparisons apply (reach below the cell size along every axis).
  [[nodiscard]] bool near() const { return near_; }
  [[nodiscard]] int dimension() const { return g_.dimension; }
  /// Lower and upper face of the centre's cell along axis a, m.
  [[nodiscard]] double lo(int a) const { return lo_[a]; }
  [[nodiscard]] double hi(int a) const { return hi_[a]; }
  /// The cell (folded: wrapped or clamped) at offsets d0, d1, d2 in {-1, 0, 1} from the
  /// centre's (z ignored on 2D grids).
  [[nodiscard]] std::int64_t cell_at(int d0, int d1, int d2) const {
    return g_.index(g_.fold(0, i_[0] + d0), g_.fold(1, i_[1] + d1),
                    g_.dimension == 2 ? 0 : g_.fold(2, i_[2] + d2));
  }

 private:
  const fluid::Grid& g_;
  int i_[3];
  double lo_[3], hi_[3];
  bool near_;
};

/// Adds scale * value(p) * w_pc to out[c] for every particle, deterministically (see header).
template <class T, class Value>
void deposit_footprints(const Footprints& fp, Value&& value, T* out) {
  const std::size_t n = fp.size();
  const std::int64_t n_cells = fp.n_cells;
  const std::int64_t* off = fp.offsets.data();
  const CellShare* shares = fp.shares.data();
  // Each part owns a contiguous range of cells and adds, in particle order, only what falls
  // into it: every cell sees the same sequence of additions for any number of parts. Small
  // deposits stay on one thread (a parallel region costs more than they do).
  const int n_parts = n == 0 || off[n] < kMinParallelShares ? 1 : std::max(1, exec::n_threads());
  exec::parallel_for_dynamic(n_parts, [&](exec::index_t part) {
    const std::int64_t c0 = n_cells * part / n_parts, c1 = n_cells * (part + 1) / n_parts;
    for (std::size_t i = 0; i < n; ++i) {
      const T v = value(i);
      for (std::int64_t s = off[i]; s < off[i + 1]; ++s) {
        const std::int64_t c = shares[s].cell;
        if (c >= c0 && c < c1) out[c] += shares[s].weight * v;
      }
    }
  });
}

/// Merges the pairs of one footprint that share a cell (weights summed, first-occurrence
/// order); returns the number left. A grain smaller than a cell touches at most 8 cells.
int compact_footprint(CellShare* f, int m) {
  int k = 0;
  for (int q = 0; q < m; ++q) {
    int j = 0;
    while (j < k && f[j].cell != f[q].cell) ++j;
    if (j == k)
      f[k++] = f[q];
    else
      f[j].weight += f[q].weight;
  }
  return k;
}

/// The turned sphere points ordered along one axis: s[k] the k-th smallest coordinate (padded
/// with +inf to 64), below[k] the bit set (bit = the point's index in the set) of the k
/// smallest. Since c + r s rounds monotonically in s for r > 0, the points of a sphere below a
/// plane x_a = t are always such a prefix, found by a binary search on c + r s[k] < t: the same
/// comparisons, bit for bit, as locating every point.
struct AxisOrder {
  std::array<double, 64> s;
  std::array<std::uint64_t, kSpherePoints + 1> below;
};

const std::array<AxisOrder, 3>& sphere_axis_orders() {
  static const auto orders = [] {
    std::array<AxisOrder, 3> o{};
    const auto& pts = sphere_points_turned();
    for (int a = 0; a < 3; ++a) {
      std::array<int, kSpherePoints> idx{};
      for (int q = 0; q < kSpherePoints; ++q) idx[q] = q;
      std::stable_sort(idx.begin(), idx.end(), [&](int x, int y) { return pts[x][a] < pts[y][a]; });
      o[a].s.fill(std::numeric_limits<double>::infinity());
      o[a].below[0] = 0;
      for (int k = 0; k < kSpherePoints; ++k) {
        o[a].s[k] = pts[idx[k]][a];
        o[a].below[k + 1] = o[a].below[k] | (std::uint64_t{1} << idx[k]);
      }
    }
    return o;
  }();
  return orders;
}

/// Bits set in x (SWAR: the baseline x86-64 build has no popcnt instruction, and the library
/// call GCC emits instead costs more than these dozen operations).
int popcount64(std::uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ULL);
  x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
  return static_cast<int>((x * 0x0101010101010101ULL) >> 56);
}

/// Number of sorted points k with c + r s[k] < t (branch-free binary search over 64 slots).
/// A face the sphere does not reach (most of them when grains are smaller than cells) is
/// settled by the first or last point alone: the same comparison the search would make there.
int count_below(const AxisOrder& o, double c, double r, double t) {
  if (!(c + r * o.s[0] < t)) return 0;
  if (c + r * o.s[kSpherePoints - 1] < t) return kSpherePoints;
  int k = 0;
  for (int step = 32; step > 0; step >>= 1) k += (c + r * o.s[k + step - 1] < t) ? step : 0;
  return k;
}

/// count / 48 for every count of sample points (a table instead of a division per cell).
const std::array<double, kSpherePoints + 1>& point_fractions() {
  static const auto table = [] {
    std::array<double, kSpherePoints + 1> t{};
    for (int q = 0; q <= kSpherePoints; ++q) t[q] = static_cast<double>(q) / kSpherePoints;
    return t;
  }();
  return table;
}

/// A sphere's divided footprint, compacted, when the face comparisons apply (else -1): the
/// same cells and point counts as footprint() followed by compact_footprint(), in ascending
/// neighbour order instead of first occurrence (the order within a footprint changes no
/// deposit: each cell occurs once), each weight the exact count / 48 instead of a running sum.
/// Along each axis the points below the cell's lower face and those below its upper face are
/// prefixes of the axis order (two binary searches); the points in neighbour cell (d0, d1, d2)
/// are the intersection of the three axes' bit sets, their number a popcount. Neighbours that
/// fold onto the same cell (a clamped wall layer, a periodic axis of one or two cells) are
/// merged. About 6x fewer instructions than locating 48 points one by one.
int sphere_footprint_binned(const NearCell& near, const Vec3& c, double r, CellShare* out) {
  if (!near.near()) return -1;
  constexpr std::uint64_t kAll = (std::uint64_t{1} << kSpherePoints) - 1;
  const auto& orders = sphere_axis_orders();
  const auto& fractions = point_fractions();
  const int dims = near.dimension() == 2 ? 2 : 3;
  std::uint64_t part[3][3];  // part[a][d]: points below (d = 0), inside (1), above (2) along a
  for (int a = 0; a < 3; ++a) {
    if (a >= dims) {
      part[a][0] = part[a][2] = 0;
      part[a][1] = kAll;
      continue;
    }
    const AxisOrder& o = orders[a];
    const std::uint64_t lo = o.below[count_below(o, c[a], r, near.lo(a))];
    const std::uint64_t hi = o.below[count_below(o, c[a], r, near.hi(a))];
    part[a][0] = lo;
    part[a][1] = hi & ~lo;
    part[a][2] = kAll & ~hi;
  }
  int m = 0;
  for (int d2 = 0; d2 < 3; ++d2) {
    if (part[2][d2] == 0) continue;
    for (int d1 = 0; d1 < 3; ++d1) {
      const std::uint64_t m12 = part[2][d2] & part[1][d1];
      if (m12 == 0) continue;
      for (int d0 = 0; d0 < 3; ++d0) {
        const std::uint64_t set = m12 & part[0][d0];
        if (set == 0) continue;
        const double w = fractions[popcount64(set)];
        const std::int64_t cell = near.cell_at(d0 - 1, d1 - 1, d2 - 1);
        int j = 0;
        while (j < m && out[j].cell != cell) ++j;
        if (j == m)
          out[m++] = {cell, w};
        else
          out[j].weight += w;
      }
    }
  }
  return m;
}

/// True when the divided footprint of particle i lies in one cell: its bounding box spans no
/// cell face (before folding, so a periodic image counts as another cell).
bool inside_one_cell(const fluid::Grid& g, const ParticleGeometry& p, std::size_t i) {
  const double r = p.radius[i], h = p.half(i);
  const Vec3 c = p.x[i];
  const Vec3 u = h > 0 ? p.axis[i] : Vec3{};
  const int dims = g.dimension == 2 ? 2 : 3;
  for (int a = 0; a < dims; ++a) {
    const double reach = r + h * std::abs(u[a]);
    if (g.cell_of(a, c[a] - reach) != g.cell_of(a, c[a] + reach)) return false;
  }
  return true;
}

template <class T>
void check_deposit_sizes(const Footprints& fp, std::size_t n_values, std::size_t n_cells) {
  REQUIRE(n_values == fp.size(), "deposit: {} values for {} particles", n_values, fp.size());
  REQUIRE(static_cast<std::int64_t>(n_cells) == fp.n_cells, "deposit: {} cell values for {} cells",
          n_cells, fp.n_cells);
}

}  // namespace

void check_geometry(const fluid::Grid& g, const ParticleGeometry& p) {
  const std::size_t n = p.size();
  REQUIRE(p.radius.size() == n, "particle geometry: {} radii for {} particles", p.radius.size(), n);
  REQUIRE(p.half_length.empty() || p.half_length.size() == n,
          "particle geometry: {} half lengths for {} particles", p.half_length.size(), n);
  REQUIRE(p.half_length.empty() || p.axis.size() == n,
          "particle geometry: {} axes for {} spherocylinders", p.axis.size(), n);
  REQUIRE(g.n[0] > 0 && g.n[1] > 0 && g.n[2] > 0 && g.h.x > 0 && g.h.y > 0 && g.h.z > 0,
          "fluid grid: cells {}x{}x{} of size {}x{}x{} m", g.n[0], g.n[1], g.n[2], g.h.x, g.h.y,
          g.h.z);
  const bool bad = exec::parallel_any(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    if (!(p.radius[i] > 0.0) || !(p.half(i) >= 0.0)) return true;
    if (p.half(i) > 0.0 && std::abs(norm2(p.axis[i]) - 1.0) > 1e-6) return true;
    return false;
  });
  REQUIRE(!bad,
          "particle geometry: a radius <= 0, a negative half length, or a spherocylinder "
          "axis that is not a unit vector");
}

double ParticleGeometry::volume(std::size_t i) const {
  return spherocylinder_volume(radius[i], 2.0 * half(i));
}

GrainShape grain_shape(const ParticleStore& s, std::size_t i) {
  if (!s.has_shapes()) return {s.radius()[i], 0.0, Vec3{0, 0, 1}};
  const bool rod = static_cast<ShapeCode>(s.shape()[i]) == ShapeCode::Spherocylinder;
  const double h = rod ? s.half_length()[i] : 0.0;
  // The store keeps the bounding radius r + l/2.
  return {s.radius()[i] - h, h, rotate(s.orientation()[i], Vec3{0, 0, 1})};
}

ParticleGeometry geometry_of(const ParticleStore& s, StoreGeometry& b) {
  const std::size_t n = s.size();
  ParticleGeometry p;
  p.x = std::span<const Vec3>(s.x(), n);
  if (!s.has_shapes()) {
    p.radius = std::span<const double>(s.radius(), n);
    return p;
  }
  b.radius.resize(n);
  b.half_length.resize(n);
  b.axis.resize(n);
  const bool other = exec::parallel_any(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    const auto code = static_cast<ShapeCode>(s.shape()[i]);
    return code != ShapeCode::Sphere && code != ShapeCode::Spherocylinder;
  });
  REQUIRE(!other,
          "CFD-DEM coupling supports spheres and spherocylinders only (found a disk or "
          "polygon grain)");
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    const GrainShape g = grain_shape(s, static_cast<std::size_t>(i));
    b.half_length[i] = g.half_length;
    b.radius[i] = g.radius;
    b.axis[i] = g.axis;
  });
  p.radius = b.radius;
  p.half_length = b.half_length;
  p.axis = b.axis;
  return p;
}

std::span<const Vec3> sphere_sample_points() {
  return sphere_points();
}

std::span<const Vec3> turned_sphere_sample_points() {
  return sphere_points_turned();
}

int cylinder_slabs(double r, double half_length) {
  if (!(half_length > 0.0)) return 0;
  const double n = std::ceil(2.0 * half_length / r);
  return n < 1 ? 1 : (n > kMaxSlabs ? kMaxSlabs : static_cast<int>(n));
}

namespace {

/// Calls f(x, w, l) for every sample point x of particle i's divided footprint with its share w
/// (the shares sum to 1) and, for a spherocylinder, its coordinates l in the frame (e1, e2, u)
/// of complete_basis: x = c + l.x e1 + l.y e2 + l.z u (spheres: l = 0).
template <class F>
void for_each_sample_point(const ParticleGeometry& p, std::size_t i, F&& f) {
  const Vec3 c = p.x[i];
  const double r = p.radius[i], h = p.half(i);
  const int n_slabs = cylinder_slabs(r, h);
  if (n_slabs == 0) {  // a sphere: the turned set in the world frame
    const double w = 1.0 / kSpherePoints;
    for (const Vec3& s : sphere_points_turned()) f(c + r * s, w, Vec3{0, 0, 0});
    return;
  }
  Vec3 e1, e2;
  const Vec3 u = p.axis[i];
  complete_basis(u, e1, e2);
  // Shares of the volume: the caps make one sphere, the cylinder pi r^2 l.
  const double v_sphere = 4.0 / 3.0 * kPi * r * r * r, v_cyl = kPi * r * r * 2.0 * h;
  const double v_total = v_sphere + v_cyl;
  const double w_sphere = v_sphere / kSpherePoints / v_total;
  for (const Vec3& s : sphere_points()) {   // in the rod's frame: bands split at the equator
    const double shift = s.z > 0 ? h : -h;  // the upper half of the set goes to the upper cap
    const Vec3 l{r * s.x, r * s.y, r * s.z + shift};
    f(c + l.x * e1 + l.y * e2 + l.z * u, w_sphere, l);
  }
  const double w_cyl = v_cyl / (n_slabs * kDiskPoints) / v_total;
  // Slab j is cut into 8 thin sub-slabs along the axis, one point each at the sub-slab's
  // mid-plane and at one of the 8 cross-section centroids: every point has its own axial
  // position (a rod moving along its axis moves one point at a time across a face) and each
  // slab still samples the whole cross-section.
  const double dz = 2.0 * h / (n_slabs * kDiskPoints);
  for (int j = 0; j < n_slabs; ++j) {
    const DiskSet& disk = disk_points()[j % kDiskVariants];
    for (int m = 0; m < kDiskPoints; ++m) {
      const Vec3& d = disk[kDiskOrder[m]];
      const double z = -h + (j * kDiskPoints + m + 0.5) * dz;
      const Vec3 l{r * d.x, r * d.y, z};
      f(c + l.x * e1 + l.y * e2 + l.z * u, w_cyl, l);
    }
  }
}

/// The block of unfolded cell indices along axis a that the trilinear stencils of points
/// within `reach` of coordinate c can touch: [base, base + extent), from floor(s) at c - reach
/// to floor(s) + 1 at c + reach (s the position in cells from centre 0). The points lie
/// strictly inside the reach (centroids of pieces of the body); positions far off the grid are
/// clamped (every index folds to the boundary there, and the conversion to int stays defined).
void smoothed_axis_block(const fluid::Grid& g, int a, double c, double reach, int& base,
                         int& extent) {
  const double lo = std::clamp((c - reach - g.lo[a]) / g.h[a] - 0.5, -1e9, 1e9);
  const double hi = std::clamp((c + reach - g.lo[a]) / g.h[a] - 0.5, -1e9, 1e9);
  base = static_cast<int>(std::floor(lo));
  extent = static_cast<int>(std::floor(hi)) + 2 - base;
}

/// Room for particle i's smoothed pairs: the product over the axes of its block's extent, at
/// most the axis' cell count (distinct cells after folding).
int smoothed_size_bound(const fluid::Grid& g, const ParticleGeometry& p, std::size_t i) {
  int total = 1;
  const int dims = g.dimension == 2 ? 2 : 3;
  for (int a = 0; a < dims; ++a) {
    int base = 0, extent = 0;
    smoothed_axis_block(g, a, p.x[i][a], p.radius[i] + p.half(i), base, extent);
    total *= std::min(extent, g.n[a]);
  }
  return total;
}

/// Adds weight w to cell c in the list out[0 .. m) (appending a new pair); returns the new m.
int add_share(CellShare* out, int m, std::int64_t c, double w) {
  for (int q = m - 1; q >= 0; --q)
    if (out[q].cell == c) {
      out[q].weight += w;
      return m;
    }
  out[m] = {c, w};
  return m + 1;
}

/// Accumulates one grain's smoothed shares (or their time derivatives) on the block of cells
/// its points' trilinear stencils can reach, indexed without folding (index floor(s) and
/// floor(s) + 1 along each axis, s the position in cells from centre 0); emit() folds the
/// indices onto the grid (wrapped across periodic faces, clamped at walls: a stencil beyond the
/// outermost centres then lands wholly in the boundary cell, as trilinear_stencil's does, and
/// its derivative cancels there) and merges the pairs that land in one cell.
class SmoothedBlock {
 public:
  /// copies: interleaved copies of the block (see add; 1 for a single point); sets: 2 to keep
  /// the weights and their rates side by side (add_both).
  SmoothedBlock(const fluid::Grid& g, const Vec3& c, double reach, std::size_t copies = 4,
                std::size_t sets = 1)
      : g_(g), copies_(copies) {
    dims_ = g.dimension == 2 ? 2 : 3;
    for (int a = 0; a < 3; ++a) {
      inv_h_[a] = 1.0 / g.h[a];
      if (a >= dims_) {
        base_[a] = 0;
        extent_[a] = 1;
        continue;
      }
      smoothed_axis_block(g, a, c[a], reach, base_[a], extent_[a]);
    }
    // One buffer per thread, kept: no allocation once it has grown to the largest grain.
    thread_local std::vector<double> storage;
    size_ = static_cast<std::size_t>(extent_[0]) * extent_[1] * extent_[2];
    storage.assign(sets * copies_ * size_, 0.0);
    acc_ = storage.data();
  }

  /// Adds w times point x's trilinear weights; with a velocity vx (rates), w times the rate of
  /// change of those weights, grad(weight) . vx.
  void add(const Vec3& x, double w, const Vec3* vx = nullptr) {
    if (vx)
      accumulate<kRates>(x, w, *vx);
    else
      accumulate<kWeights>(x, w, Vec3{0, 0, 0});
  }
  /// Both at once, in a block built with sets = 2: the weights into the first set, the rates
  /// into the second (each the same sums as add's).
  void add_both(const Vec3& x, double w, const Vec3& vx) { accumulate<kBoth>(x, w, vx); }

  /// Writes the non-zero sums of set `set` as (cell, value) pairs, one per cell; returns their
  /// number.
  int emit(CellShare* out, std::size_t set = 0) const {
    const double* acc = acc_ + set * copies_ * size_;
    int m = 0;
    for (int k = 0; k < extent_[2]; ++k)
      for (int j = 0; j < extent_[1]; ++j)
        for (int i = 0; i < extent_[0]; ++i) {
          const std::size_t at = index(i, j, k);
          double v = 0.0;
          for (std::size_t q = 0; q < copies_; ++q) v += acc[q * size_ + at];
          if (v == 0.0) continue;
          const std::int64_t cell = g_.index(g_.fold(0, base_[0] + i), g_.fold(1, base_[1] + j),
                                             dims_ == 3 ? g_.fold(2, base_[2] + k) : 0);
          m = add_share(out, m, cell, v);
        }
    return m;
  }

 private:
  enum Mode { kWeights, kRates, kBoth };

  template <Mode mode>
  void accumulate(const Vec3& x, double w, const Vec3& vx) {
    int i[3] = {0, 0, 0};
    double t[3] = {0, 0, 0}, dt[3] = {0, 0, 0};
    for (int a = 0; a < dims_; ++a) {
      // Clamped as in smoothed_axis_block; add() keeps the index inside the block anyway.
      const double s = std::clamp((x[a] - g_.lo[a]) * inv_h_[a] - 0.5, -1e9, 1e9);
      // floor(s) by truncation (std::floor is a library call without SSE4.1, three per point).
      int f = static_cast<int>(s);
      f -= static_cast<int>(s < f);
      i[a] = std::clamp(f - base_[a], 0, extent_[a] - 2);
      t[a] = s - f;
      if constexpr (mode != kWeights) dt[a] = vx[a] * inv_h_[a];
    }
    // Consecutive points mostly hit the same cells: adding them to interleaved copies of the
    // block breaks the chain of dependent additions.
    const std::size_t copy = (n_added_++ % copies_) * size_;
    const std::size_t second = copies_ * size_;  // the rates' set (kBoth)
    const int nk = dims_ == 3 ? 2 : 1;
    for (int c = 0; c < nk; ++c) {
      const double wk = dims_ == 3 ? (c ? t[2] : 1.0 - t[2]) : 1.0;
      const double dk = dims_ == 3 ? (c ? dt[2] : -dt[2]) : 0.0;
      for (int b = 0; b < 2; ++b) {
        const double wj = b ? t[1] : 1.0 - t[1], dj = b ? dt[1] : -dt[1];
        // The row's factors along y and z: the share a = w wj wk and its rate r = w d(wj wk)/dt;
        // a corner along x adds wi a and d(wi a)/dt = di a + wi r.
        const double a = w * (wj * wk);
        const double r = mode == kWeights ? 0.0 : w * (dj * wk + wj * dk);
        double* row = &acc_[copy + index(i[0], i[1] + b, i[2] + c)];
        for (int d = 0; d < 2; ++d) {
          const double wi = d ? t[0] : 1.0 - t[0], di = d ? dt[0] : -dt[0];
          if constexpr (mode == kWeights) {
            row[d] += wi * a;
          } else if constexpr (mode == kRates) {
            row[d] += di * a + wi * r;
          } else {
            row[d] += wi * a;
            row[second + d] += di * a + wi * r;
          }
        }
      }
    }
  }

  [[nodiscard]] std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * extent_[1] + j) * extent_[0] + i;
  }
  const fluid::Grid& g_;
  int dims_ = 3;
  int base_[3] = {0, 0, 0}, extent_[3] = {1, 1, 1};
  double inv_h_[3] = {1, 1, 1};
  std::size_t copies_ = 4, size_ = 0, n_added_ = 0;
  double* acc_ = nullptr;  // copies_ x extent_[0] x extent_[1] x extent_[2] sums, x fastest
};

/// Particle i's smoothed footprint, compacted, into out (room for smoothed_size_bound); returns
/// the number of pairs.
int smoothed_footprint(const fluid::Grid& g, const ParticleGeometry& p, std::size_t i,
                       CellShare* out) {
  SmoothedBlock block(g, p.x[i], p.radius[i] + p.half(i));
  for_each_sample_point(p, i, [&](const Vec3& x, double w, const Vec3&) { block.add(x, w); });
  return block.emit(out);
}

}  // namespace

int footprint_size(const fluid::Grid& g, const ParticleGeometry& p, std::size_t i,
                   DepositScheme scheme) {
  switch (scheme) {
    case DepositScheme::CentreInCell:
      return 1;
    case DepositScheme::Trilinear:
      return g.dimension == 2 ? 4 : 8;
    case DepositScheme::Divided:
      return kSpherePoints + kDiskPoints * cylinder_slabs(p.radius[i], p.half(i));
    case DepositScheme::Smoothed:
      return smoothed_size_bound(g, p, i);
  }
  return 0;
}

void footprint(const fluid::Grid& g, const ParticleGeometry& p, std::size_t i, DepositScheme scheme,
               CellShare* out) {
  const Vec3 c = p.x[i];
  if (scheme == DepositScheme::CentreInCell) {
    out[0] = {cell_containing(g, c), 1.0};
    return;
  }
  if (scheme == DepositScheme::Trilinear) {
    const CellStencil s = trilinear_stencil(g, c);
    for (int q = 0; q < s.n; ++q) out[q] = {s.cell[q], s.weight[q]};
    return;
  }
  if (scheme == DepositScheme::Smoothed) {
    // Compacted already; the rest of the room repeats the first cell with no weight.
    const int m = smoothed_footprint(g, p, i, out);
    const int size = footprint_size(g, p, i, scheme);
    for (int q = m; q < size; ++q) out[q] = {out[0].cell, 0.0};
    return;
  }
  const NearCell cell_of_point(g, c, p.radius[i] + p.half(i));
  int q = 0;
  for_each_sample_point(p, i, [&](const Vec3& x, double w, const Vec3&) {
    out[q++] = {cell_of_point(x), w};
  });
}

namespace {

/// Builds N footprint sets block by block, particle k's pairs of every set bounded by size(k):
/// fill(k, out) writes them (compacted: one per cell) to out[0..N) and returns their numbers.
template <std::size_t N, class Size, class Fill>
void build_footprint_sets(const fluid::Grid& g, const ParticleGeometry& p,
                          const std::array<Footprints*, N>& fps, Size&& size, Fill&& fill) {
  check_geometry(g, p);
  const std::size_t n = p.size();
  for (Footprints* fp : fps) {
    fp->n_cells = g.cell_count();
    fp->cell_volume = g.cell_volume();
    fp->offsets.resize(n + 1);
    fp->offsets[0] = 0;
    fp->volume.resize(n);
    fp->shares.clear();
  }
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t nb = std::min(kBlock, n - start);
    auto& off = fps[0]->raw_offsets;  // the bounds, shared by the sets
    off.resize(nb + 1);
    off[0] = 0;
    for (std::size_t i = 0; i < nb; ++i) off[i + 1] = off[i] + size(start + i);
    std::array<CellShare*, N> raw;
    for (std::size_t s = 0; s < N; ++s) {
      fps[s]->raw.resize(static_cast<std::size_t>(off[nb]));
      fps[s]->counts.resize(nb);
      raw[s] = fps[s]->raw.data();
    }
    exec::parallel_for(static_cast<exec::index_t>(nb), [&](exec::index_t i) {
      const std::size_t k = start + static_cast<std::size_t>(i);
      std::array<CellShare*, N> out;
      for (std::size_t s = 0; s < N; ++s) out[s] = raw[s] + off[i];
      const std::array<int, N> counts = fill(k, out);
      const double volume = p.volume(k);
      for (std::size_t s = 0; s < N; ++s) {
        fps[s]->volume[k] = volume;
        fps[s]->counts[i] = counts[s];
      }
    });
    // Compaction: offsets by a running sum, then one copy per particle into place (a vector
    // insert per particle cost more than the footprints of grains inside one cell).
    for (std::size_t s = 0; s < N; ++s) {
      Footprints& fp = *fps[s];
      for (std::size_t i = 0; i < nb; ++i)
        fp.offsets[start + i + 1] = fp.offsets[start + i] + fp.counts[i];
      fp.shares.resize(static_cast<std::size_t>(fp.offsets[start + nb]));
      CellShare* shares = fp.shares.data();
      const std::int64_t* dst = fp.offsets.data() + start;
      const CellShare* from = raw[s];
      exec::parallel_for(static_cast<exec::index_t>(nb), [&](exec::index_t i) {
        std::copy(from + off[i], from + off[i] + fp.counts[i], shares + dst[i]);
      });
    }
  }
}

/// A spherocylinder's divided footprint, compacted, when the face comparisons apply and no two
/// neighbour cells it touches fold onto one cell (else -1): the same pairs in the same order,
/// with the same sums, as footprint() followed by compact_footprint(). Each sample point is
/// binned by its neighbour offset (27 slots, summed in point order as the compaction sums them)
/// instead of being folded onto the grid and searched for among the pairs found so far.
int rod_footprint_binned(const NearCell& near, const ParticleGeometry& p, std::size_t i,
                         CellShare* out) {
  if (!near.near()) return -1;
  const bool flat = near.dimension() == 2;  // cell_at ignores z: one slot for all of it
  std::array<double, 27> sum;
  std::array<int, 27> order;
  std::uint32_t used = 0;
  int n = 0;
  const double lo0 = near.lo(0), hi0 = near.hi(0), lo1 = near.lo(1), hi1 = near.hi(1);
  const double lo2 = near.lo(2), hi2 = near.hi(2);
  for_each_sample_point(p, i, [&](const Vec3& x, double w, const Vec3&) {
    const int d0 = static_cast<int>(x.x >= hi0) - static_cast<int>(x.x < lo0);
    const int d1 = static_cast<int>(x.y >= hi1) - static_cast<int>(x.y < lo1);
    const int d2 = flat ? 0 : static_cast<int>(x.z >= hi2) - static_cast<int>(x.z < lo2);
    const int code = (d0 + 1) + 3 * (d1 + 1) + 9 * (d2 + 1);
    if (used & (std::uint32_t{1} << code)) {
      sum[code] += w;
    } else {
      used |= std::uint32_t{1} << code;
      sum[code] = w;
      order[n++] = code;
    }
  });
  for (int k = 0; k < n; ++k) {
    const int code = order[k];
    const std::int64_t cell = near.cell_at(code % 3 - 1, code / 3 % 3 - 1, code / 9 - 1);
    for (int j = 0; j < k; ++j)
      if (out[j].cell == cell) return -1;  // folded: the generic path sums such cells
    out[k] = {cell, sum[code]};
  }
  return n;
}

/// One footprint set: fill(k, out) writes particle k's pairs and returns their number.
template <class Size, class Fill>
void build_footprints(const fluid::Grid& g, const ParticleGeometry& p, Footprints& fp, Size&& size,
                      Fill&& fill) {
  build_footprint_sets<1>(g, p, {&fp}, size,
                          [&](std::size_t k, const std::array<CellShare*, 1>& out) {
                            return std::array<int, 1>{fill(k, out[0])};
                          });
}

/// The velocities of particle k's sample points, v + l.x de1/dt + l.y de2/dt + l.z du/dt for the
/// point at l in the frame (e1, e2, u): a sphere's points translate with it (they are fixed in
/// the world frame); a rod's follow its frame, which turns with the axis (the spin about it moves
/// none).
struct PointVelocity {
  Vec3 v, de1{0, 0, 0}, de2{0, 0, 0}, du{0, 0, 0};
  PointVelocity(const ParticleGeometry& p, std::size_t k, std::span<const Vec3> vel,
                std::span<const Vec3> omega)
      : v(vel[k]) {
    if (p.half(k) > 0 && !omega.empty()) {
      du = cross(omega[k], p.axis[k]);
      basis_rates(p.axis[k], du, de1, de2);
    }
  }
  Vec3 operator()(const Vec3& l) const { return v + l.x * de1 + l.y * de2 + l.z * du; }
};

void check_rate_inputs(const ParticleGeometry& p, DepositScheme scheme, std::span<const Vec3> v,
                       std::span<const Vec3> omega) {
  REQUIRE(has_time_derivative(scheme),
          "footprint rates: only the trilinear and smoothed deposits have a time derivative");
  REQUIRE(v.size() == p.size() && (omega.empty() || omega.size() == p.size()),
          "footprint rates: {} velocities and {} angular velocities for {} particles", v.size(),
          omega.size(), p.size());
}

}  // namespace

void compute_footprints(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                        Footprints& fp) {
  build_footprints(
      g, p, fp, [&](std::size_t k) { return footprint_size(g, p, k, scheme); },
      [&](std::size_t k, CellShare* f) {
        if (scheme == DepositScheme::Smoothed) return smoothed_footprint(g, p, k, f);
        if (scheme == DepositScheme::Divided) {
          // Binned where the face comparisons apply (one NearCell for either shape); a sphere
          // inside one cell comes out as the single pair (cell, 1) there too, a rod before it.
          const double r = p.radius[k], h = p.half(k);
          const NearCell near(g, p.x[k], r + h);
          const bool rod = h > 0.0;
          if (!rod) {
            const int m = sphere_footprint_binned(near, p.x[k], r, f);
            if (m > 0) return m;
          }
          if (inside_one_cell(g, p, k)) {
            f[0] = {cell_containing(g, p.x[k]), 1.0};
            return 1;
          }
          if (rod) {
            const int m = rod_footprint_binned(near, p, k, f);
            if (m > 0) return m;
          }
        }
        footprint(g, p, k, scheme, f);
        return compact_footprint(f, footprint_size(g, p, k, scheme));
      });
}

void footprint_rates(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                     std::span<const Vec3> v, std::span<const Vec3> omega, Footprints& rates) {
  check_rate_inputs(p, scheme, v, omega);
  if (scheme == DepositScheme::Trilinear) {  // one point, the centre, moving at v
    build_footprints(
        g, p, rates, [&](std::size_t) { return g.dimension == 2 ? 4 : 8; },
        [&](std::size_t k, CellShare* f) {
          SmoothedBlock block(g, p.x[k], 0.0, 1);
          block.add(p.x[k], 1.0, &v[k]);
          return block.emit(f);
        });
    return;
  }
  build_footprints(
      g, p, rates, [&](std::size_t k) { return smoothed_size_bound(g, p, k); },
      [&](std::size_t k, CellShare* f) {
        const PointVelocity velocity(p, k, v, omega);
        SmoothedBlock block(g, p.x[k], p.radius[k] + p.half(k));
        for_each_sample_point(p, k, [&](const Vec3& x, double w, const Vec3& l) {
          const Vec3 vs = velocity(l);
          block.add(x, w, &vs);
        });
        return block.emit(f);
      });
}

void footprints_with_rates(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                           std::span<const Vec3> v, std::span<const Vec3> omega, Footprints& fp,
                           Footprints& rates) {
  if (scheme == DepositScheme::Trilinear) {  // one point: nothing to share
    compute_footprints(g, p, scheme, fp);
    footprint_rates(g, p, scheme, v, omega, rates);  // (checks the inputs)
    return;
  }
  check_rate_inputs(p, scheme, v, omega);
  build_footprint_sets<2>(
      g, p, {&fp, &rates}, [&](std::size_t k) { return smoothed_size_bound(g, p, k); },
      [&](std::size_t k, const std::array<CellShare*, 2>& out) {
        const PointVelocity velocity(p, k, v, omega);
        SmoothedBlock block(g, p.x[k], p.radius[k] + p.half(k), 4, 2);
        for_each_sample_point(p, k, [&](const Vec3& x, double w, const Vec3& l) {
          block.add_both(x, w, velocity(l));
        });
        return std::array<int, 2>{block.emit(out[0], 0), block.emit(out[1], 1)};
      });
}

void deposit(const Footprints& fp, std::span<const double> value, std::span<double> per_cell,
             double scale) {
  check_deposit_sizes<double>(fp, value.size(), per_cell.size());
  deposit_footprints<double>(
      fp, [&](std::size_t i) { return scale * value[i]; }, per_cell.data());
}

void deposit(const Footprints& fp, std::span<const Vec3> value, std::span<Vec3> per_cell,
             double scale) {
  check_deposit_sizes<Vec3>(fp, value.size(), per_cell.size());
  deposit_footprints<Vec3>(
      fp, [&](std::size_t i) { return scale * value[i]; }, per_cell.data());
}

namespace {

/// Both deposit overloads that build their own footprints.
template <class T>
void deposit_values(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                    std::span<const T> value, std::span<T> per_cell, double scale,
                    DepositScratch* scratch) {
  Footprints local;
  Footprints& fp = scratch ? *scratch : local;
  compute_footprints(g, p, scheme, fp);
  deposit(fp, value, per_cell, scale);
}

}  // namespace

void deposit(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
             std::span<const double> value, std::span<double> per_cell, double scale,
             DepositScratch* scratch) {
  deposit_values<double>(g, p, scheme, value, per_cell, scale, scratch);
}

void deposit(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
             std::span<const Vec3> value, std::span<Vec3> per_cell, double scale,
             DepositScratch* scratch) {
  deposit_values<Vec3>(g, p, scheme, value, per_cell, scale, scratch);
}

void deposit_reaction_forces(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                             std::span<const Vec3> force, std::span<Vec3> cell_force,
                             DepositScratch* scratch) {
  deposit(g, p, scheme, force, cell_force, -1.0, scratch);
}

namespace {

/// K_c = sum_p w_pc beta_p / V_c and s_explicit_c = sum_p w_pc beta_p rel(p) / V_c.
template <class Rel>
void exchange_source(const Footprints& fp, std::span<const double> beta, std::size_t n_v, Rel&& rel,
                     std::span<Vec3> s_explicit, std::span<double> k) {
  REQUIRE(n_v == fp.size() && beta.size() == fp.size(),
          "drag exchange: {} velocities and {} beta for {} particles", n_v, beta.size(), fp.size());
  REQUIRE(static_cast<std::int64_t>(s_explicit.size()) == fp.n_cells,
          "drag exchange: {} source values for {} cells", s_explicit.size(), fp.n_cells);
  std::fill(s_explicit.begin(), s_explicit.end(), Vec3{});
  std::fill(k.begin(), k.end(), 0.0);
  const double inv_cell = 1.0 / fp.cell_volume;
  deposit(fp, beta, k, inv_cell);  // checks k's size
  deposit_footprints<Vec3>(
      fp, [&](std::size_t i) { return (inv_cell * beta[i]) * rel(i); }, s_explicit.data());
}

}  // namespace

void drag_exchange_source(const Footprints& fp, std::span<const double> beta,
                          std::span<const Vec3> v, std::span<Vec3> s_explicit,
                          std::span<double> k) {
  exchange_source(
      fp, beta, v.size(), [&](std::size_t i) { return v[i]; }, s_explicit, k);
}

void drag_exchange_source(const Footprints& fp, std::span<const double> beta,
                          std::span<const Vec3> v, std::span<const Vec3> u_seen,
                          std::span<const Vec3> cell_u, std::span<Vec3> s_explicit,
                          std::span<double> k) {
  REQUIRE(u_seen.size() == v.size(), "drag exchange: {} fluid velocities for {} particles",
          u_seen.size(), v.size());
  REQUIRE(static_cast<std::int64_t>(cell_u.size()) == fp.n_cells,
          "drag exchange: {} cell velocities for {} cells", cell_u.size(), fp.n_cells);
  exchange_source(
      fp, beta, v.size(), [&](std::size_t i) { return v[i] - u_seen[i]; }, s_explicit, k);
  exec::parallel_for(static_cast<exec::index_t>(fp.n_cells),
                     [&](exec::index_t c) { s_explicit[c] += k[c] * cell_u[c]; });
}

void drag_exchange_source(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                          std::span<const double> beta, std::span<const Vec3> v,
                          std::span<Vec3> s_explicit, std::span<double> k,
                          DepositScratch* scratch) {
  Footprints local;
  Footprints& fp = scratch ? *scratch : local;
  compute_footprints(g, p, scheme, fp);
  drag_exchange_source(fp, beta, v, s_explicit, k);
}

namespace {

template <class T>
void check_interpolation(const fluid::Grid& g, std::span<const T> field, std::size_t n_points,
                         std::size_t n_out) {
  REQUIRE(static_cast<std::int64_t>(field.size()) == g.cell_count(),
          "interpolate: {} cell values for {} cells", field.size(), g.cell_count());
  REQUIRE(n_out == n_points, "interpolate: {} outputs for {} points", n_out, n_points);
}

template <class T>
void interpolate_one(const fluid::Grid& g, std::span<const T> field, std::span<const Vec3> x,
                     std::span<T> out) {
  check_interpolation(g, field, x.size(), out.size());
  exec::parallel_for(static_cast<exec::index_t>(x.size()), [&](exec::index_t i) {
    out[i] = interpolate(lerp_stencil(g, x[i]), field.data());
  });
}

template <class A, class B>
void interpolate_two(const fluid::Grid& g, std::span<const LerpStencil> s,
                     std::span<const A> field_a, std::span<A> out_a, std::span<const B> field_b,
                     std::span<B> out_b) {
  check_interpolation(g, field_a, s.size(), out_a.size());
  check_interpolation(g, field_b, s.size(), out_b.size());
  exec::parallel_for(static_cast<exec::index_t>(s.size()), [&](exec::index_t i) {
    out_a[i] = interpolate(s[i], field_a.data());
    out_b[i] = interpolate(s[i], field_b.data());
  });
}

}  // namespace

void interpolate_to_points(const fluid::Grid& g, std::span<const double> field,
                           std::span<const Vec3> x, std::span<double> out) {
  interpolate_one(g, field, x, out);
}

void interpolate_to_points(const fluid::Grid& g, std::span<const Vec3> field,
                           std::span<const Vec3> x, std::span<Vec3> out) {
  interpolate_one(g, field, x, out);
}

void point_stencils(const fluid::Grid& g, std::span<const Vec3> x, std::span<LerpStencil> out,
                    PointRead read) {
  REQUIRE(out.size() == x.size(), "point stencils: {} outputs for {} points", out.size(), x.size());
  const auto n = static_cast<exec::index_t>(x.size());
  if (read == PointRead::CellValue)
    exec::parallel_for(n, [&](exec::index_t i) { out[i] = cell_value_stencil(g, x[i]); });
  else
    exec::parallel_for(n, [&](exec::index_t i) { out[i] = lerp_stencil(g, x[i]); });
}

void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const Vec3> field_a, std::span<Vec3> out_a,
                    std::span<const double> field_b, std::span<double> out_b) {
  interpolate_two(g, s, field_a, out_a, field_b, out_b);
}

void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const Vec3> field_a, std::span<Vec3> out_a,
                    std::span<const Vec3> field_b, std::span<Vec3> out_b) {
  interpolate_two(g, s, field_a, out_a, field_b, out_b);
}

void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const Vec3> field, std::span<Vec3> out) {
  check_interpolation(g, field, s.size(), out.size());
  exec::parallel_for(static_cast<exec::index_t>(s.size()),
                     [&](exec::index_t i) { out[i] = interpolate(s[i], field.data()); });
}

void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const double> field, std::span<double> out) {
  check_interpolation(g, field, s.size(), out.size());
  exec::parallel_for(static_cast<exec::index_t>(s.size()),
                     [&](exec::index_t i) { out[i] = interpolate(s[i], field.data()); });
}

}  // namespace gf::cfd_dem
