// SPDX-License-Identifier: GPL-3.0-or-later
// The particle-particle force stage: narrow phase + contact law over the Verlet list.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "contact/laws/contact_io.hpp"
#include "core/domain.hpp"
#include "core/mat3.hpp"
#include "neighbor/verlet_list.hpp"
#include "particles/material.hpp"
#include "particles/particle_store.hpp"

namespace gf::contact {

/// Sphere-sphere narrow phase: kinematics of the contact of i with j, false if they do not touch.
/// `arm_i`, `arm_j` are the distances from the centres to the contact point, m.
GF_HOST_DEVICE inline bool sphere_sphere(const Domain& dom, const Vec3& xi, const Vec3& xj,
                                         double ri, double rj, ContactKinematics& k, double& arm_i,
                                         double& arm_j) {
  const Vec3 d = dom.delta(xi, xj);
  const double dist2 = norm2(d);
  const double rs = ri + rj;
  if (dist2 >= rs * rs) return false;
  const double dist = std::sqrt(dist2);
  k.overlap = rs - dist;
  k.normal = dist > 0 ? d / dist : Vec3{0, 0, 1};
  arm_i = ri - 0.5 * k.overlap;
  arm_j = rj - 0.5 * k.overlap;
  k.r_eff = ri * rj / rs;
  k.inv_r_sum = 1.0 / rs;
  return true;
}

/// Kinematics of two touching spheres from d = x_i - x_j, dist2 = |d|^2 < (r_i + r_j)^2:
/// overlap, unit normal (from j to i), R*, 1/(r_i + r_j), and the distances arm_i, arm_j from
/// the centres to the contact point, m. m*, v_rel and omega_rel are the caller's. Shared by the
/// host's row loop and the device's force body (gpu/kernels.hpp), so that both compute the same
/// bits.
GF_HOST_DEVICE_INLINE ContactKinematics touching_spheres(const Vec3& d, double dist2, double ri,
                                                         double rj, double& arm_i, double& arm_j) {
  ContactKinematics kin;
  const double rs = ri + rj;
  const double dist = std::sqrt(dist2);
  kin.overlap = rs - dist;
  kin.normal = dist > 0 ? (1.0 / dist) * d : Vec3{0, 0, 1};
  arm_i = ri - 0.5 * kin.overlap;
  arm_j = rj - 0.5 * kin.overlap;
  kin.r_eff = ri * rj / rs;
  kin.inv_r_sum = 1.0 / rs;
  return kin;
}

/// Reduced mass m* of a contact, kg: m_i m_j / (m_i + m_j), the mass of the two-body relative
/// motion that the damping slot's critical damping 2 sqrt(m* S_n) refers to. A fixed grain (a
/// particle group with `fixed: true`: glued to an immobile base, never integrated) takes no part
/// in that motion: its mass counts as infinite (1/m = 0) and m* is the free grain's mass, so that
/// a grain hitting a fixed one rebounds with the requested restitution, as against a wall
/// (docs/models/fixed_particles.md). Two fixed grains never meet (the neighbour list leaves such
/// pairs out); the first one's mass is returned for them.
GF_HOST_DEVICE inline double reduced_mass(double mi, double mj, bool fixed_i, bool fixed_j) {
  return fixed_j ? mi : (fixed_i ? mj : mi * mj / (mi + mj));
}

/// One touching pair as the force loop saw it (output.contacts_csv): grains i and j (indices in
/// the store; i < 0 marks a list entry whose pair is apart), the contact point, the unit normal
/// (pointing from j to i), the force on i from j (j gets -force), the overlap and the branch
/// vector x_i - x_j to the image of j that touches i.
struct ContactRecord {
  std::int32_t i = -1, j = -1;
  Vec3 point, normal, force, branch;
  double overlap = 0;
};

/// What a force loop reports besides the forces, on the steps that ask for it:
/// - with `rows`, the contact virial W = sum over pairs of d (x) F (W[a][b] = d_a F_b,
///   d = x_i - x_j to the nearest image of j, F the force on i from j): rows[i] collects the
///   pairs of row i whose branch midpoint x_i - d/2 has coordinate `axis` in [lo, hi). The
///   collisional stress of a region of volume V is then sum_i rows[i] / V
///   (analysis/rheology.hpp). With `normals`, normals[i] also collects n (x) n of the same pairs
///   (n the unit contact normal; its trace counts the pairs): the contact fabric. `rows` (and
///   `normals`) hold n zeroed entries;
/// - with `contacts`, contacts[k] gets the record of neighbour-list entry k when its pair
///   touches (entries hold ContactRecord{} before the loop, whatever the region).
/// Row i's sums are written only by the thread of row i, records only at their own entry.
struct ContactSink {
  Mat3* rows = nullptr;
  Mat3* normals = nullptr;
  ContactRecord* contacts = nullptr;
  /// Per list entry: the overlap of each touching pair (spheres; entries apart are left as the
  /// caller set them), for heat conduction, which then needs no second pass over the list.
  double* overlaps = nullptr;
  int axis = 2;
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  GF_HOST_DEVICE bool counts(const Vec3& xi, const Vec3& d) const {
    const double c = xi[axis] - 0.5 * d[axis];
    return c >= lo && c < hi;
  }
  /// Reports the touching pair (i, j) of list entry k at position xi of i: branch d, unit
  /// normal n, contact point, force f on i, overlap.
  GF_HOST_DEVICE void add(std::int64_t k, std::int32_t i, std::int32_t j, const Vec3& xi,
                          const Vec3& d, const Vec3& n, const Vec3& point, const Vec3& f,
                          double overlap) const {
    if (rows != nullptr && counts(xi, d)) {
      rows[i] = rows[i] + outer(d, f);
      if (normals != nullptr) normals[i] = normals[i] + outer(n, n);
    }
    if (contacts != nullptr) contacts[k] = ContactRecord{i, j, point, n, f, d, overlap};
    if (overlaps != nullptr) overlaps[k] = overlap;
  }
};

/// Adds contact forces and torques of all touching pairs to f and torque; clears the history of
/// pairs that are apart. With Lees-Edwards images the relative velocity of a pair across the
/// gradient boundary includes the image's velocity. With `report`, also collects what it asks for
/// (virial, fabric, contact records: ContactSink).
/// Returns the number of touching pairs.
std::int64_t compute_pair_forces(ParticleStore& p, const Domain& domain, VerletList& list,
                                 const PairTable<PairCoeffs>& pairs, double dt,
                                 const ContactSink* report = nullptr);

/// True when every interacting material pair (model >= 0) uses one law; `model` gets it.
bool uniform_model(const PairTable<PairCoeffs>& pairs, int& model);
/// True when some material pair has rolling friction.
bool any_rolling_friction(const PairTable<PairCoeffs>& pairs);
/// True when some material pair has cohesion (k_c > 0): the vectorised kernels then include the
/// cohesion slot, which the others leave out.
bool any_cohesion(const PairTable<PairCoeffs>& pairs);

/// For tests: use the baseline (SSE2) batch kernel even where the CPU has AVX2, to check that
/// both give the same bits. Not for use while a force loop runs on another thread.
void use_baseline_kernels(bool on);
/// Whether the vectorised contact kernels run their AVX2 build (the CPU has it and
/// use_baseline_kernels is off); the wall loop asks too.
bool avx2_kernels();

}  // namespace gf::contact
