// SPDX-License-Identifier: GPL-3.0-or-later
// Force loop over the half Verlet list. When every material pair uses the same law the loop is
// instantiated for that law alone (no dispatch per contact); otherwise a switch per contact.
#include "contact/pair_forces.hpp"

#include <algorithm>
#include <array>

#include "contact/batch_columns.hpp"
#include "contact/registry.hpp"
#include "contact/row_loop.hpp"
#include "core/exec.hpp"

namespace gf::contact {

namespace {

/// Displacement x_i - x_j: the minimum image only when some axis is periodic, the Lees-Edwards
/// shift only in a sheared box (the periodic loop of other runs stays as it was).
template <bool Periodic, bool Sheared>
inline Vec3 pair_delta(const Domain& dom, const Vec3& a, const Vec3& b) {
  if constexpr (Sheared)
    return dom.delta(a, b);
  else if constexpr (Periodic)
    return dom.min_image(a - b);
  else
    return a - b;
}

/// The force loop over the rows of the half list. The narrow phase is sphere_sphere
/// (pair_forces.hpp) inlined by hand: one reciprocal instead of three divisions for the normal,
/// the minimum image only in periodic domains, the per-row values (x_i, r_i, the row of the
/// material-pair table) loaded once per row. The row is inlined into the slab loop so that the
/// array pointers stay in registers. Without rolling friction in any pair (Rolling = false) the
/// law's rolling torque is zero and is left out of the torque sums.
template <bool Periodic, bool Sheared, bool Rolling, bool Report, class Eval>
std::int64_t pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                       const PairTable<PairCoeffs>& pairs, double dt, const ContactSink* report,
                       Eval&& eval) {
  const Vec3* const x = p.x();
  const Vec3* const v = p.v();
  const Vec3* const om = p.omega();
  Vec3* const f = p.f();
  Vec3* const tq = p.torque();
  const double* const r = p.radius();
  const double* const m = p.mass();
  const std::int32_t* const fixed = p.fixed();  // null: no fixed grains
  const std::int32_t* const mat = p.material();
  const std::int64_t* const off = list.offsets().data();
  const std::int32_t* const nb = list.neighbors().data();
  Vec3* const hist = list.history().data();
  const PairCoeffs* const coeffs = pairs.data();
  const std::size_t n_mat = static_cast<std::size_t>(pairs.n());
  const Domain dom = domain;
  const ContactSink sink = report ? *report : ContactSink{};
  auto row = [ =, &eval ](std::int64_t i) __attribute__((always_inline))->std::int64_t {
    const Vec3 xi = x[i];
    const double ri = r[i];
    const double mi = m[i];
    const bool fixed_i = fixed != nullptr && fixed[i] != 0;
    const PairCoeffs* const c_row = coeffs + static_cast<std::size_t>(mat[i]) * n_mat;
    std::int64_t touching = 0;
    Vec3 fi{}, ti{};
    const std::int64_t end = off[i + 1];
    for (std::int64_t k = off[i]; k < end; ++k) {
      const std::int32_t j = nb[k];
      const Vec3 d = pair_delta<Periodic, Sheared>(dom, xi, x[j]);
      const double rj = r[j];
      const double rs = ri + rj;
      const double dist2 = norm2(d);
      if (dist2 >= rs * rs) {
        hist[k] = {};
        continue;
      }
      ++touching;
      double arm_i, arm_j;
      ContactKinematics kin = touching_spheres(d, dist2, ri, rj, arm_i, arm_j);
      kin.m_eff = reduced_mass(mi, m[j], fixed_i, fixed != nullptr && fixed[j] != 0);
      Vec3 vj = v[j];
      if constexpr (Sheared) vj += dom.image_velocity(xi, x[j]);
      kin.v_rel = v[i] - vj - cross(arm_i * om[i] + arm_j * om[j], kin.normal);
      kin.omega_rel = om[i] - om[j];
      const ContactResult res = eval(c_row[mat[j]], kin, dt, hist[k]);
      const Vec3 nxf = cross(kin.normal, res.force);
      fi += res.force;
      f[j] -= res.force;
      if constexpr (Report)
        sink.add(k, static_cast<std::int32_t>(i), j, xi, d, kin.normal, xi - arm_i * kin.normal,
                 res.force, kin.overlap);
      if constexpr (Rolling) {
        ti += res.rolling_torque - arm_i * nxf;
        tq[j] -= res.rolling_torque + arm_j * nxf;
      } else {
        ti -= arm_i * nxf;
        tq[j] -= arm_j * nxf;
      }
    }
    f[i] += fi;
    tq[i] += ti;
    return touching;
  };
  return for_rows_in_slabs(list, row);
}

/// The touching contacts of a run of rows, in structure-of-arrays form, so that the contact law
/// runs as a loop over contacts the compiler vectorises (the per-entry loop of a row is short,
/// ~4.5 entries, and half of its touch tests go either way at random: as branches they are
/// mispredicted about half the time). Lives on the stack of the thread that fills it (~45 KiB).
struct ContactBatch {
  static constexpr int cap = 128;
  std::int32_t i[cap], j[cap];
  std::int64_t k[cap];
  VecColumns<cap> d;     // x_i - x_j
  VecColumns<cap> hist;  // tangential history, in and out
  // gathered per contact: radii, masses, v_i - v_j, omega_i, omega_j
  double ri[cap], rj[cap], mi[cap], mj[cap];
  VecColumns<cap> dv, om_i, om_j;
  CoeffColumns<cap> coeffs;  // gathered only when there is more than one material
  VecColumns<cap> f;         // force on i (j gets the opposite)
  VecColumns<cap> t_i;       // torque on i
  VecColumns<cap> t_j;       // minus the torque on j
};

/// Forces of the n contacts of a batch: the kinematics of the row loop (pair_loop) with fewer
/// divisions, the same law; one contact per iteration from contiguous arrays, no branch (the laws
/// are written with selects) and no loop-carried dependence, so each iteration is a vector lane.
/// Cohesive: the law's cohesion slot is evaluated (runs where some pair has k_c > 0).
template <class Law, bool Rolling, bool OneType, bool Cohesive>
__attribute__((always_inline)) inline void batch_body(ContactBatch& b, int n,
                                                      const PairCoeffs& c_in, double dt) {
  const PairCoeffs c0 = c_in;  // a local copy: no aliasing with the batch's stores
  for (int c = 0; c < n; ++c) {
    const double ri = b.ri[c];
    const double rj = b.rj[c];
    const double rs = ri + rj;
    const Vec3 d = b.d.get(c);
    ContactKinematics kin;
    const double dist = std::sqrt(norm2(d));
    kin.overlap = rs - dist;
    const double arm_i = ri - 0.5 * kin.overlap;
    const double arm_j = rj - 0.5 * kin.overlap;
    const double mi = b.mi[c];
    const double mj = b.mj[c];
    const double ms = mi + mj;
    // 1/|d|, R* = r_i r_j / (r_i + r_j) and m* = m_i m_j / (m_i + m_j) from one division: the
    // divider (sqrt and division share it) is what limits the vectorised loop.
    const double dist_or_1 = dist > 0 ? dist : 1.0;
    const double q = 1.0 / (dist_or_1 * rs * ms);
    kin.normal = dist > 0 ? (rs * ms * q) * d : Vec3{0, 0, 1};
    kin.r_eff = ri * rj * ms * (dist_or_1 * q);
    if constexpr (Cohesive) kin.inv_r_sum = ms * (dist_or_1 * q);  // 1 / (r_i + r_j)
    // A fixed grain is gathered with mass 0, standing for an infinite one (reduced_mass): m* is
    // then the free grain's mass, m_i + m_j. (A select: every lane computes both.)
    const bool free_pair = mi > 0 && mj > 0;
    kin.m_eff = free_pair ? mi * mj * rs * (dist_or_1 * q) : ms;
    const Vec3 omi = b.om_i.get(c);
    const Vec3 omj = b.om_j.get(c);
    kin.v_rel = b.dv.get(c) - cross(arm_i * omi + arm_j * omj, kin.normal);
    kin.omega_rel = omi - omj;
    Vec3 h = b.hist.get(c);
    // One material pair: the loop-invariant c0; otherwise the gathered constants.
    const PairCoeffs cc = OneType ? c0 : b.coeffs.get(c, c0.model);
    const ContactResult res = Law::template evaluate<Cohesive>(cc, kin, dt, h);
    b.hist.set(c, h);
    const Vec3 nxf = cross(kin.normal, res.force);
    Vec3 ti = -arm_i * nxf;
    Vec3 tj = arm_j * nxf;
    if constexpr (Rolling) {
      ti += res.rolling_torque;
      tj += res.rolling_torque;
    }
    b.f.set(c, res.force);
    b.t_i.set(c, ti);
    b.t_j.set(c, tj);
  }
}

// The batch loop built twice: for AVX2 (4 lanes), chosen at run time where the CPU has it, and
// for the baseline x86-64 of the build (2 lanes of SSE2). No FMA in either, and the vector
// add/mul/div/sqrt round exactly as the scalar ones, so both give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
template <class Law, bool Rolling, bool OneType, bool Cohesive>
__attribute__((target("avx2"), noinline, flatten)) void batch_avx2(ContactBatch& b, int n,
                                                                   const PairCoeffs& c0,
                                                                   double dt) {
  batch_body<Law, Rolling, OneType, Cohesive>(b, n, c0, dt);
}
inline bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#endif
using BatchKernel = void (*)(ContactBatch&, int, const PairCoeffs&, double);
template <class Law, bool Rolling, bool OneType, bool Cohesive>
__attribute__((noinline, flatten)) void batch_default(ContactBatch& b, int n, const PairCoeffs& c0,
                                                      double dt) {
  batch_body<Law, Rolling, OneType, Cohesive>(b, n, c0, dt);
}

/// The batch kernel for law Law (AVX2 where the CPU has it), with or without rolling friction,
/// for one material pair or several. With cohesion (some pair has k_c > 0) one kernel serves
/// all: rolling on (a zero coefficient gives a zero torque) and the pair constants gathered
/// (the caller then runs the loop with OneType = false).
bool baseline_only = false;  // use_baseline_kernels

template <class Law>
BatchKernel batch_kernel(bool rolling, bool one_type, bool cohesive) {
  auto pick = [&]<bool Rolling, bool OneType, bool Cohesive = false>()->BatchKernel {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
    if (avx2_kernels()) return batch_avx2<Law, Rolling, OneType, Cohesive>;
#endif
    return batch_default<Law, Rolling, OneType, Cohesive>;
  };
  if (cohesive) return pick.template operator()<true, false, true>();
  if (rolling)
    return one_type ? pick.template operator()<true, true>()
                    : pick.template operator()<true, false>();
  return one_type ? pick.template operator()<false, true>()
                  : pick.template operator()<false, false>();
}

/// The force loop for one law: rows are scanned for touching pairs (branch-free: every entry is
/// written to the batch, the count advances only for a touching one), the particle data of the
/// touching ones gathered, the histories of the scanned entries cleared, the batch's forces
/// computed by `compute` in one vectorised loop, then added to the particles (and the touching
/// histories written back, and the contacts reported) in the order of the list, so that the sums
/// do not depend on the thread count. Geometry: minimum image when some axis is periodic
/// (Periodic), Lees-Edwards images and their velocities (Sheared).
template <bool Periodic, bool Sheared, bool Report, bool OneType>
std::int64_t batched_pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                               const PairTable<PairCoeffs>& pairs, double dt,
                               const ContactSink* report, BatchKernel compute) {
  const Vec3* const x = p.x();
  Vec3* const f = p.f();
  Vec3* const tq = p.torque();
  const double* const r = p.radius();
  const std::int64_t* const off = list.offsets().data();
  const std::int32_t* const nb = list.neighbors().data();
  Vec3* const hist = list.history().data();
  const Domain dom = domain;
  const Vec3* const v = p.v();
  const Vec3* const om = p.omega();
  const double* const m = p.mass();
  const std::int32_t* const fixed = p.fixed();  // null: no fixed grains
  const std::int32_t* const mat = p.material();
  const PairCoeffs* const coeffs = pairs.data();
  const std::size_t n_mat = static_cast<std::size_t>(pairs.n());
  const PairCoeffs c0 = coeffs[0];
  const ContactSink sink = report ? *report : ContactSink{};
  // The batch holds the touching entries among the list entries [k_lo, k_hi).
  // Not inlined into the scan: the scan's loop then keeps its pointers in registers.
  auto flush = [=](ContactBatch & b, int n, std::int64_t k_lo, std::int64_t k_hi)
      __attribute__((noinline)) {
    for (int c = 0; c < n; ++c) {  // gather
      const std::int32_t i = b.i[c];
      const std::int32_t j = b.j[c];
      b.hist.set(c, hist[b.k[c]]);
      b.ri[c] = r[i];
      b.rj[c] = r[j];
      b.mi[c] = m[i];
      b.mj[c] = m[j];
      if (fixed != nullptr) {
        // A fixed grain's mass is infinite for the contact law (reduced_mass): gathered as 0,
        // which batch_body reads as such. (Two fixed grains are never listed.)
        if (fixed[j] != 0)
          b.mj[c] = 0;
        else if (fixed[i] != 0)
          b.mi[c] = 0;
      }
      Vec3 vj = v[j];
      if constexpr (Sheared) vj += dom.image_velocity(x[i], x[j]);
      b.dv.set(c, v[i] - vj);
      b.om_i.set(c, om[i]);
      b.om_j.set(c, om[j]);
      if constexpr (!OneType)
        b.coeffs.set(c, coeffs[static_cast<std::size_t>(mat[i]) * n_mat + mat[j]]);
    }
    // Pairs that are apart lose their history; the touching ones get theirs back below.
    std::fill(hist + k_lo, hist + k_hi, Vec3{});
    compute(b, n, c0, dt);
    for (int c = 0; c < n; ++c) {  // scatter, in list order
      const std::int32_t i = b.i[c];
      const std::int32_t j = b.j[c];
      const Vec3 fc = b.f.get(c);
      f[i] += fc;
      f[j] -= fc;
      tq[i] += b.t_i.get(c);
      tq[j] -= b.t_j.get(c);
      hist[b.k[c]] = b.hist.get(c);
      if constexpr (Report) {
        const Vec3 d = b.d.get(c);
        const double dist = norm(d);  // the normal as the batch's kernel takes it
        const Vec3 unit = dist > 0 ? (1.0 / dist) * d : Vec3{0, 0, 1};
        const double overlap = r[i] + r[j] - dist;
        sink.add(b.k[c], i, j, x[i], d, unit, x[i] - (r[i] - 0.5 * overlap) * unit, fc, overlap);
      }
    }
  };
  return for_slab_ranges(list, [=](std::int64_t begin, std::int64_t end) -> std::int64_t {
    // Local copies of the captures: the batch's stores could alias the closure's members, which
    // would reload every pointer at every list entry.
    const Vec3* const xs = x;
    const double* const rad = r;
    const std::int64_t* const offs = off;
    const std::int32_t* const nbs = nb;
    Vec3* const hs = hist;
    const Domain dl = dom;
    ContactBatch b;
    int n = 0;
    std::int64_t touching = 0;
    std::int64_t k_lo = offs[begin];
    for (std::int64_t i = begin; i < end; ++i) {
      const Vec3 xi = xs[i];
      const double ri = rad[i];
      const std::int64_t row_end = offs[i + 1];
      for (std::int64_t k = offs[i]; k < row_end; ++k) {
        const std::int32_t j = nbs[k];
        const Vec3 d = pair_delta<Periodic, Sheared>(dl, xi, xs[j]);
        const double rs = ri + rad[j];
        // The gather reads only the touching entries' histories: too sparse for the hardware
        // prefetcher, so each entry's line is requested here (measured: the gather's largest
        // stall without it).
        __builtin_prefetch(hs + k);
        b.i[n] = static_cast<std::int32_t>(i);
        b.j[n] = j;
        b.k[n] = k;
        b.d.set(n, d);
        n += norm2(d) < rs * rs;
        if (n == ContactBatch::cap) {
          flush(b, n, k_lo, k + 1);
          touching += n;
          n = 0;
          k_lo = k + 1;
        }
      }
    }
    flush(b, n, k_lo, offs[end]);
    return touching + n;
  });
}

