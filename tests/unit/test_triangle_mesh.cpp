// SPDX-License-Identifier: GPL-3.0-or-later
// Triangle-mesh walls (boundaries/triangle_mesh.hpp, their use in boundaries/wall.cpp) against
// oracles written here:
// - closest_on_triangle: the distance against a quad-precision brute force (the projection on
//   the plane when inside, else the closest point of the three edges) for random, obtuse, thin and
//   needle triangles, and the feature code consistent with the returned point; degenerate
//   (collinear, coincident-vertex) triangles against the closest point of their segments;
// - contact ownership: on flat meshed squares (2 triangles, an 8x8 grid, a fan) exactly one
//   contact, with the plane's gap and normal, also for centres exactly above shared edges and
//   vertices; on a cube, V-shaped valley, roof, bumpy height field and three fins sharing an edge
//   (non-manifold) the contacts are exactly the local minima of the distance from the centre to
//   the union of the triangles (found by brute force: a triangle's closest point is a local
//   minimum when no triangle that contains it has a point closer to the centre);
// - the grid: candidates() holds every triangle within the reach, in increasing order;
// - place(): vertices equal RigidMotion::point_at, bit-identical at rest, the grid follows;
// - the constructor: invalid input refused, boundary and non-manifold edge counts;
// - through WallContactList and compute_wall_forces: a sphere on a meshed floor feels the force
//   it feels on a plane floor, pressed at rest and sliding across triangle edges (the tangential
//   history carried from triangle to triangle), and in a meshed V-shaped valley the force of two
//   planes.
// Several tests guard bugs found by them in the first version (named "Regression" in their
// comment): degenerate and very thin triangles in closest_on_triangle, zero-area slivers and
// near-ties in the contact ownership, and the history of two contacts moving at once going to
// the wrong contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "boundaries/motion.hpp"
#include "boundaries/triangle_mesh.hpp"
#include "boundaries/wall.hpp"
#include "contact/pair_forces.hpp"
#include "contact/registry.hpp"

using namespace gf;