/// batched_pair_loop for law M, with the geometry, report and material choices made once.
template <class M>
std::int64_t batched_pair_forces(ParticleStore& p, const Domain& domain, VerletList& list,
                                 const PairTable<PairCoeffs>& pairs, double dt,
                                 const ContactSink* report) {
  const bool rolling = any_rolling_friction(pairs);
  const bool cohesive = any_cohesion(pairs);
  const bool one = pairs.n() == 1 && !cohesive;  // (the cohesive kernel gathers the constants)
  const BatchKernel kernel = batch_kernel<typename M::Law>(rolling, one, cohesive);
  auto go = [&]<bool Periodic, bool Sheared>() {
    auto go2 = [&]<bool Report>() {
      return one ? batched_pair_loop<Periodic, Sheared, Report, true>(p, domain, list, pairs, dt,
                                                                      report, kernel)
                 : batched_pair_loop<Periodic, Sheared, Report, false>(p, domain, list, pairs, dt,
                                                                       report, kernel);
    };
    return report ? go2.template operator()<true>() : go2.template operator()<false>();
  };
  if (domain.sheared()) return go.template operator()<true, true>();
  if (domain.any_periodic()) return go.template operator()<true, false>();
  return go.template operator()<false, false>();
}

template <bool Periodic, bool Sheared, class Eval>
std::int64_t pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                       const PairTable<PairCoeffs>& pairs, double dt, bool rolling,
                       const ContactSink* report, Eval&& eval) {
  if (report)
    return rolling
               ? pair_loop<Periodic, Sheared, true, true>(p, domain, list, pairs, dt, report, eval)
               : pair_loop<Periodic, Sheared, false, true>(p, domain, list, pairs, dt, report,
                                                           eval);
  return rolling
             ? pair_loop<Periodic, Sheared, true, false>(p, domain, list, pairs, dt, report, eval)
             : pair_loop<Periodic, Sheared, false, false>(p, domain, list, pairs, dt, report, eval);
}