namespace {

using Tri = std::array<int, 3>;

// ---------------------------------------------------------------------------------------------
// Brute-force closest points, in a wider floating-point type S (long double, or quad precision
// for the closest_on_triangle test, where thin triangles make the plane's normal ill-conditioned).

__extension__ typedef __float128 Quad;
using LD = long double;

template <class S>
struct P3 {
  S x = 0, y = 0, z = 0;
};
template <class S>
P3<S> wide(const Vec3& a) {
  return {S(a.x), S(a.y), S(a.z)};
}
template <class S>
P3<S> operator-(const P3<S>& a, const P3<S>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class S>
P3<S> operator+(const P3<S>& a, const P3<S>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class S>
P3<S> operator*(S s, const P3<S>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class S>
S dot3(const P3<S>& a, const P3<S>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class S>
P3<S> cross3(const P3<S>& a, const P3<S>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class S>
S dist2(const P3<S>& a, const P3<S>& b) {
  const P3<S> d = a - b;
  return dot3(d, d);
}

/// Closest point of the segment [a, b] to p (a when a == b).
template <class S>
P3<S> segment_closest(const P3<S>& p, const P3<S>& a, const P3<S>& b) {
  const P3<S> ab = b - a;
  const S l2 = dot3(ab, ab);
  S s = l2 > 0 ? dot3(p - a, ab) / l2 : S(0);
  s = s < 0 ? S(0) : (s > 1 ? S(1) : s);
  return a + s * ab;
}

/// Closest point of the triangle (a, b, c) to p: the projection of p on the plane when it lies
/// inside (the three sub-triangles with p's projection turn as the triangle does), else the
/// closest of the three edges' closest points. Degenerate triangles: their edges.
template <class S>
P3<S> triangle_closest(const P3<S>& p, const P3<S>& a, const P3<S>& b, const P3<S>& c) {
  P3<S> best = segment_closest(p, a, b);
  for (const P3<S>& q : {segment_closest(p, b, c), segment_closest(p, c, a)})
    if (dist2(p, q) < dist2(p, best)) best = q;
  const P3<S> n = cross3(b - a, c - a);
  const S nn = dot3(n, n);
  if (nn > 0 && dot3(cross3(b - a, p - a), n) >= 0 && dot3(cross3(c - b, p - b), n) >= 0 &&
      dot3(cross3(a - c, p - c), n) >= 0) {
    const P3<S> q = p - (dot3(p - a, n) / nn) * n;
    if (dist2(p, q) < dist2(p, best)) best = q;
  }
  return best;
}

double to_double(Quad q) {
  return static_cast<double>(q);
}

// ---------------------------------------------------------------------------------------------
// Meshes.

/// The square [0, 1]^2 at height z split into n x n squares, each into two triangles; `alternate`:
/// the diagonal of square (i, j) joins (i, j)-(i+1, j+1) when i + j is even and (i+1, j)-(i, j+1)
/// otherwise (vertices of 4 and 8 triangles), else always the former.
TriangleMesh square_grid(int n, bool alternate, double z = 0) {
  std::vector<Vec3> pts;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) pts.push_back({double(i) / n, double(j) / n, z});
  std::vector<Tri> tris;
  const auto id = [n](int i, int j) { return i + (n + 1) * j; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v00 = id(i, j), v10 = id(i + 1, j), v11 = id(i + 1, j + 1), v01 = id(i, j + 1);
      if (alternate && (i + j) % 2 == 1) {
        tris.push_back({v00, v10, v01});
        tris.push_back({v10, v11, v01});
      } else {
        tris.push_back({v00, v10, v11});
        tris.push_back({v00, v11, v01});
      }
    }
  return TriangleMesh(pts, tris);
}

/// The square [0, 1]^2 at z = 0 as a fan of 8 triangles around (0.5, 0.5).
TriangleMesh square_fan() {
  std::vector<Vec3> pts{{0.5, 0.5, 0}, {0, 0, 0},   {0.5, 0, 0}, {1, 0, 0},  {1, 0.5, 0},
                        {1, 1, 0},     {0.5, 1, 0}, {0, 1, 0},   {0, 0.5, 0}};
  std::vector<Tri> tris;
  for (int k = 0; k < 8; ++k) tris.push_back({0, 1 + k, 1 + (k + 1) % 8});
  return TriangleMesh(pts, tris);
}

/// The cube [0, 1]^3, 12 triangles (orientations mixed).
TriangleMesh unit_cube() {
  std::vector<Vec3> pts;
  for (int v = 0; v < 8; ++v) pts.push_back({double(v & 1), double((v >> 1) & 1), double(v >> 2)});
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  std::vector<Tri> tris;
  for (const auto& q : quads) {
    tris.push_back({q[0], q[1], q[2]});
    tris.push_back({q[0], q[2], q[3]});
  }
  return TriangleMesh(pts, tris);
}

/// Two strips along x in [0, 1] meeting at the line y = 0, z = 0: the left one up to (y, z) =
/// (-1, slope), the right one up to (1, slope) (slope > 0: a valley; < 0: a roof, ridge on top).
TriangleMesh two_strips(double slope) {
  std::vector<Vec3> pts{{0, -1, slope}, {1, -1, slope}, {0, 0, 0},
                        {1, 0, 0},      {0, 1, slope},  {1, 1, slope}};
  std::vector<Tri> tris{{0, 1, 3}, {0, 3, 2}, {2, 3, 5}, {2, 5, 4}};
  return TriangleMesh(pts, tris);
}

/// Three fins (unit squares) sharing the edge x in [0, 1], y = z = 0 (a non-manifold edge), at
/// angles 90, 210 and 330 degrees about it.
TriangleMesh three_fins() {
  std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}};
  std::vector<Tri> tris;
  for (int f = 0; f < 3; ++f) {
    const double a = (90.0 + 120.0 * f) * M_PI / 180;
    const Vec3 d{0, std::cos(a), std::sin(a)};
    pts.push_back(Vec3{0, 0, 0} + d);
    pts.push_back(Vec3{1, 0, 0} + d);
    const int p0 = 2 + 2 * f, p1 = p0 + 1;
    tris.push_back({0, 1, p1});  // the first triangle of each fin holds the shared edge
    tris.push_back({0, p1, p0});
  }
  return TriangleMesh(pts, tris);
}

/// Height field on [0, 1]^2, n x n squares, random heights in [0, amp).
TriangleMesh bumpy(int n, double amp, unsigned seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> pts;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) pts.push_back({double(i) / n, double(j) / n, amp * u(g)});
  std::vector<Tri> tris;
  const auto id = [n](int i, int j) { return i + (n + 1) * j; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return TriangleMesh(pts, tris);
}

/// Latitude-longitude sphere of radius `rad` about c (poles as single vertices).
TriangleMesh uv_sphere(const Vec3& c, double rad, int n_lat, int n_lon) {
  std::vector<Vec3> pts{c + Vec3{0, 0, rad}};
  for (int a = 1; a < n_lat; ++a)
    for (int b = 0; b < n_lon; ++b) {
      const double th = M_PI * a / n_lat, ph = 2 * M_PI * b / n_lon;
      pts.push_back(
          c + rad * Vec3{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
  pts.push_back(c + Vec3{0, 0, -rad});
  const int south = static_cast<int>(pts.size()) - 1;
  const auto ring = [n_lon](int a, int b) { return 1 + (a - 1) * n_lon + (b % n_lon); };
  std::vector<Tri> tris;
  for (int b = 0; b < n_lon; ++b) {
    tris.push_back({0, ring(1, b), ring(1, b + 1)});
    tris.push_back({south, ring(n_lat - 1, b + 1), ring(n_lat - 1, b)});
  }
  for (int a = 1; a + 1 < n_lat; ++a)
    for (int b = 0; b < n_lon; ++b) {
      tris.push_back({ring(a, b), ring(a + 1, b), ring(a + 1, b + 1)});
      tris.push_back({ring(a, b), ring(a + 1, b + 1), ring(a, b + 1)});
    }
  return TriangleMesh(pts, tris);
}

// ---------------------------------------------------------------------------------------------
// Contacts of the code under test, and the brute-force local minima.

struct Contact {
  int tri;
  Vec3 normal;
  double gap;
};

/// sphere_contact over every triangle of the mesh.
std::vector<Contact> all_contacts(const TriangleMesh& m, const Vec3& x, double r) {
  std::vector<Contact> out;
  for (std::size_t t = 0; t < m.size(); ++t) {
    Contact c{static_cast<int>(t), {}, 0};
    if (m.sphere_contact(static_cast<std::int32_t>(t), x, r, c.normal, c.gap)) out.push_back(c);
  }
  return out;
}

P3<LD> corner(const TriangleMesh& m, std::size_t t, int k) {
  return wide<LD>(
      m.points()[static_cast<std::size_t>(m.triangles()[t][static_cast<std::size_t>(k)])]);
}

struct Minimum {
  P3<LD> q;
  LD d2;
};

/// Local minima of the distance from x to the union of the triangles, closer than r: a triangle's
/// closest point q is one unless a triangle that contains q has a point strictly closer to x.
/// Minima at the same point (shared by several triangles) are listed once.
std::vector<Minimum> oracle_minima(const TriangleMesh& m, const Vec3& x, double r) {
  const std::size_t n = m.size();
  const P3<LD> xl = wide<LD>(x);
  std::vector<P3<LD>> q(n);
  std::vector<LD> d2(n);
  for (std::size_t t = 0; t < n; ++t) {
    q[t] = triangle_closest(xl, corner(m, t, 0), corner(m, t, 1), corner(m, t, 2));
    d2[t] = dist2(xl, q[t]);
  }
  std::vector<Minimum> out;
  const LD on_tol2 = 1e-24L;  // q lies on a triangle: within 1e-12
  for (std::size_t t = 0; t < n; ++t) {
    if (!(d2[t] < LD(r) * LD(r))) continue;
    bool local = true;
    for (std::size_t u = 0; u < n && local; ++u) {
      if (u == t) continue;
      const P3<LD> qu = triangle_closest(q[t], corner(m, u, 0), corner(m, u, 1), corner(m, u, 2));
      if (dist2(qu, q[t]) > on_tol2) continue;
      if (d2[u] < d2[t] * (1 - 1e-12L)) local = false;
    }
    if (!local) continue;
    bool seen = false;
    for (const auto& mm : out) seen = seen || dist2(mm.q, q[t]) < 1e-18L;
    if (!seen) out.push_back({q[t], d2[t]});
  }
  return out;
}

std::string describe(const Vec3& x, double r) {
  std::ostringstream s;
  s.precision(17);
  s << "centre (" << x.x << ", " << x.y << ", " << x.z << "), r " << r;
  return s.str();
}

std::string describe(const std::vector<Contact>& cs) {
  std::ostringstream s;
  s.precision(17);
  s << cs.size() << " contact(s):";
  for (const auto& c : cs)
    s << " [tri " << c.tri << " n (" << c.normal.x << ", " << c.normal.y << ", " << c.normal.z
      << ") gap " << c.gap << "]";
  return s.str();
}

/// Empty when the contacts of the code are the oracle's local minima, one each, with the same
/// point (1e-9), gap (1e-12) and a unit normal; else what differs.
std::string oracle_mismatch(const TriangleMesh& m, const Vec3& x, double r) {
  const auto got = all_contacts(m, x, r);
  const auto want = oracle_minima(m, x, r);
  bool ok = got.size() == want.size();
  for (const auto& w : want) {
    int matches = 0;
    for (const auto& c : got) {
      const P3<LD> point = wide<LD>(x - (c.gap + r) * c.normal);
      const double want_gap = static_cast<double>(std::sqrt(w.d2)) - r;
      if (dist2(point, w.q) < 1e-18L && std::abs(c.gap - want_gap) < 1e-12 &&
          std::abs(norm(c.normal) - 1) < 1e-12)
        ++matches;
    }
    ok = ok && matches == 1;
  }
  if (ok) return {};
  std::ostringstream s;
  s.precision(17);
  s << describe(x, r) << ": " << describe(got) << "; expected " << want.size() << " minima:";
  for (const auto& w : want)
    s << " [q (" << double(w.q.x) << ", " << double(w.q.y) << ", " << double(w.q.z) << ") dist "
      << double(std::sqrt(w.d2)) << "]";
  return s.str();
}

/// Runs oracle_mismatch at every centre; expects no mismatch and reports the first.
void expect_oracle(const TriangleMesh& m, const std::vector<std::pair<Vec3, double>>& spheres,
                   const char* what) {
  int failures = 0;
  std::string first;
  for (const auto& [x, r] : spheres) {
    const std::string s = oracle_mismatch(m, x, r);
    if (!s.empty() && failures++ == 0) first = s;
  }
  EXPECT_EQ(failures, 0) << what << " (of " << spheres.size() << "), first: " << first;
}

/// Random multiple of 2^-20 in [a, b): exact sums and differences with the grid's coordinates.
double dyadic(std::mt19937_64& g, double a, double b) {
  std::uniform_real_distribution<double> u(a, b);
  return std::ldexp(std::floor(std::ldexp(u(g), 20)), -20);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 1. closest_on_triangle.

namespace {

struct ClosestStats {
  int n = 0, failures = 0;
  double worst_rel = 0, worst_abs = 0;  // error / distance, error / size
  std::string first;
};

/// closest_on_triangle at p against the quad-precision oracle: the distance within
/// rel * distance + abs_tol * size, and the returned point on the returned feature.
void check_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double rel,
                   ClosestStats& st, double abs_tol = 1e-15) {
  Vec3 q;
  const TriangleFeature f = closest_on_triangle(p, a, b, c, q);
  const P3<Quad> pq = wide<Quad>(p), aq = wide<Quad>(a), bq = wide<Quad>(b), cq = wide<Quad>(c);
  const P3<Quad> best = triangle_closest(pq, aq, bq, cq);
  const double d_want = std::sqrt(to_double(dist2(pq, best)));
  const double d_got = std::sqrt(to_double(dist2(pq, wide<Quad>(q))));
  const double size = std::max({norm(b - a), norm(c - b), norm(a - c)});
  const double err = std::abs(d_got - d_want);
  ++st.n;
  st.worst_rel = std::max(st.worst_rel, err / std::max(d_want, 1e-300));
  st.worst_abs = std::max(st.worst_abs, err / size);
  bool ok = err <= rel * d_want + abs_tol * size;
  // The feature: the point lies on it.
  const Vec3 v[3] = {a, b, c};
  const double on = 1e-14 * size;
  if (f == TriangleFeature::Face) {
    const P3<Quad> in = triangle_closest(wide<Quad>(q), aq, bq, cq);
    ok = ok && std::sqrt(to_double(dist2(in, wide<Quad>(q)))) <= on;
  } else if (f <= TriangleFeature::Edge2) {
    const int k = static_cast<int>(f) - static_cast<int>(TriangleFeature::Edge0);
    const P3<Quad> s = segment_closest(wide<Quad>(q), wide<Quad>(v[k]), wide<Quad>(v[(k + 1) % 3]));
    ok = ok && std::sqrt(to_double(dist2(s, wide<Quad>(q)))) <= on;
  } else {
    const int k = static_cast<int>(f) - static_cast<int>(TriangleFeature::Vertex0);
    ok = ok && q == v[k];
  }
  if (!ok && st.failures++ == 0) {
    std::ostringstream s;
    s.precision(17);
    s << "p (" << p.x << ", " << p.y << ", " << p.z << ") a (" << a.x << ", " << a.y << ", " << a.z
      << ") b (" << b.x << ", " << b.y << ", " << b.z << ") c (" << c.x << ", " << c.y << ", "
      << c.z << "): feature " << static_cast<int>(f) << " q (" << q.x << ", " << q.y << ", " << q.z
      << ") distance " << d_got << ", brute force " << d_want;
    st.first = s.str();
  }
}

Vec3 random_unit(std::mt19937_64& g) {
  std::normal_distribution<double> nd(0, 1);
  const Vec3 v{nd(g), nd(g), nd(g)};
  return normalized(v);
}

}  // namespace

// Random triangles (all shapes, obtuse ones included) and points around them, near their plane
// and far: the distance to 1e-12, the feature holding the point.
TEST(ClosestOnTriangle, MatchesBruteForceOnRandomAndObtuseTriangles) {
  std::mt19937_64 g(1);
  std::uniform_real_distribution<double> u(-1, 1);
  ClosestStats st;
  for (int t = 0; t < 1000; ++t) {
    Vec3 a{u(g), u(g), u(g)}, b{u(g), u(g), u(g)}, c{u(g), u(g), u(g)};
    if (t % 4 == 1) c = 0.5 * (a + b) + 0.05 * random_unit(g);  // very obtuse at c
    if (t % 4 == 2) {                                           // obtuse at a, tilted
      b = a + Vec3{1, 0.1, 0};
      c = a + Vec3{-0.8, 0.3, 0.2};
    }
    const Vec3 o = (1.0 / 3) * (a + b + c);
    const Vec3 n = normalized(cross(b - a, c - a));
    for (int k = 0; k < 10; ++k) {
      Vec3 p = o + 1.5 * Vec3{u(g), u(g), u(g)};
      if (k % 3 == 0) p = p - (dot(p - o, n) - 1e-3 * u(g)) * n;  // close to the plane
      check_closest(p, a, b, c, 1e-12, st);
    }
    // Points projecting on the vertices and on the middle of the edges.
    for (const Vec3& s : {a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)})
      check_closest(s + 0.3 * u(g) * n, a, b, c, 1e-12, st);
  }
  EXPECT_EQ(st.failures, 0) << "of " << st.n << ", worst relative error " << st.worst_rel
                            << ", first: " << st.first;
}

namespace {

/// Thin triangles (height h = 10^-e of their length, e in [e_lo, e_hi]) and needles (two vertices
/// `needle` apart, times the length), points around them and points over their face; the
/// distance within 1e-12 of itself plus abs_tol times the triangle's size.
void thin_sweep(double e_lo, double e_hi, double needle, double abs_tol, unsigned seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-1, 1), s01(0, 1);
  ClosestStats st[2][2];  // [thin, needle][points around, points over the face]
  for (int t = 0; t < 1000; ++t) {
    const Vec3 a{u(g), u(g), u(g)};
    const Vec3 e = random_unit(g);
    const double len = 0.5 + s01(g);
    const Vec3 b = a + len * e;
    Vec3 perp = random_unit(g);
    perp = normalized(perp - dot(perp, e) * e);
    const double h = len * std::pow(10.0, -(e_lo + (e_hi - e_lo) * s01(g)));
    Vec3 c = a + (-0.2 + 1.4 * s01(g)) * (b - a) + h * perp;  // thin, obtuse when outside [0, 1]
    const int kind = t % 3 == 0;
    if (kind == 1) c = b + needle * len * random_unit(g);  // needle
    const Vec3 o = (1.0 / 3) * (a + b + c);
    for (int k = 0; k < 10; ++k)
      check_closest(o + Vec3{u(g), u(g), u(g)}, a, b, c, 1e-12, st[kind][0], abs_tol);
    // Points projecting inside the triangle (its face region), or just outside.
    const Vec3 n = normalized(cross(b - a, c - a));
    for (int k = 0; k < 10; ++k) {
      double s = s01(g), t_ = s01(g);
      if (s + t_ > 1) {
        s = 1 - s;
        t_ = 1 - t_;
      }
      const Vec3 in = a + s * (b - a) + t_ * (c - a) + (k % 2 ? 1e-3 : 0.5) * u(g) * n;
      check_closest(in + 0.01 * h * u(g) * perp, a, b, c, 1e-12, st[kind][1], abs_tol);
    }
  }
  const char* names[2][2] = {{"thin, points around", "thin, points over the face"},
                             {"needle, points around", "needle, points over the face"}};
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l)
      EXPECT_EQ(st[k][l].failures, 0)
          << names[k][l] << ", of " << st[k][l].n << ", worst error / distance "
          << st[k][l].worst_rel << ", worst error / size " << st[k][l].worst_abs
          << ", first: " << st[k][l].first;
}

}  // namespace

// Thin triangles, height 1e-2 to 1e-3 of their length, and needles 1e-3 wide: the distance
// within 1e-12 of itself plus 1e-14 of the size (rounding of the returned point).
TEST(ClosestOnTriangle, MatchesBruteForceOnThinTriangles) {
  thin_sweep(2, 3, 1e-3, 1e-14, 2);
}

// Very thin triangles, height 1e-5 to 1e-7 of their length, and needles 1e-6 wide. The distance
// is as well conditioned as for any triangle (1-Lipschitz in the vertices: projecting on the plane
// of the cross product's normal and testing the sub-triangles' orientation gives it to rounding),
// so 1e-13 of the size is asked. Regression (first version): closest_on_triangle's unscaled area
// coordinates (vc = d1 d4 - d3 d2, ...) are differences of products of size L^4 whose sum is |ab x
// ac|^2 ~ L^4 (h / L)^2; they cancel, and the point returned for the face region is off along the
// triangle. Measured distance errors, in units of the size, for points over the face: 3e-13 at
// h / L = 1e-4, 6e-10 at 1e-5, 1e-6 at 1e-6, 2e-3 at 1e-7.
TEST(ClosestOnTriangle, VeryThinTrianglesKeepTheirAccuracy) {
  thin_sweep(5, 7, 1e-6, 1e-13, 18);
}

// Degenerate triangles: three collinear vertices (collinear as computed: a, a + 0.375 (b - a), b
// and a, b, a + 2 (b - a)), and each pair of coincident vertices. The closest point is that of
// the union of the segments (the header: "Degenerate triangles are handled (their closest point
// lies on an edge or a vertex)"). Regression (first version): collinear: the area coordinates va,
// vb, vc are rounding noise whose sum can be positive, which passes the `!(sum > 0)` guard and
// returns Face with a point elsewhere on the line (91 of 6000 here, distance up to 68 % too large);
// a == b: the Edge0 branch is taken with s = 0 (d1 = d3 = 0, vc = 0) and returns vertex a whatever
// p (2376 of 3000). (A TriangleMesh merges such vertices and refuses the triangle; the function is
// public, and the collinear case reaches meshes: FlatRectangleWithSliverTriangleOneContact.)
TEST(ClosestOnTriangle, DegenerateTrianglesGiveTheClosestPointOfTheirSegments) {
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> u(-1, 1);
  ClosestStats collinear, coincident[3];
  for (int t = 0; t < 300; ++t) {
    const Vec3 a{u(g), u(g), u(g)}, b{u(g), u(g), u(g)};
    const Vec3 m = a + 0.375 * (b - a);
    for (int k = 0; k < 10; ++k) {
      const Vec3 p = m + Vec3{u(g), u(g), u(g)};
      check_closest(p, a, b, a + 2.0 * (b - a), 1e-12, collinear);
      check_closest(p, a, m, b, 1e-12, collinear);
      check_closest(p, a, a, b, 1e-12, coincident[0]);  // vertex 0 = vertex 1
      check_closest(p, a, b, b, 1e-12, coincident[1]);  // vertex 1 = vertex 2
      check_closest(p, a, b, a, 1e-12, coincident[2]);  // vertex 2 = vertex 0
    }
  }
  EXPECT_EQ(collinear.failures, 0)
      << "collinear, of " << collinear.n << ", first: " << collinear.first;
  const char* names[3] = {"a == b", "b == c", "c == a"};
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(coincident[k].failures, 0)
        << names[k] << ", of " << coincident[k].n << ", first: " << coincident[k].first;
}

// The simplest case of the a == b failure above. Regression (first version): q = (0, 0, 0) both
// times.
TEST(ClosestOnTriangle, FirstTwoVerticesCoincident) {
  const Vec3 a{0, 0, 0}, c{1, 0, 0};
  Vec3 q;
  closest_on_triangle({1, 1, 0}, a, a, c, q);  // closest point (1, 0, 0), distance 1
  EXPECT_NEAR(norm(q - Vec3{1, 0, 0}), 0, 1e-15) << q.x << " " << q.y << " " << q.z;
  closest_on_triangle({0.5, 1, 0}, a, a, c, q);  // closest point (0.5, 0, 0)
  EXPECT_NEAR(norm(q - Vec3{0.5, 0, 0}), 0, 1e-15) << q.x << " " << q.y << " " << q.z;
}

// ---------------------------------------------------------------------------------------------
// 2. Flat meshed squares: one contact, the plane's gap and normal.

namespace {

/// Exactly one contact with gap |z| - r and normal (0, 0, sign z) for every sphere (whose
/// projection lies in the square); mismatches counted, the first described.
void expect_flat(const TriangleMesh& m, const std::vector<std::pair<Vec3, double>>& spheres,
                 const char* what) {
  int failures = 0;
  std::string first;
  for (const auto& [x, r] : spheres) {
    const auto cs = all_contacts(m, x, r);
    const Vec3 n{0, 0, x.z > 0 ? 1.0 : -1.0};
    const bool ok = cs.size() == 1 && std::abs(cs[0].gap - (std::abs(x.z) - r)) <= 1e-12 &&
                    norm(cs[0].normal - n) <= 1e-12;
    if (!ok && failures++ == 0) first = describe(x, r) + ": " + describe(cs);
  }
  EXPECT_EQ(failures, 0) << what << " (of " << spheres.size() << "), first: " << first;
}

/// Centres at random heights (above and below, |z| in [0.01, 0.3)) and radii (|z| < r < |z| +
/// 0.2) above the given (x, y).
std::vector<std::pair<Vec3, double>> spheres_above(std::mt19937_64& g,
                                                   const std::vector<std::array<double, 2>>& xy) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::pair<Vec3, double>> out;
  for (std::size_t k = 0; k < xy.size(); ++k) {
    const double z = (k % 2 ? -1 : 1) * (0.01 + 0.29 * u(g));
    out.push_back({{xy[k][0], xy[k][1], z}, std::abs(z) + 0.001 + 0.2 * u(g)});
  }
  return out;
}

}  // namespace

TEST(TriangleMeshContact, FlatSquaresRandomCentresOneContact) {
  std::mt19937_64 g(4);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::array<double, 2>> xy;
  for (int k = 0; k < 2000; ++k) xy.push_back({u(g), u(g)});
  const auto spheres = spheres_above(g, xy);
  expect_flat(square_grid(1, false), spheres, "2 triangles");
  expect_flat(square_grid(8, false), spheres, "8x8 squares");
  expect_flat(square_grid(8, true), spheres, "8x8 squares, alternating diagonals");
  expect_flat(square_fan(), spheres, "fan");
}

// Centres exactly above shared edges (grid lines, both kinds of diagonals, the fan's spokes) and
// shared vertices: the minimum is shared by several triangles, one takes it.
TEST(TriangleMeshContact, FlatSquaresCentresAboveSharedEdgesAndVerticesOneContact) {
  std::mt19937_64 g(5);
  std::uniform_int_distribution<int> cell(1, 7), sq(0, 7);
  std::vector<std::array<double, 2>> grid_lines, diagonals, anti_diagonals, vertices;
  for (int k = 0; k < 300; ++k) {
    const double s = dyadic(g, 0, 1);
    grid_lines.push_back({cell(g) / 8.0, s});
    grid_lines.push_back({s, cell(g) / 8.0});
    vertices.push_back({cell(g) / 8.0, cell(g) / 8.0});
    // Inside square (i, j): the diagonal (i, j)-(i+1, j+1) (x - y = (i - j) / 8) and the other
    // one (x + y = (i + j + 1) / 8).
    const int i = sq(g), j = sq(g);
    const double t = dyadic(g, 0, 1) / 8;
    diagonals.push_back({i / 8.0 + t, j / 8.0 + t});
    anti_diagonals.push_back({(i + 1) / 8.0 - t, j / 8.0 + t});
  }
  std::vector<std::array<double, 2>> main_diag;  // the 2-triangle square's diagonal
  for (int k = 0; k < 300; ++k) {
    const double t = dyadic(g, 0, 1);
    main_diag.push_back({t, t});
  }
  expect_flat(square_grid(1, false), spheres_above(g, main_diag), "2 triangles, diagonal");
  const TriangleMesh grid = square_grid(8, false), alt = square_grid(8, true);
  expect_flat(grid, spheres_above(g, grid_lines), "8x8, grid lines");
  expect_flat(grid, spheres_above(g, vertices), "8x8, vertices");
  expect_flat(grid, spheres_above(g, diagonals), "8x8, diagonals");
  expect_flat(alt, spheres_above(g, grid_lines), "8x8 alternating, grid lines");
  expect_flat(alt, spheres_above(g, vertices), "8x8 alternating, vertices");
  // In the alternating grid square (i, j) has the first diagonal when i + j is even.
  std::vector<std::array<double, 2>> alt_diag;
  for (std::size_t k = 0; k < diagonals.size(); ++k) {
    const int i = static_cast<int>(diagonals[k][0] * 8), j = static_cast<int>(diagonals[k][1] * 8);
    alt_diag.push_back((i + j) % 2 == 0 ? diagonals[k] : anti_diagonals[k]);
  }
  expect_flat(alt, spheres_above(g, alt_diag), "8x8 alternating, diagonals");
  std::vector<std::array<double, 2>> spokes{{0.5, 0.5}};
  for (int k = 0; k < 100; ++k) {
    const double a = dyadic(g, 0, 0.5), b = dyadic(g, 0.5, 1);
    spokes.push_back({0.5, a});
    spokes.push_back({b, 0.5});
    spokes.push_back({a, a});
    spokes.push_back({b, 1 - b});
  }
  expect_flat(square_fan(), spheres_above(g, spokes), "fan, spokes and centre");
}

// Centres within rounding of a shared edge or vertex of a flat surface (1e-14 to 1e-8 off it, on
// either side): still one contact. Regression (first version): owns() counts a neighbour across an
// edge (or around a vertex) as tied, no point closer than q, when its points are closer by up to
// 1e-9 |d|, and then lets the lower index take the contact; but the neighbour's own closest point
// is then in its face, and Face contacts are always taken. A centre less than 1e-9 |d| off a shared
// edge, on the side of the higher-index triangle, gets two contacts (up to four near a vertex of
// the 8x8 grid): the 2-triangle square, centre (0.375, 0.375 + 1e-12, 0.1), r 0.2: triangle 0
// (edge) and triangle 1 (face).
TEST(TriangleMeshContact, FlatSquaresCentresWithinRoundingOfSharedEdgesOneContact) {
  std::vector<std::pair<Vec3, double>> spheres;
  for (double eps : {1e-14, 1e-12, 1e-11, 1e-10, 1e-8})
    for (double side : {1.0, -1.0})
      for (double z : {0.1, -0.05}) {
        const double r = std::abs(z) + 0.1;
        spheres.push_back({{0.375, 0.375 + side * eps, z}, r});                 // main diagonal
        spheres.push_back({{0.5 + side * eps, 0.3, z}, r});                     // x = 0.5
        spheres.push_back({{0.3 + side * eps, 0.6875 - side * eps, z}, r});     // anti-diagonal
        spheres.push_back({{0.5 + side * eps, 0.5 + 0.7 * side * eps, z}, r});  // near vertex
        spheres.push_back({{0.5 - side * eps, 0.5 + 0.3 * side * eps, z}, r});
      }
  expect_flat(square_grid(1, false), spheres, "2 triangles");
  expect_flat(square_grid(8, false), spheres, "8x8 squares");
  expect_flat(square_grid(8, true), spheres, "8x8 squares, alternating diagonals");
  expect_flat(square_fan(), spheres, "fan");
}

// A flat rectangle whose diagonal is split by a vertex m: triangles (v0, v1, m), (m, v1, v2),
// the sliver (v0, m, v2) and (v0, v2, v3) (a T-junction closed by a zero-area triangle, common in
// STL files). With m on the diagonal as computed (m = 0.3 v2: the sliver has zero area, or 1e-15
// of its length off the line) the surface is still the flat rectangle, touched once; with m 1e-6
// off the diagonal (a thin but proper triangle) likewise. Regression (first version), for the
// sliver (1632 and 427 of 2000 centres get 2 or 3 contacts; the 1e-6 case passes): the sliver takes
// a contact of its own besides the face under the centre, when its closest point is on its long
// edge (v2, v0) (the only triangle across that edge is (v0, v2, v3): the triangles that cover the
// sliver from the other side, across its short edges, are not consulted), or when
// closest_on_triangle returns Face with a wrong point for it (see
// DegenerateTrianglesGiveTheClosestPointOfTheirSegments).
TEST(TriangleMeshContact, FlatRectangleWithSliverTriangleOneContact) {
  std::mt19937_64 g(17);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::array<double, 2>> xy;
  for (int k = 0; k < 2000; ++k) {
    // Near the diagonal (within 0.01), inside the rectangle [0, 1] x [0, 0.7].
    const double s = 0.02 + 0.96 * u(g), off = 0.01 * (2 * u(g) - 1);
    xy.push_back({s - 0.7 * off / std::sqrt(1.49), 0.7 * s + off / std::sqrt(1.49)});
  }
  const auto spheres = spheres_above(g, xy);
  for (double off : {1e-6, 1e-15, 0.0}) {
    const Vec3 v0{0, 0, 0}, v1{1, 0, 0}, v2{1, 0.7, 0}, v3{0, 0.7, 0};
    const Vec3 m = 0.3 * v2 + off * Vec3{0.7, -1, 0};
    const TriangleMesh rect({v0, v1, v2, v3, m}, {{0, 1, 4}, {4, 1, 2}, {0, 4, 2}, {0, 2, 3}});
    expect_flat(rect, spheres,
                off == 0 ? "sliver of zero area"
                         : (off < 1e-9 ? "sliver 1e-15 thick" : "thin triangle 1e-6 thick"));
  }
}

// Centres beyond the rim of the open squares (their closest point on the boundary edges and
// corners), and everywhere: the brute-force local minima (a single one: the squares are flat
// and convex).
TEST(TriangleMeshContact, FlatSquaresAgainstBruteForceAlsoBeyondTheRim) {
  std::mt19937_64 g(6);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::pair<Vec3, double>> spheres;
  for (int k = 0; k < 500; ++k) {
    const Vec3 x{-0.3 + 1.6 * u(g), -0.3 + 1.6 * u(g), 0.4 * (u(g) - 0.5)};
    spheres.push_back({x, 0.05 + 0.4 * u(g)});
  }
  for (const auto& m : {square_grid(1, false), square_grid(8, true), square_fan()}) {
    expect_oracle(m, spheres, "flat square");
    for (const auto& [x, r] : spheres) ASSERT_LE(all_contacts(m, x, r).size(), 1u);
  }
}

// ---------------------------------------------------------------------------------------------
// 3. The cube.

TEST(TriangleMeshContact, CubeOutsideFaceEdgeCorner) {
  const TriangleMesh cube = unit_cube();
  const auto one = [&](const Vec3& x, double r, const Vec3& q, const char* what) {
    const auto cs = all_contacts(cube, x, r);
    ASSERT_EQ(cs.size(), 1u) << what << ": " << describe(x, r) << ": " << describe(cs);
    EXPECT_LE(norm(cs[0].normal - normalized(x - q)), 1e-12) << what << ": " << describe(cs);
    EXPECT_NEAR(cs[0].gap, norm(x - q) - r, 1e-12) << what;
    EXPECT_EQ(oracle_mismatch(cube, x, r), "") << what;
  };
  // Above the top face, off its diagonal and exactly above it (its centre).
  one({0.43, 0.61, 1.1}, 0.2, {0.43, 0.61, 1}, "face");
  one({0.5, 0.5, 1.1}, 0.2, {0.5, 0.5, 1}, "face centre, on the diagonal");
  one({0.37, -0.08, 0.55}, 0.2, {0.37, 0, 0.55}, "side face");
  // Beyond the convex edge x = 1, z = 1 (both faces' closest points on it): the bisecting
  // normal for a symmetric centre, the direction from the edge otherwise.
  one({1.1, 0.37, 1.1}, 0.2, {1, 0.37, 1}, "edge, bisecting");
  one({1.05, 0.37, 1.12}, 0.2, {1, 0.37, 1}, "edge");
  one({0.22, -0.07, -0.09}, 0.2, {0.22, 0, 0}, "bottom edge");
  // Beyond a corner: along the diagonal and off it.
  one({1.1, 1.1, 1.1}, 0.2, {1, 1, 1}, "corner, diagonal");
  one({1.05, 1.08, 1.11}, 0.2, {1, 1, 1}, "corner");
  one({-0.05, 1.08, -0.11}, 0.2, {0, 1, 0}, "corner (0, 1, 0)");
}

TEST(TriangleMeshContact, CubeInsideCornerThreeContacts) {
  const TriangleMesh cube = unit_cube();
  const auto three = [&](const Vec3& x, double r, const Vec3& c) {
    // Inside near corner c: the three faces through c, inward normals.
    const auto cs = all_contacts(cube, x, r);
    ASSERT_EQ(cs.size(), 3u) << describe(x, r) << ": " << describe(cs);
    for (int k = 0; k < 3; ++k) {
      Vec3 n{};
      n[k] = c[k] == 0 ? 1.0 : -1.0;
      int found = 0;
      for (const auto& ct : cs)
        if (norm(ct.normal - n) <= 1e-12) {
          ++found;
          EXPECT_NEAR(ct.gap, std::abs(x[k] - c[k]) - r, 1e-12);
        }
      EXPECT_EQ(found, 1) << "face " << k << ": " << describe(cs);
    }
    EXPECT_EQ(oracle_mismatch(cube, x, r), "");
  };
  three({0.1, 0.12, 0.14}, 0.2, {0, 0, 0});
  three({0.1, 0.1, 0.1}, 0.2, {0, 0, 0});  // above the diagonals of all three faces
  three({0.91, 0.13, 0.85}, 0.2, {1, 0, 1});
  three({0.875, 0.875, 0.875}, 0.25, {1, 1, 1});
}

TEST(TriangleMeshContact, CubeRandomCentresAgainstBruteForce) {
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::pair<Vec3, double>> spheres;
  for (int k = 0; k < 2000; ++k)
    spheres.push_back(
        {{-0.3 + 1.6 * u(g), -0.3 + 1.6 * u(g), -0.3 + 1.6 * u(g)}, 0.05 + 0.45 * u(g)});
  expect_oracle(unit_cube(), spheres, "cube");
}

// ---------------------------------------------------------------------------------------------
// 4. Valleys and ridges, a bumpy surface, a non-manifold edge.

TEST(TriangleMeshContact, ValleyTwoContactsRidgeOne) {
  // 90 degree valley: sides z = -y and z = y.
  const TriangleMesh valley = two_strips(1.0);
  {
    const Vec3 x{0.43, 0, 0.3};
    const double r = 0.3;  // distance to each side 0.3 / sqrt(2)
    const auto cs = all_contacts(valley, x, r);
    ASSERT_EQ(cs.size(), 2u) << describe(cs);
    const Vec3 nl = normalized(Vec3{0, 1, 1}), nr = normalized(Vec3{0, -1, 1});
    EXPECT_TRUE((norm(cs[0].normal - nl) < 1e-12 && norm(cs[1].normal - nr) < 1e-12) ||
                (norm(cs[0].normal - nr) < 1e-12 && norm(cs[1].normal - nl) < 1e-12))
        << describe(cs);
    for (const auto& c : cs) EXPECT_NEAR(c.gap, 0.3 / std::sqrt(2.0) - r, 1e-12);
    EXPECT_EQ(oracle_mismatch(valley, x, r), "");
    // Off the middle: still both sides when within reach; one when the other is out of reach.
    EXPECT_EQ(all_contacts(valley, {0.61, 0.05, 0.32}, 0.3).size(), 2u);
    EXPECT_EQ(all_contacts(valley, {0.61, 0.2, 0.32}, 0.3).size(), 1u);
  }
  // A wide valley (sides at 20 degrees) and a narrow one (70 degrees from horizontal).
  for (double slope : {std::tan(20 * M_PI / 180), std::tan(70 * M_PI / 180)}) {
    const TriangleMesh v = two_strips(slope);
    const Vec3 x{0.3, 0, 0.2};
    const double d = 0.2 * std::cos(std::atan(slope));
    const auto cs = all_contacts(v, x, d + 0.01);
    ASSERT_EQ(cs.size(), 2u) << slope << ": " << describe(cs);
    for (const auto& c : cs) EXPECT_NEAR(c.gap, -0.01, 1e-12);
    EXPECT_EQ(oracle_mismatch(v, x, d + 0.01), "");
  }
  // Roof: ridge along x at z = 0, sides going down (z = -|y|). A sphere above the left side near
  // the ridge: its face only, not the ridge seen from the right side's triangles.
  const TriangleMesh roof = two_strips(-1.0);
  const Vec3 nl = normalized(Vec3{0, -1, 1});
  for (double h : {0.1, 0.2}) {
    const Vec3 q{0.5, -0.05, -0.05};  // on the left side
    const Vec3 x = q + h * nl;
    const double r = h + 0.05;
    ASSERT_LT(norm(x - Vec3{0.5, 0, 0}), r);  // the ridge is within reach
    const auto cs = all_contacts(roof, x, r);
    ASSERT_EQ(cs.size(), 1u) << describe(x, r) << ": " << describe(cs);
    EXPECT_LE(norm(cs[0].normal - nl), 1e-12);
    EXPECT_NEAR(cs[0].gap, h - r, 1e-12);
    EXPECT_EQ(oracle_mismatch(roof, x, r), "");
  }
  // Above the ridge: one contact, normal from the ridge.
  const Vec3 x{0.5, 0.02, 0.1};
  const auto cs = all_contacts(roof, x, 0.2);
  ASSERT_EQ(cs.size(), 1u) << describe(cs);
  EXPECT_LE(norm(cs[0].normal - normalized(x - Vec3{0.5, 0, 0})), 1e-12);
  // Random centres around the valley and the roof, above and below.
  std::mt19937_64 g(8);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::pair<Vec3, double>> spheres;
  for (int k = 0; k < 1000; ++k)
    spheres.push_back(
        {{-0.2 + 1.4 * u(g), -1.2 + 2.4 * u(g), -0.8 + 1.6 * u(g)}, 0.05 + 0.5 * u(g)});
  expect_oracle(valley, spheres, "valley");
  expect_oracle(roof, spheres, "roof");
}

TEST(TriangleMeshContact, BumpySurfaceAgainstBruteForce) {
  const TriangleMesh m = bumpy(6, 0.15, 9);
  std::mt19937_64 g(10);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::pair<Vec3, double>> spheres;
  for (int k = 0; k < 2000; ++k)
    spheres.push_back(
        {{-0.1 + 1.2 * u(g), -0.1 + 1.2 * u(g), -0.2 + 0.55 * u(g)}, 0.03 + 0.3 * u(g)});
  expect_oracle(m, spheres, "bumpy");
}

TEST(TriangleMeshContact, NonManifoldFinsAgainstBruteForce) {
  const TriangleMesh m = three_fins();
  EXPECT_EQ(m.nonmanifold_edges(), 1u);
  // Between the fins at 90 and 210 degrees (the sector about 150): both faces.
  const double a = 150 * M_PI / 180;
  const Vec3 x{0.4, 0.3 * std::cos(a), 0.3 * std::sin(a)};  // 0.3 sin 60 from both fins
  const auto cs = all_contacts(m, x, 0.3);
  EXPECT_EQ(cs.size(), 2u) << describe(cs);
  for (const auto& c : cs) EXPECT_NEAR(c.gap, 0.3 * std::sin(M_PI / 3) - 0.3, 1e-12);
  EXPECT_EQ(oracle_mismatch(m, x, 0.3), "");
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::pair<Vec3, double>> spheres;
  for (int k = 0; k < 1000; ++k)
    spheres.push_back(
        {{-0.3 + 1.6 * u(g), -1.2 + 2.4 * u(g), -1.2 + 2.4 * u(g)}, 0.05 + 0.5 * u(g)});
  expect_oracle(m, spheres, "fins");
}

// distance() against the brute force.
TEST(TriangleMeshContact, DistanceMatchesBruteForce) {
  const TriangleMesh m = bumpy(4, 0.3, 12);
  std::mt19937_64 g(13);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int k = 0; k < 200; ++k) {
    const Vec3 x{u(g), u(g), u(g)};
    for (std::size_t t = 0; t < m.size(); ++t) {
      const P3<LD> q =
          triangle_closest(wide<LD>(x), corner(m, t, 0), corner(m, t, 1), corner(m, t, 2));
      const double want = static_cast<double>(std::sqrt(dist2(wide<LD>(x), q)));
      ASSERT_NEAR(m.distance(static_cast<std::int32_t>(t), x), want, 1e-12 * (1 + want)) << t;
    }
  }
}

// distance_bound() and segment_distance_bound() (the wall list's cheap rejections) never exceed
// the exact distances, and reject: points far from a triangle get a bound close to the distance.
TEST(TriangleMeshContact, DistanceBoundsAreLowerBounds) {
  const TriangleMesh m = bumpy(4, 0.3, 12);
  std::mt19937_64 g(15);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  int tight = 0, checked = 0;
  for (int k = 0; k < 300; ++k) {
    const Vec3 x{u(g), u(g), u(g)};
    const Vec3 x1 = x + 0.3 * Vec3{u(g) - 0.5, u(g) - 0.5, u(g) - 0.5};
    for (std::size_t t = 0; t < m.size(); ++t) {
      const auto tri = static_cast<std::int32_t>(t);
      const double d = m.distance(tri, x), b = m.distance_bound(tri, x);
      ASSERT_LE(b, d) << "triangle " << t << " point " << describe(x, 0);
      ASSERT_LE(m.segment_distance_bound(tri, x, x1), m.segment_distance(tri, x, x1)) << t;
      ASSERT_EQ(m.segment_distance_bound(tri, x, x), b);
      ++checked;
      if (b > 0.5 * d) ++tight;
    }
  }
  // Most random point-triangle pairs are far apart: the bound is useful for them.
  EXPECT_GT(tight, checked / 2);
  // Above a flat square's triangle: the plane's distance, less the mesh's tolerance (1e-9 of its
  // size, here 1.4e-9); through it, 0 at most.
  const TriangleMesh sq = square_grid(1, false);
  EXPECT_NEAR(sq.distance_bound(0, {0.7, 0.2, 0.25}), 0.25, 2e-9);
  EXPECT_LE(sq.segment_distance_bound(0, {0.7, 0.2, -0.5}, {0.7, 0.2, 0.5}), 0.0);
}

// ---------------------------------------------------------------------------------------------
// 5. The grid.

namespace {

/// For random points around the mesh: every triangle within `reach` is a candidate; the
/// candidates increase strictly and are valid indices. Returns the mean number of candidates.
double check_candidates(const TriangleMesh& m, double reach, std::mt19937_64& g) {
  m.index(reach);
  Vec3 lo = m.points()[0], hi = lo;
  for (const auto& p : m.points())
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  std::uniform_real_distribution<double> u(0, 1);
  std::size_t total = 0;
  int points = 0;
  const auto check = [&](const Vec3& x) {
    const auto [b, e] = m.candidates(x);
    std::vector<int> cand(b, e);
    total += cand.size();
    ++points;
    for (std::size_t k = 0; k < cand.size(); ++k) {
      ASSERT_GE(cand[k], 0);
      ASSERT_LT(cand[k], static_cast<int>(m.size()));
      if (k > 0) {
        ASSERT_LT(cand[k - 1], cand[k]) << "not increasing";
      }
    }
    for (std::size_t t = 0; t < m.size(); ++t) {
      const P3<LD> q =
          triangle_closest(wide<LD>(x), corner(m, t, 0), corner(m, t, 1), corner(m, t, 2));
      if (std::sqrt(dist2(wide<LD>(x), q)) <= reach) {
        ASSERT_TRUE(std::binary_search(cand.begin(), cand.end(), static_cast<int>(t)))
            << "triangle " << t << " within reach " << reach << " of " << describe(x, 0)
            << " is not a candidate";
      }
    }
  };
  for (int k = 0; k < 800; ++k) {
    Vec3 x;
    for (int d = 0; d < 3; ++d) x[d] = lo[d] - 1.5 * reach + (hi[d] - lo[d] + 3 * reach) * u(g);
    check(x);
  }
  // Vertices, and points at exactly the reach from a vertex along an axis.
  for (std::size_t v = 0; v < m.points().size(); v += 3) {
    check(m.points()[v]);
    check(m.points()[v] + Vec3{reach, 0, 0});
    check(m.points()[v] - Vec3{0, 0, reach});
  }
  // Far away: nothing.
  const auto [b, e] = m.candidates(hi + Vec3{1e3, 1e3, 1e3});
  EXPECT_EQ(b, e);
  const auto [b2, e2] = m.candidates(lo - Vec3{1e3, 0, 0});
  EXPECT_EQ(b2, e2);
  return double(total) / points;
}

}  // namespace

TEST(TriangleMeshGrid, CandidatesHoldEveryTriangleWithinReach) {
  std::mt19937_64 g(14);
  std::uniform_real_distribution<double> u(0, 1);
  const TriangleMesh sphere = uv_sphere({0.3, -0.2, 0.1}, 1.0, 8, 16);
  // A soup of random triangles of very different sizes, some far apart.
  std::vector<Vec3> pts;
  std::vector<Tri> tris;
  for (int t = 0; t < 60; ++t) {
    const Vec3 o{4 * u(g), 2 * u(g), u(g)};
    const double s = t % 5 == 0 ? 1.5 : 0.02 + 0.2 * u(g);
    for (int k = 0; k < 3; ++k) pts.push_back(o + s * Vec3{u(g) - 0.5, u(g) - 0.5, u(g) - 0.5});
    tris.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  const TriangleMesh soup(pts, tris);
  const TriangleMesh single({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  for (double reach : {0.0, 0.01, 0.1, 0.7}) {
    check_candidates(sphere, reach, g);
    check_candidates(soup, reach, g);
    check_candidates(single, reach, g);
    check_candidates(square_grid(8, true), reach, g);
  }
  // A small reach selects: fewer candidates than triangles.
  EXPECT_LT(check_candidates(sphere, 0.01, g), 0.5 * double(sphere.size()));
  // A mesh without triangles: no candidates.
  const TriangleMesh none;
  none.index(0.1);
  const auto [b, e] = none.candidates({0, 0, 0});
  EXPECT_EQ(b, e);
}

// ---------------------------------------------------------------------------------------------
// 6. place().

TEST(TriangleMeshPlace, VerticesFollowTheMotionAndTheGridFollows) {
  TriangleMesh m = uv_sphere({0.3, -0.2, 0.1}, 0.5, 6, 12);
  RigidMotion motion;
  motion.axis = normalized(Vec3{1, 2, 2});
  motion.center = {0.1, 0.2, 0.3};
  motion.rate = 2.5;
  motion.velocity = {3.0, -1.0, 2.0};
  motion.start = 0.1;
  const double reach = 0.05;
  m.index(reach);
  for (double t : {0.05, 0.7, 1.3}) {
    m.place(motion, t);
    ASSERT_EQ(m.points().size(), m.points0().size());
    for (std::size_t k = 0; k < m.points().size(); ++k)
      ASSERT_EQ(m.points()[k], motion.point_at(m.points0()[k], t)) << k;
    // The grid follows, with the same reach: a point on the moved surface finds its triangles.
    m.index(reach);
    std::mt19937_64 g(15);
    std::uniform_real_distribution<double> u(0, 1);
    for (std::size_t t_ = 0; t_ < m.size(); t_ += 5) {
      const auto& tr = m.triangles()[t_];
      const Vec3 x = (1.0 / 3) * (m.points()[static_cast<std::size_t>(tr[0])] +
                                  m.points()[static_cast<std::size_t>(tr[1])] +
                                  m.points()[static_cast<std::size_t>(tr[2])]) +
                     0.02 * Vec3{u(g), u(g), u(g)};
      const auto [b, e] = m.candidates(x);
      EXPECT_TRUE(std::find(b, e, static_cast<std::int32_t>(t_)) != e)
          << "t " << t << ": triangle " << t_ << " not a candidate after place()";
      EXPECT_NEAR(m.distance(static_cast<std::int32_t>(t_), x),
                  static_cast<double>(std::sqrt(
                      dist2(wide<LD>(x), triangle_closest(wide<LD>(x), corner(m, t_, 0),
                                                          corner(m, t_, 1), corner(m, t_, 2))))),
                  1e-12);
    }
    // The box of t = 0 is unchanged.
    Vec3 lo = m.points0()[0], hi = lo;
    for (const auto& q : m.points0())
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], q[d]);
        hi[d] = std::max(hi[d], q[d]);
      }
    EXPECT_EQ(m.lo0(), lo);
    EXPECT_EQ(m.hi0(), hi);
  }
  // A wall at rest: the vertices bit for bit, whatever the time and centre.
  TriangleMesh still = uv_sphere({0.3, -0.2, 0.1}, 0.5, 6, 12);
  RigidMotion rest;
  rest.center = {0.123, 0.456, 0.789};
  for (double t : {0.0, 0.5, 123.0}) {
    still.place(rest, t);
    for (std::size_t k = 0; k < still.points().size(); ++k)
      ASSERT_EQ(still.points()[k], still.points0()[k]);
  }
  // A translation that has not started yet (t < start): the vertices are point_at's.
  TriangleMesh late = uv_sphere({0.3, -0.2, 0.1}, 0.5, 6, 12);
  RigidMotion later;
  later.velocity = {1, 0, 0};
  later.start = 1.0;
  late.place(later, 0.5);
  for (std::size_t k = 0; k < late.points().size(); ++k)
    ASSERT_EQ(late.points()[k], later.point_at(late.points0()[k], 0.5));
}

// A mesh translated far away: the grid of the old position must not be reused.
TEST(TriangleMeshPlace, GridReindexedAfterTranslation) {
  TriangleMesh m = square_grid(4, false);
  m.index(0.05);
  const Vec3 above{0.3, 0.3, 0.01};
  {
    const auto [b, e] = m.candidates(above);
    ASSERT_NE(b, e);
  }
  RigidMotion shift;
  shift.velocity = {5, 0, 0};
  m.place(shift, 1.0);  // now over [5, 6] x [0, 1]
  m.index(0.05);
  {
    const auto [b, e] = m.candidates(above + Vec3{5, 0, 0});
    std::vector<int> cand(b, e);
    int within = 0;
    for (std::size_t t = 0; t < m.size(); ++t)
      if (m.distance(static_cast<std::int32_t>(t), above + Vec3{5, 0, 0}) <= 0.05) {
        ++within;
        EXPECT_TRUE(std::binary_search(cand.begin(), cand.end(), static_cast<int>(t))) << t;
      }
    EXPECT_GT(within, 0);
    const auto [b0, e0] = m.candidates(above);  // the old place: nothing there now
    for (auto p = b0; p != e0; ++p) EXPECT_GT(m.distance(*p, above), 0.05);
  }
  EXPECT_EQ(m.lo0(), (Vec3{0, 0, 0}));
  EXPECT_EQ(m.hi0(), (Vec3{1, 1, 0}));
}

// ---------------------------------------------------------------------------------------------
// 7. Constructor and topology.

TEST(TriangleMeshTopology, InvalidInputThrows) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  EXPECT_THROW(TriangleMesh(pts, {{0, 1, 4}}), std::invalid_argument);
  EXPECT_THROW(TriangleMesh(pts, {{0, 1, 2}, {-1, 1, 2}}), std::invalid_argument);
  EXPECT_THROW(TriangleMesh(pts, {{0, 1, 1}}), std::invalid_argument);
  EXPECT_THROW(TriangleMesh(pts, {{2, 1, 2}}), std::invalid_argument);
  EXPECT_THROW(TriangleMesh(pts, {{1, 2, 3}, {3, 0, 3}}), std::invalid_argument);
  EXPECT_NO_THROW(TriangleMesh(pts, {{0, 1, 3}, {0, 3, 2}}));
  const TriangleMesh empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.size(), 0u);
}