template <class Eval>
std::int64_t pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                       const PairTable<PairCoeffs>& pairs, double dt, const ContactSink* report,
                       Eval&& eval) {
  const bool rolling = any_rolling_friction(pairs);
  if (domain.sheared())
    return pair_loop<true, true>(p, domain, list, pairs, dt, rolling, report, eval);
  if (domain.any_periodic())
    return pair_loop<true, false>(p, domain, list, pairs, dt, rolling, report, eval);
  return pair_loop<false, false>(p, domain, list, pairs, dt, rolling, report, eval);
}

}  // namespace

bool uniform_model(const PairTable<PairCoeffs>& pairs, int& model) {
  model = -1;
  for (int a = 0; a < pairs.n(); ++a)
    for (int b = 0; b < pairs.n(); ++b) {
      const int mm = pairs(a, b).model;
      if (mm < 0) continue;
      if (model >= 0 && mm != model) return false;
      model = mm;
    }
  return model >= 0;
}

bool any_rolling_friction(const PairTable<PairCoeffs>& pairs) {
  for (int a = 0; a < pairs.n(); ++a)
    for (int b = 0; b < pairs.n(); ++b)
      if (pairs(a, b).rolling_friction != 0) return true;
  return false;
}

bool any_cohesion(const PairTable<PairCoeffs>& pairs) {
  for (int a = 0; a < pairs.n(); ++a)
    for (int b = 0; b < pairs.n(); ++b)
      if (pairs(a, b).model >= 0 && pairs(a, b).cohesion > 0) return true;
  return false;
}

void use_baseline_kernels(bool on) {
  baseline_only = on;
}

bool avx2_kernels() {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
  return !baseline_only && cpu_has_avx2();
#else
  return false;
#endif
}

std::int64_t compute_pair_forces(ParticleStore& p, const Domain& domain, VerletList& list,
                                 const PairTable<PairCoeffs>& pairs, double dt,
                                 const ContactSink* report) {
  int model;
  if (uniform_model(pairs, model)) {
    return dispatch_index(ContactModels{}, model, [&]<class M>() {
      return batched_pair_forces<M>(p, domain, list, pairs, dt, report);
    });
  }
  return pair_loop(p, domain, list, pairs, dt, report,
                   [](const PairCoeffs& c, const ContactKinematics& k, double h, Vec3& xi) {
                     return dispatch_index(ContactModels{}, c.model, [&]<class M>() {
                       return M::Law::evaluate(c, k, h, xi);
                     });
                   });
}

}  // namespace gf::contact