// Vertices repeated per triangle (as in STL files), also off by rounding, are merged, so that the
// triangles share their edges; a triangle whose vertices merge is refused.
TEST(TriangleMeshTopology, CloseVerticesMergedIntoSharedEdges) {
  const double e = 1e-12;  // 1e-12 of the size: merged (below 1e-9)
  const TriangleMesh square({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {e, -e, 0}, {1, 1 + e, 0}, {0, 1, 0}},
                            {{0, 1, 2}, {3, 4, 5}});
  EXPECT_EQ(square.points().size(), 4u);
  EXPECT_EQ(square.boundary_edges(), 4u);
  EXPECT_EQ(square.nonmanifold_edges(), 0u);
  // Then one contact above the shared diagonal, as for the indexed square.
  std::mt19937_64 g(19);
  std::vector<std::array<double, 2>> diag;
  for (int k = 0; k < 200; ++k) {
    const double t = dyadic(g, 0.01, 0.99);
    diag.push_back({t, t});
  }
  expect_flat(square, spheres_above(g, diag), "merged square, diagonal");
  // Apart by 1e-6 of the size: kept apart (two triangles, 6 boundary edges).
  const TriangleMesh apart(
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1e-6, 0, 0}, {1, 1 + 1e-6, 0}, {0, 1, 0}},
      {{0, 1, 2}, {3, 4, 5}});
  EXPECT_EQ(apart.points().size(), 6u);
  EXPECT_EQ(apart.boundary_edges(), 6u);
  EXPECT_THROW(TriangleMesh({{0, 0, 0}, {1, 0, 0}, {1e-12, 0, 0}}, {{0, 1, 2}}),
               std::invalid_argument);
}

TEST(TriangleMeshTopology, BoundaryAndNonManifoldEdges) {
  const TriangleMesh square = square_grid(1, false);
  EXPECT_EQ(square.size(), 2u);
  EXPECT_EQ(square.boundary_edges(), 4u);
  EXPECT_EQ(square.nonmanifold_edges(), 0u);
  const TriangleMesh grid = square_grid(8, true);
  EXPECT_EQ(grid.size(), 128u);
  EXPECT_EQ(grid.boundary_edges(), 32u);
  EXPECT_EQ(grid.nonmanifold_edges(), 0u);
  const TriangleMesh fan = square_fan();
  EXPECT_EQ(fan.boundary_edges(), 8u);
  EXPECT_EQ(fan.nonmanifold_edges(), 0u);
  const TriangleMesh cube = unit_cube();
  EXPECT_EQ(cube.boundary_edges(), 0u);
  EXPECT_EQ(cube.nonmanifold_edges(), 0u);
  const TriangleMesh sphere = uv_sphere({0, 0, 0}, 1, 6, 10);
  EXPECT_EQ(sphere.boundary_edges(), 0u);
  EXPECT_EQ(sphere.nonmanifold_edges(), 0u);
  // Three triangles on one edge (orientations mixed).
  const TriangleMesh book({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, 0, 1}, {0.5, -1, 0.2}},
                          {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_EQ(book.nonmanifold_edges(), 1u);
  EXPECT_EQ(book.boundary_edges(), 6u);
  const TriangleMesh fins = three_fins();
  EXPECT_EQ(fins.nonmanifold_edges(), 1u);
  EXPECT_EQ(fins.boundary_edges(), 3u * 3u);
  // Reference box and radius.
  EXPECT_EQ(cube.lo0(), (Vec3{0, 0, 0}));
  EXPECT_EQ(cube.hi0(), (Vec3{1, 1, 1}));
  EXPECT_DOUBLE_EQ(cube.radius_about({0.5, 0.5, 0.5}), std::sqrt(0.75));
  EXPECT_DOUBLE_EQ(cube.radius_about({0, 0, 0}), std::sqrt(3.0));
}

// ---------------------------------------------------------------------------------------------
// 8. Through the wall list and the force loop: a meshed floor against a plane floor.

namespace {

struct FloorSetup {
  Material glass{"glass", 2500, 1e7, 0.3};
  Material steel{"steel", 7800, 2e8, 0.28};
  PairTable<contact::PairCoeffs> pairs{2};
  std::vector<Wall> plane, mesh;

  /// The floor z = 0 as a plane, and as a mesh of 16 x 16 squares of side 2^-8 m centred on the
  /// origin (alternating diagonals).
  FloorSetup() {
    const Material* mats[2] = {&glass, &steel};
    for (int a = 0; a < 2; ++a)
      for (int b = a; b < 2; ++b)
        pairs.set(a, b,
                  contact::prepare_pair(
                      "hertz_mindlin", {mats[a], mats[b], 0.004},
                      {{"restitution", 0.5}, {"friction", 0.4}, {"rolling_friction", 0.0}}));
    Wall p;
    p.name = p.group = "floor";
    p.material = 1;
    p.point0 = {0, 0, 0};
    p.dir0 = {0, 0, 1};
    plane = {p};
    Wall w;
    w.name = w.group = "floor";
    w.kind = WallKind::Mesh;
    w.material = 1;
    const int n = 16;
    const double h = std::ldexp(1.0, -8);
    std::vector<Vec3> pts;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) pts.push_back({(i - n / 2) * h, (j - n / 2) * h, 0});
    std::vector<Tri> tris;
    const auto id = [](int i, int j) { return i + (n + 1) * j; };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int v00 = id(i, j), v10 = id(i + 1, j), v11 = id(i + 1, j + 1), v01 = id(i, j + 1);
        if ((i + j) % 2 == 1) {
          tris.push_back({v00, v10, v01});
          tris.push_back({v10, v11, v01});
        } else {
          tris.push_back({v00, v10, v11});
          tris.push_back({v00, v11, v01});
        }
      }
    w.mesh = TriangleMesh(pts, tris);
    w.point0 = {0, 0, 0};
    w.dir0 = {1, 0, 0};  // normal to the motion's axis (z)
    w.radius = w.mesh.radius_about(w.point0);
    mesh = {w};
    plane[0].update_geometry(0);
    mesh[0].update_geometry(0);
  }
};

void zero(ParticleStore& p) {
  for (std::size_t i = 0; i < p.size(); ++i) p.f()[i] = p.torque()[i] = {};
}

}  // namespace

// Spheres pressed onto the floor above triangle interiors, edges (grid lines and diagonals) and
// vertices, with a velocity and a spin: the force and torque of one step on the meshed floor are
// those on the plane, and so are the wall's reaction, the contact count and the elastic energy.
// The floor at rest, and sliding in its own plane (the vertices moved by place()).
TEST(TriangleMeshWall, PressedSphereFeelsThePlaneForce) {
  for (int moving = 0; moving < 2; ++moving) {
    SCOPED_TRACE(moving ? "moving floor" : "floor at rest");
    FloorSetup s;
    const double h = std::ldexp(1.0, -8), r = 0.003;
    const double t = moving ? 0.375 : 0.0;
    const Vec3 V = moving ? Vec3{4 * h, -2 * h, 0} : Vec3{};  // displacement (1.5 h, -0.75 h)
    s.plane[0].motion.velocity = s.mesh[0].motion.velocity = V;
    s.plane[0].update_geometry(t);
    s.mesh[0].update_geometry(t);
    std::vector<Vec3> centres;
    std::mt19937_64 g(16);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 20; ++k) {
      const double z = r * (1 - 0.02 * (0.2 + u(g)));  // overlap 0.4 to 2.4 % of r
      const int i = static_cast<int>(u(g) * 8) - 4, j = static_cast<int>(u(g) * 8) - 4;
      const double a = dyadic(g, 0, 1);
      centres.push_back({(i + 0.3 * u(g) + 0.35) * h, (j + 0.3 * u(g) + 0.35) * h, z});  // inside
      centres.push_back({i * h, (j + a) * h, z});  // grid line
      centres.push_back({(i + a) * h, j * h, z});  // grid line
      centres.push_back({i * h, j * h, z});        // vertex
      // The diagonal of square (i, j) (alternating: x - y constant when i + j is even).
      centres.push_back((i + j + 16) % 2 == 0 ? Vec3{(i + a) * h, (j + a) * h, z}
                                              : Vec3{(i + 1 - a) * h, (j + a) * h, z});
    }
    for (auto& c : centres) c += t * V;  // exact: dyadic
    ParticleStore p_plane, p_mesh;
    for (std::size_t k = 0; k < centres.size(); ++k) {
      const Vec3 v{0.05 * (u(g) - 0.5), 0.05 * (u(g) - 0.5), -0.02 * u(g)};
      const Vec3 w{20 * (u(g) - 0.5), 20 * (u(g) - 0.5), 20 * (u(g) - 0.5)};
      p_plane.add_sphere(static_cast<std::int64_t>(k) + 1, 0, r, s.glass.density, centres[k], v, w);
      p_mesh.add_sphere(static_cast<std::int64_t>(k) + 1, 0, r, s.glass.density, centres[k], v, w);
    }
    WallContactList l_plane, l_mesh;
    l_plane.build(s.plane, p_plane.x(), p_plane.radius(), p_plane.size(), 0.001);
    l_mesh.build(s.mesh, p_mesh.x(), p_mesh.radius(), p_mesh.size(), 0.001);
    ASSERT_GT(l_mesh.entries().size(), 4 * centres.size());  // several triangles within the skin
    for (int step = 0; step < 3; ++step) {  // the second and third with a tangential history
      zero(p_plane);
      zero(p_mesh);
      const auto n_plane = compute_wall_forces(p_plane, s.plane, l_plane, s.pairs, t, 1e-6);
      const auto n_mesh = compute_wall_forces(p_mesh, s.mesh, l_mesh, s.pairs, t, 1e-6);
      EXPECT_EQ(n_plane, static_cast<std::int64_t>(centres.size()));
      EXPECT_EQ(n_mesh, n_plane) << "step " << step;
      for (std::size_t k = 0; k < centres.size(); ++k) {
        const Vec3 f = p_plane.f()[k], tq = p_plane.torque()[k];
        ASSERT_GT(norm(f), 0);
        EXPECT_LE(norm(p_mesh.f()[k] - f), 1e-12 * norm(f))
            << "step " << step << ", " << describe(centres[k], r) << ": mesh f (" << p_mesh.f()[k].x
            << ", " << p_mesh.f()[k].y << ", " << p_mesh.f()[k].z << "), plane (" << f.x << ", "
            << f.y << ", " << f.z << ")";
        EXPECT_LE(norm(p_mesh.torque()[k] - tq), 1e-12 * norm(tq) + 1e-12 * r * norm(f))
            << "step " << step << ", " << describe(centres[k], r);
      }
      EXPECT_LE(norm(s.mesh[0].force - s.plane[0].force), 1e-12 * norm(s.plane[0].force));
      EXPECT_LE(norm(s.mesh[0].torque - s.plane[0].torque), 1e-12 * norm(s.plane[0].torque));
      EXPECT_NEAR(s.mesh[0].contact_stiffness, s.plane[0].contact_stiffness,
                  1e-12 * s.plane[0].contact_stiffness);
      const double e_plane = wall_elastic_energy(p_plane, s.plane, l_plane, s.pairs);
      ASSERT_GT(e_plane, 0);
      EXPECT_NEAR(wall_elastic_energy(p_mesh, s.mesh, l_mesh, s.pairs), e_plane, 1e-12 * e_plane);
    }
  }
}

// A sphere pressed onto the meshed floor with its centre within rounding (1e-15 to 1e-12) of the
// diagonal of a square, on either side: the force of the plane, once. Regression (first version):
// the contact is counted twice, twice the plane's force, when the centre is on the side of the
// higher-index triangle (see FlatSquaresCentresWithinRoundingOfSharedEdgesOneContact); the first
// case is where a sphere sliding along y = 1.7 h from x = 3.3 h at 2 um per step lands after 3125
// steps.
TEST(TriangleMeshWall, SphereWithinRoundingOfAnEdgeFeelsThePlaneForceOnce) {
  FloorSetup s;
  const double h = std::ldexp(1.0, -8), r = 0.003, z = 0.99 * r;
  std::vector<Vec3> centres{{0.0066406249999991698, 0.0066406249999999998, z}};
  for (double eps : {1e-15, 1e-14, 1e-13, 1e-12})
    for (double side : {1.0, -1.0}) centres.push_back({1.7 * h + side * eps, 1.7 * h, z});
  ParticleStore p_plane, p_mesh;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    p_plane.add_sphere(static_cast<std::int64_t>(k) + 1, 0, r, s.glass.density, centres[k],
                       {-1, 0, 0});
    p_mesh.add_sphere(static_cast<std::int64_t>(k) + 1, 0, r, s.glass.density, centres[k],
                      {-1, 0, 0});
  }
  WallContactList l_plane, l_mesh;
  l_plane.build(s.plane, p_plane.x(), p_plane.radius(), p_plane.size(), 0.001);
  l_mesh.build(s.mesh, p_mesh.x(), p_mesh.radius(), p_mesh.size(), 0.001);
  zero(p_plane);
  zero(p_mesh);
  compute_wall_forces(p_plane, s.plane, l_plane, s.pairs, 0, 2e-6);
  const auto n_mesh = compute_wall_forces(p_mesh, s.mesh, l_mesh, s.pairs, 0, 2e-6);
  EXPECT_EQ(n_mesh, static_cast<std::int64_t>(centres.size()));
  for (std::size_t k = 0; k < centres.size(); ++k) {
    const Vec3 f = p_plane.f()[k], fm = p_mesh.f()[k];
    EXPECT_LE(norm(fm - f), 1e-12 * norm(f))
        << describe(centres[k], r) << ": mesh f (" << fm.x << ", " << fm.y << ", " << fm.z
        << "), plane (" << f.x << ", " << f.y << ", " << f.z << ")";
  }
}

// Spheres sliding (and spinning) across the meshed floor over many small steps, the list built
// with a large skin (and rebuilt every 1000 steps): a generic direction, exactly along a grid line,
// exactly along diagonals through vertices. The tangential force history on the mesh is the
// plane's: the history is handed from triangle to triangle as the contact moves on.
TEST(TriangleMeshWall, SlidingSphereKeepsThePlaneHistoryAcrossEdges) {
  FloorSetup s;
  const double h = std::ldexp(1.0, -8), r = 0.003, dt = 2e-6;
  const double z = r * 0.99;
  struct Path {
    Vec3 x0, v, w;
  };
  const std::vector<Path> paths{
      {{-6.3 * h, -5.1 * h, z}, {0.84, 0.52, 0}, {5, -3, 8}},  // generic
      {{-6.3 * h, 2 * h, z}, {1.0, 0, 0}, {0, 0, 0}},          // along the grid line y = 2h
      {{-5 * h, -5 * h, z}, {0.8, 0.8, 0}, {0, 0, 3}},         // diagonal x = y (vertices)
      {{-3 * h, 4 * h, z}, {0.68, -0.68, 0}, {0, 0, 0}},       // anti-diagonal x + y = h
      {{3.3 * h, 1.71 * h, z}, {-1.0, -0.0, 0}, {0, 160, 0}},  // rolling-ish, backwards
  };
  ParticleStore p_plane, p_mesh;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    p_plane.add_sphere(static_cast<std::int64_t>(k) + 1, 0, r, s.glass.density, paths[k].x0,
                       paths[k].v, paths[k].w);
    p_mesh.add_sphere(static_cast<std::int64_t>(k) + 1, 0, r, s.glass.density, paths[k].x0,
                      paths[k].v, paths[k].w);
  }
  WallContactList l_plane, l_mesh;
  l_plane.build(s.plane, p_plane.x(), p_plane.radius(), p_plane.size(), 0.02);
  l_mesh.build(s.mesh, p_mesh.x(), p_mesh.radius(), p_mesh.size(), 0.02);
  const int steps = 6000;  // 12 ms: 10 to 14 mm, 3 to 4 squares
  std::vector<int> failures(paths.size(), 0);
  std::vector<std::set<std::int32_t>> visited(paths.size());
  std::vector<std::string> first(paths.size());
  double max_ratio = 0;
  for (int step = 0; step < steps; ++step) {
    zero(p_plane);
    zero(p_mesh);
    const auto n_plane = compute_wall_forces(p_plane, s.plane, l_plane, s.pairs, 0, dt);
    const auto n_mesh = compute_wall_forces(p_mesh, s.mesh, l_mesh, s.pairs, 0, dt);
    ASSERT_EQ(n_plane, static_cast<std::int64_t>(paths.size()));
    for (std::size_t k = 0; k < paths.size(); ++k) {
      const Vec3 f = p_plane.f()[k], fm = p_mesh.f()[k];
      max_ratio = std::max(max_ratio, std::hypot(f.x, f.y) / f.z);
      const bool ok =
          norm(fm - f) <= 1e-9 * norm(f) && norm(p_mesh.torque()[k] - p_plane.torque()[k]) <=
                                                1e-9 * (norm(p_plane.torque()[k]) + r * norm(f));
      if (!ok && failures[k]++ == 0) {
        std::ostringstream o;
        o.precision(17);
        o << "step " << step << ", " << describe(p_mesh.x()[k], r) << ", " << n_mesh
          << " contacts in all: mesh f (" << fm.x << ", " << fm.y << ", " << fm.z << "), plane ("
          << f.x << ", " << f.y << ", " << f.z << ")";
        first[k] = o.str();
      }
    }
    for (std::size_t k = 0; k < paths.size(); ++k) {
      p_plane.x()[k] += dt * paths[k].v;
      p_mesh.x()[k] += dt * paths[k].v;
    }
    if (step % 10 == 0) {  // the triangles that hold the contacts
      const auto groups = l_mesh.particle_groups();
      for (std::size_t gr = 0; gr + 1 < groups.size(); ++gr)
        for (auto k = groups[gr]; k < groups[gr + 1]; ++k) {
          const auto& e = l_mesh.entries()[static_cast<std::size_t>(k)];
          Vec3 nrm;
          double gap;
          if (s.mesh[0].mesh.sphere_contact(e.element, p_mesh.x()[e.particle], r, nrm, gap))
            visited[static_cast<std::size_t>(e.particle)].insert(e.element);
        }
    }
    if (step % 1000 == 999) {  // rebuilt lists carry the histories (by particle, wall, triangle)
      l_plane.build(s.plane, p_plane.x(), p_plane.radius(), p_plane.size(), 0.02);
      l_mesh.build(s.mesh, p_mesh.x(), p_mesh.radius(), p_mesh.size(), 0.02);
    }
  }
  for (std::size_t k = 0; k < paths.size(); ++k) {
    EXPECT_EQ(failures[k], 0) << "path " << k << ", first: " << first[k];
    EXPECT_GE(visited[k].size(), 3u) << "path " << k;  // it crossed edges
  }
  // The tangential force grew to Coulomb's limit (friction 0.4) from the history.
  EXPECT_GT(max_ratio, 0.39);
}

// A sphere sliding along a meshed V-shaped valley (sides at 45 degrees, two contacts), spinning
// about the vertical so that the slip at its two contacts has opposite signs, against the same
// valley made of two planes. Both contacts move to the next triangles at the same step; the
// triangles are numbered left side first in every segment, then left side first in even segments
// and right side first in odd ones. Each
// new contact must take the history of the triangle it leaves on its own side. Regression (first
// version), for the alternating numbering (every segment numbered left side first passes):
// compute_wall_forces hands a new contact the history of the first triangle, in entry order, of the
// same mesh that lost its contact, which at a segment boundary here is the other side's: the two
// slips swap, and the axial force jumps from 0 to -0.094 N (vertical force 0.18 N) at the first
// boundary (step 586).
TEST(TriangleMeshWall, SlidingInAValleyKeepsEachSideItsHistory) {
  for (bool alternate : {false, true}) {
    SCOPED_TRACE(alternate ? "segments numbered left first, right first, ..."
                           : "left side first in every segment");
    FloorSetup s;  // for the pair table
    const double h = std::ldexp(1.0, -8), r = 0.003, width = 0.004, dt = 1e-5;
    const int n = 16;
    std::vector<Vec3> pts;
    for (int i = 0; i <= n; ++i) {
      const double x = (i - n / 2) * h;
      pts.push_back({x, 0, 0});           // 3 i: the bottom
      pts.push_back({x, -width, width});  // 3 i + 1: left rim
      pts.push_back({x, width, width});   // 3 i + 2: right rim
    }
    std::vector<Tri> tris;
    for (int i = 0; i < n; ++i) {
      const int b0 = 3 * i, b1 = 3 * (i + 1);
      const std::array<Tri, 2> left{Tri{b0, b1, b1 + 1}, Tri{b0, b1 + 1, b0 + 1}};
      const std::array<Tri, 2> right{Tri{b0, b1, b1 + 2}, Tri{b0, b1 + 2, b0 + 2}};
      const bool left_first = !alternate || i % 2 == 0;
      for (const Tri& t : left_first ? left : right) tris.push_back(t);
      for (const Tri& t : left_first ? right : left) tris.push_back(t);
    }
    Wall mw;
    mw.name = mw.group = "valley";
    mw.kind = WallKind::Mesh;
    mw.material = 1;
    mw.mesh = TriangleMesh(pts, tris);
    mw.point0 = {0, 0, 0};
    mw.dir0 = {1, 0, 0};
    mw.radius = mw.mesh.radius_about(mw.point0);
    std::vector<Wall> mesh{mw};
    Wall pl;
    pl.name = pl.group = "left";
    pl.material = 1;
    pl.dir0 = normalized(Vec3{0, 1, 1});
    Wall pr = pl;
    pr.name = pr.group = "right";
    pr.dir0 = normalized(Vec3{0, -1, 1});
    std::vector<Wall> planes{pl, pr};
    for (auto& w : mesh) w.update_geometry(0);
    for (auto& w : planes) w.update_geometry(0);
    // 0.99 r from each side; sliding along x at 0.2 m/s, spinning at 100 rad/s about z (slip
    // 0.2 +- 0.21 m/s at the two contacts).
    const Vec3 x0{-6.3 * h, 0, 0.99 * r * std::sqrt(2.0)}, v{0.2, 0, 0}, w{0, 0, 100};
    ParticleStore p_plane, p_mesh;
    p_plane.add_sphere(1, 0, r, s.glass.density, x0, v, w);
    p_mesh.add_sphere(1, 0, r, s.glass.density, x0, v, w);
    WallContactList l_plane, l_mesh;
    l_plane.build(planes, p_plane.x(), p_plane.radius(), 1, 0.02);
    l_mesh.build(mesh, p_mesh.x(), p_mesh.radius(), 1, 0.02);
    int failures = 0;
    std::string first;
    for (int step = 0; step < 6000; ++step) {  // 12 mm: 3 segments
      zero(p_plane);
      zero(p_mesh);
      ASSERT_EQ(compute_wall_forces(p_plane, planes, l_plane, s.pairs, 0, dt), 2);
      const auto n_mesh = compute_wall_forces(p_mesh, mesh, l_mesh, s.pairs, 0, dt);
      const Vec3 f = p_plane.f()[0], fm = p_mesh.f()[0];
      const Vec3 t = p_plane.torque()[0], tm = p_mesh.torque()[0];
      if ((n_mesh != 2 || norm(fm - f) > 1e-9 * norm(f) ||
           norm(tm - t) > 1e-9 * (norm(t) + r * norm(f))) &&
          failures++ == 0) {
        std::ostringstream o;
        o.precision(17);
        o << "step " << step << ", x " << p_mesh.x()[0].x << ", " << n_mesh << " contacts: mesh f ("
          << fm.x << ", " << fm.y << ", " << fm.z << ") torque (" << tm.x << ", " << tm.y << ", "
          << tm.z << "), planes f (" << f.x << ", " << f.y << ", " << f.z << ") torque (" << t.x
          << ", " << t.y << ", " << t.z << ")";
        first = o.str();
      }
      p_plane.x()[0] += dt * v;
      p_mesh.x()[0] += dt * v;
    }
    EXPECT_EQ(failures, 0) << "first: " << first;
  }
}

// ---------------------------------------------------------------------------------------------
// Spherocylinders: TriangleMesh::capsule_contact against the plane it triangulates, against
// configurations with known contacts (a rod across a ridge, over the edges and a corner of a
// cube, along a ridge) and against a brute force: the local minima of the distance from the axis
// to the union of the triangles, sampled along the axis.

namespace {

struct AxisContact {
  int tri, slot;
  Vec3 centre, normal;
  double gap, weight;
};

std::vector<AxisContact> axis_contacts(const TriangleMesh& m, const Vec3& p0, const Vec3& p1,
                                       double r) {
  std::vector<AxisContact> out;
  for (std::size_t t = 0; t < m.size(); ++t)
    for (int slot = 0; slot < TriangleMesh::capsule_slots; ++slot) {
      AxisContact c{static_cast<int>(t), slot, {}, {}, 0, 0};
      if (m.capsule_contact(static_cast<std::int32_t>(t), slot, p0, p1, r, c.centre, c.normal,
                            c.gap, c.weight))
        out.push_back(c);
    }
  return out;
}

/// Distance from x to the union of the triangles (long double).
LD union_distance(const TriangleMesh& m, const Vec3& x) {
  const P3<LD> xl = wide<LD>(x);
  LD best = std::numeric_limits<LD>::infinity();
  for (std::size_t t = 0; t < m.size(); ++t)
    best = std::min(
        best, dist2(xl, triangle_closest(xl, corner(m, t, 0), corner(m, t, 1), corner(m, t, 2))));
  return std::sqrt(best);
}

std::string describe(const std::vector<AxisContact>& cs) {
  std::ostringstream s;
  s.precision(12);
  s << cs.size() << " contact(s):";
  for (const auto& c : cs)
    s << " [tri " << c.tri << " slot " << c.slot << " centre (" << c.centre.x << ", " << c.centre.y
      << ", " << c.centre.z << ") n (" << c.normal.x << ", " << c.normal.y << ", " << c.normal.z
      << ") gap " << c.gap << " weight " << c.weight << "]";
  return s.str();
}

Vec3 horizontal(double phi) {
  return {std::cos(phi), std::sin(phi), 0};
}

}  // namespace

// Rods lying on a flat meshed square (alternating diagonals, vertices of 4 and 8 triangles), level
// or tilted, ends anywhere including exactly above shared vertices and edges: their two end
// spheres only, each once, with the plane's gap and normal, as on a plane wall.
TEST(TriangleMeshCapsule, RodsOnAFlatMeshTouchAtBothEndsAsOnAPlane) {
  const TriangleMesh m = square_grid(8, true);
  std::mt19937_64 g(21);
  std::uniform_real_distribution<double> u(0, 1);
  const double r = 0.03;
  int failures = 0;
  std::string first;
  for (int k = 0; k < 600; ++k) {
    const double half = 0.02 + 0.13 * u(g), d0 = 0.01 * u(g), d1 = 0.01 * u(g);
    Vec3 c{0.25 + 0.5 * u(g), 0.25 + 0.5 * u(g), 0};
    const Vec3 a = horizontal(2 * M_PI * u(g));
    if (k % 3 == 1) c = Vec3{4.0 / 8, 3.0 / 8, 0} + half * a;           // the first end on a vertex
    if (k % 3 == 2) c = Vec3{5.0 / 8, 0.4 + 0.2 * u(g), 0} + half * a;  // on an edge x = 5/8
    const Vec3 p0 = c - half * a + Vec3{0, 0, r - d0}, p1 = c + half * a + Vec3{0, 0, r - d1};
    const auto got = axis_contacts(m, p0, p1, r);
    bool ok = got.size() == 2;
    for (const auto& x : got) {
      const double want = x.slot == 0 ? -d0 : (x.slot == 1 ? -d1 : 1.0);
      ok = ok && std::abs(x.gap - want) < 1e-12 && norm(x.normal - Vec3{0, 0, 1}) < 1e-12;
    }
    ok = ok && got[0].slot + got[1].slot == 1;
    if (!ok && failures++ == 0) first = describe(got);
  }
  EXPECT_EQ(failures, 0) << "first: " << first;
}

// A level rod across a roof ridge (slopes 0.3) at any angle but near parallel: one contact, in
// the middle of the axis where it crosses the ridge, straight up; along the ridge: its two ends.
TEST(TriangleMeshCapsule, RodAcrossARidgeTouchesItOnceAlongItOnItsEnds) {
  const TriangleMesh m = two_strips(-0.3);
  std::mt19937_64 g(22);
  std::uniform_real_distribution<double> u(0, 1);
  const double r = 0.03, half = 0.2;
  int failures = 0;
  std::string first;
  for (int k = 0; k < 400; ++k) {
    const double delta = 0.01 * u(g), beta = (0.05 + 1.15 * u(g)) * (k % 2 ? 1 : -1);
    const Vec3 c{0.3 + 0.4 * u(g), 0.1 * u(g) - 0.05, r - delta};
    const Vec3 a{std::sin(beta), std::cos(beta), 0};
    const auto got = axis_contacts(m, c - half * a, c + half * a, r);
    const bool ok = got.size() == 1 && got[0].slot >= 2 && std::abs(got[0].gap + delta) < 1e-12 &&
                    norm(got[0].normal - Vec3{0, 0, 1}) < 1e-12 &&
                    std::abs(got[0].centre.y) < 1e-12;
    if (!ok && failures++ == 0) first = describe(got);
  }
  EXPECT_EQ(failures, 0) << "first: " << first;
  // Along the ridge (exactly, and skewed by 1e-13 rad: within the ends' tolerance).
  for (const double skew : {0.0, 1e-13}) {
    const Vec3 a{std::cos(skew), std::sin(skew), 0}, c{0.5, 0, r - 0.004};
    const auto got = axis_contacts(m, c - half * a, c + half * a, r);
    ASSERT_EQ(got.size(), 2u) << describe(got);
    EXPECT_EQ(got[0].slot + got[1].slot, 1) << describe(got);
    for (const auto& x : got) EXPECT_NEAR(x.gap, -0.004, 1e-12);
  }
}

// The cube [0, 1]^3: a level rod lying across its top (longer than the cube) rests on the two
// edges it crosses; tilted, each edge gives its own distance; a level rod passing over a corner
// touches the vertex, at the point of the axis nearest to it; one lying on the top face and over
// an edge touches with its inner end and the edge.
TEST(TriangleMeshCapsule, RodsOverTheEdgesAndCornersOfACube) {
  const TriangleMesh m = unit_cube();
  const double r = 0.05, delta = 0.01;
  std::mt19937_64 g(23);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 50; ++k) {
    const double y = 0.2 + 0.6 * u(g), tilt = k % 2 ? 0.0 : 0.004 * (u(g) - 0.5);
    const Vec3 p0{-0.2, y, 1 + r - delta - 0.2 * tilt}, p1{1.2, y, 1 + r - delta + 1.2 * tilt};
    const auto got = axis_contacts(m, p0, p1, r);
    ASSERT_EQ(got.size(), 2u) << describe(got);
    for (const auto& x : got) {
      EXPECT_GE(x.slot, 2);
      EXPECT_NEAR(x.gap, static_cast<double>(union_distance(m, x.centre)) - r, 1e-12);
      EXPECT_TRUE(std::abs(x.centre.x) < 2e-3 || std::abs(x.centre.x - 1) < 2e-3) << describe(got);
    }
    EXPECT_NEAR(std::abs(got[0].centre.x - got[1].centre.x), 1.0, 4e-3);
    if (tilt == 0.0) {
      for (const auto& x : got) EXPECT_NEAR(x.gap, -delta, 1e-12);
    }
  }
  {  // over the corner (1, 1, 1), level, the axis passing at (a, a, h) from it
    const double a = 0.01, h = 0.03, half = 0.3;
    const Vec3 d = (1 / std::sqrt(2.0)) * Vec3{1, -1, 0}, c{1 + a, 1 + a, 1 + h};
    const auto got = axis_contacts(m, c - half * d, c + half * d, r);
    ASSERT_EQ(got.size(), 1u) << describe(got);
    EXPECT_GE(got[0].slot, 5);
    EXPECT_NEAR(norm(got[0].centre - c), 0.0, 1e-12);
    EXPECT_NEAR(got[0].gap, std::sqrt(2 * a * a + h * h) - r, 1e-12);
  }
  {  // on the top face, over the edge x = 1
    const Vec3 p0{0.7, 0.5, 1 + r - delta}, p1{1.2, 0.5, 1 + r - delta};
    const auto got = axis_contacts(m, p0, p1, r);
    ASSERT_EQ(got.size(), 2u) << describe(got);
    int ends = 0, middles = 0;
    for (const auto& x : got) {
      EXPECT_NEAR(x.gap, -delta, 1e-12);
      ends += x.slot < 2;
      middles += x.slot >= 2 && std::abs(x.centre.x - 1) < 1e-12;
    }
    EXPECT_EQ(ends, 1);
    EXPECT_EQ(middles, 1);
  }
}

// Random rods near a bumpy height field and near a cube against the brute force: every contact
// in the middle of the axis is a local minimum of the distance from the axis to the surface
// (sampled at +-1e-4 of the axis), at the surface's distance, and every clear minimum inside the
// axis (found by sampling 1000 points and refining, deeper than 1e-6 and not within 1 % of an end)
// is one contact, once; every end sphere's contact is one of the surface's contacts with that
// sphere, present exactly when it lies on a flat part or the distance does not decrease into the
// axis.
TEST(TriangleMeshCapsule, RandomRodsAgainstBruteForce) {
  struct Surface {
    TriangleMesh mesh;
    Vec3 lo, hi;
  };
  const std::vector<Surface> surfaces{{bumpy(6, 0.15, 31), {-0.1, -0.1, -0.05}, {1.1, 1.1, 0.25}},
                                      {unit_cube(), {-0.15, -0.15, -0.15}, {1.15, 1.15, 1.15}}};
  std::mt19937_64 g(24);
  std::uniform_real_distribution<double> u(0, 1);
  int failures = 0, n_middle = 0, n_end = 0;
  std::string first;
  const auto fail = [&](const std::string& what) {
    if (failures++ == 0) first = what;
  };
  for (const auto& s : surfaces) {
    const TriangleMesh& m = s.mesh;
    for (int k = 0; k < 400; ++k) {
      const Vec3 c{s.lo.x + (s.hi.x - s.lo.x) * u(g), s.lo.y + (s.hi.y - s.lo.y) * u(g),
                   s.lo.z + (s.hi.z - s.lo.z) * u(g)};
      const double phi = 2 * M_PI * u(g), ct = 2 * u(g) - 1, st = std::sqrt(1 - ct * ct);
      const Vec3 a{st * std::cos(phi), st * std::sin(phi), ct};
      const double half = 0.1 + 0.2 * u(g), r = 0.04 + 0.06 * u(g);
      const Vec3 p0 = c - half * a, p1 = c + half * a;
      const auto d_at = [&](double t) {
        return static_cast<double>(union_distance(m, p0 + t * (p1 - p0)));
      };
      constexpr int n_s = 1000;
      std::vector<double> d(n_s + 1);
      for (int j = 0; j <= n_s; ++j) d[static_cast<std::size_t>(j)] = d_at(double(j) / n_s);
      // (an axis through the surface is no configuration of a simulation)
      if (*std::min_element(d.begin(), d.end()) < 2e-3) continue;
      const auto got = axis_contacts(m, p0, p1, r);
      // Middle contacts: local minima, at the surface's distance; one per point.
      std::vector<double> middles;
      for (const auto& x : got) {
        if (x.slot < 2) continue;
        ++n_middle;
        if (!(x.weight > 0 && x.weight <= 1)) fail("weight out of (0, 1]: " + describe(got));
        const double t = dot(x.centre - p0, p1 - p0) / norm2(p1 - p0), dx = d_at(t);
        const double before = d_at(t - 1e-4), after = d_at(t + 1e-4);
        // Where the axis leaves a face level or rising (the normal is the face's), the distance
        // does not decrease on the way out; elsewhere the point is a local minimum.
        const auto& tr = m.triangles()[static_cast<std::size_t>(x.tri)];
        const Vec3 nt = normalized(cross(m.points()[static_cast<std::size_t>(tr[1])] -
                                             m.points()[static_cast<std::size_t>(tr[0])],
                                         m.points()[static_cast<std::size_t>(tr[2])] -
                                             m.points()[static_cast<std::size_t>(tr[0])]));
        const bool exit = norm(cross(x.normal, nt)) < 1e-12;
        // The contact is one of the local minima of the distance from its centre to the surface;
        // where it is the only one, the distance along the axis is that to the surface.
        const auto minima = oracle_minima(m, x.centre, r);
        bool listed = false;
        for (const auto& mn : minima)
          listed = listed || std::abs(static_cast<double>(std::sqrt(mn.d2)) - r - x.gap) < 1e-10;
        if (!listed || (minima.size() == 1 && (std::abs(x.gap - (dx - r)) > 1e-10 ||
                                               (exit ? std::max(before, after) < dx - 1e-12
                                                     : std::min(before, after) < dx - 1e-12))))
          fail(std::string(exit ? "not an exit: " : "not a local minimum: ") + describe(got) +
               " (t " + std::to_string(t) + ", distance " + std::to_string(dx) + ", before " +
               std::to_string(before) + ", after " + std::to_string(after) + ", r " +
               std::to_string(r) + ")");
        for (const double t2 : middles)
          if (std::abs(t2 - t) < 1e-9) fail("counted twice: " + describe(got));
        middles.push_back(t);
      }
      // The brute force's clear minima inside the axis.
      for (int j = 1; j < n_s; ++j) {
        const auto ju = static_cast<std::size_t>(j);
        if (!(d[ju] < d[ju - 1] && d[ju] <= d[ju + 1]) || d[ju] > r) continue;
        double lo = double(j - 1) / n_s, hi = double(j + 1) / n_s;  // golden-section refinement
        for (int it = 0; it < 80; ++it) {
          const double m1 = lo + (hi - lo) * 0.382, m2 = lo + (hi - lo) * 0.618;
          (d_at(m1) < d_at(m2) ? hi : lo) = d_at(m1) < d_at(m2) ? m2 : m1;
        }
        const double t = 0.5 * (lo + hi), dt = d_at(t);
        if (t < 0.01 || t > 0.99 || dt > r - 1e-6 || d_at(t - 2e-3) < dt + 1e-9 ||
            d_at(t + 2e-3) < dt + 1e-9)
          continue;  // near an end, barely touching, or flat
        int matches = 0;
        for (const double tm : middles) matches += std::abs(tm - t) < 2e-3;
        if (matches != 1)
          fail("minimum at t = " + std::to_string(t) + " found " + std::to_string(matches) +
               " times: " + describe(got));
      }
      // End spheres.
      for (int end = 0; end < 2; ++end) {
        const Vec3& e = end == 0 ? p0 : p1;
        const Vec3 in = normalized(end == 0 ? p1 - p0 : p0 - p1);
        int want = 0;
        for (const auto& mn : oracle_minima(m, e, r)) {
          const Vec3 q{double(mn.q.x), double(mn.q.y), double(mn.q.z)};
          bool flat = false;  // the foot of a perpendicular on a triangle containing q
          for (std::size_t t = 0; t < m.size() && !flat; ++t) {
            Vec3 qt;
            closest_on_triangle(q, m.points()[static_cast<std::size_t>(m.triangles()[t][0])],
                                m.points()[static_cast<std::size_t>(m.triangles()[t][1])],
                                m.points()[static_cast<std::size_t>(m.triangles()[t][2])], qt);
            const auto& tr = m.triangles()[t];
            const Vec3 nt = normalized(cross(m.points()[static_cast<std::size_t>(tr[1])] -
                                                 m.points()[static_cast<std::size_t>(tr[0])],
                                             m.points()[static_cast<std::size_t>(tr[2])] -
                                                 m.points()[static_cast<std::size_t>(tr[0])]));
            flat = norm(qt - q) < 1e-12 && norm(cross(e - q, nt)) < 1e-9;
          }
          const double slope = dot(e - q, in);
          if (!flat && std::abs(slope) < 1e-6 * norm(e - q)) continue;  // too close to call
          want += flat || slope >= 0;
        }
        int have = 0;
        for (const auto& x : got) have += x.slot == end;
        n_end += have;
        if (have != want)
          fail("end " + std::to_string(end) + ": " + std::to_string(have) + " contacts, want " +
               std::to_string(want) + ": " + describe(got));
      }
    }
  }
  std::printf("random rods: %d middle and %d end contacts checked\n", n_middle, n_end);
  EXPECT_GT(n_middle, 100);
  EXPECT_GT(n_end, 100);
  EXPECT_EQ(failures, 0) << "first: " << first;
}

// The contacts of a rod moved in small steps change continuously: the weighted sum of the
// overlaps (what a linear spring would push with) moves by no more than its slope allows, where
// an end slides onto or off a box's top over its edge (level and tilted), and where the free end
// of a rod lying across a shallow ridge reaches the far face. A contact that appeared or vanished
// at full overlap would jump by delta (0.01 here) in one step.
TEST(TriangleMeshCapsule, ContactsChangeContinuouslyAsARodSlides) {
  struct Path {
    const char* name;
    TriangleMesh mesh;
    Vec3 p0, p1, step;
    int n;
  };
  const double r = 0.05;
  const std::vector<Path> paths{
      {"level over a cube's edge",
       unit_cube(),
       {0.5, 0.5, 1.04},
       {0.9, 0.5, 1.04},
       {1e-4, 0, 0},
       8000},
      {"tilted over a cube's edge",
       unit_cube(),
       {0.5, 0.5, 1.045},
       {0.9, 0.5, 1.035},
       {1e-4, 0, 0},
       8000},
      {"tilted the other way",
       unit_cube(),
       {0.5, 0.5, 1.035},
       {0.9, 0.5, 1.045},
       {1e-4, 0, 0},
       8000},
      {"across a shallow ridge",
       two_strips(-0.05),
       {0.5, -0.3, 0.045},
       {0.5, -0.1, 0.045},
       {0, 1e-4, 0},
       4000},
  };
  for (const auto& path : paths) {
    double last = -1, worst = 0;
    int last_count = 0, changes = 0;
    for (int k = 0; k <= path.n; ++k) {
      const Vec3 d = static_cast<double>(k) * path.step;
      const auto got = axis_contacts(path.mesh, path.p0 + d, path.p1 + d, r);
      double push = 0;
      for (const auto& c : got) push += c.weight * std::max(0.0, -c.gap);
      if (k > 0) worst = std::max(worst, std::abs(push - last));
      changes += k > 0 && static_cast<int>(got.size()) != last_count;
      last = push;
      last_count = static_cast<int>(got.size());
    }
    // Ramps over r = 0.05 of overlaps of 0.01, steps of 1e-4: 2e-5 per step; the overlap of an
    // end moving over an edge changes faster (its gap follows the edge's corner): 1e-4.
    std::printf("%s: %d changes of the contact count, largest step of the push %.3g\n", path.name,
                changes, worst);
    EXPECT_GT(changes, 0) << path.name;
    EXPECT_LT(worst, 2e-4) << path.name;
  }
}

// segment_distance (the wall list's test for spherocylinders) against the distance sampled along
// the segment: never above the sampled minimum, and below it by no more than the sampling step
// (the distance is 1-Lipschitz along the segment); zero for a segment piercing a triangle.
TEST(TriangleMeshCapsule, SegmentDistanceMatchesSampling) {
  const TriangleMesh m = bumpy(4, 0.3, 41);
  std::mt19937_64 g(42);
  std::uniform_real_distribution<double> u(0, 1);
  int failures = 0;
  std::string first;
  constexpr int n_s = 2000;
  for (int k = 0; k < 300; ++k) {
    const auto t = static_cast<std::int32_t>(k % static_cast<int>(m.size()));
    const Vec3 p0{-0.2 + 1.4 * u(g), -0.2 + 1.4 * u(g), -0.3 + 0.9 * u(g)};
    const Vec3 p1 = p0 + 0.4 * Vec3{u(g) - 0.5, u(g) - 0.5, u(g) - 0.5};
    const double d = m.segment_distance(t, p0, p1);
    double sampled = 1e300;
    for (int j = 0; j <= n_s; ++j)
      sampled = std::min(sampled, m.distance(t, p0 + (double(j) / n_s) * (p1 - p0)));
    const double step = norm(p1 - p0) / n_s;
    if ((d > sampled + 1e-12 || d < sampled - step) && failures++ == 0)
      first = "triangle " + std::to_string(t) + ": " + std::to_string(d) + " against sampled " +
              std::to_string(sampled);
  }
  EXPECT_EQ(failures, 0) << first;
  // Through the middle of the flat unit square's first triangle.
  const TriangleMesh sq = square_grid(1, false);
  EXPECT_EQ(sq.segment_distance(0, {0.7, 0.2, -0.5}, {0.7, 0.2, 0.5}), 0.0);
  EXPECT_NEAR(sq.segment_distance(0, {0.7, 0.2, 0.1}, {0.7, 0.2, 0.5}), 0.1, 1e-15);
}
