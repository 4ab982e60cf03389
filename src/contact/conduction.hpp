// SPDX-License-Identifier: GPL-3.0-or-later
// Heat conduction through the contacts of solid grains (heat: block of the case file).
//
// A contact of grains i and j at temperatures T_i, T_j carries the heat flow H (T_j - T_i) into
// i, W, with a conductance H (W/K) of the contact's geometry (overlap delta, effective radius
// R* = r_i r_j / (r_i + r_j); a wall counts as a grain of infinite radius) and of the two
// conductivities k_i, k_j (W/(m K)). The models differ in H:
//   - batchelor_obrien: the constriction of the heat flow through a circular contact of radius
//     a between two half-spaces (Holm; Batchelor & O'Brien 1977 for spheres, whose contact is
//     that of Hertz: a = sqrt(R* delta)): the two constriction resistances 1/(4 k a) in series,
//     H = 4 a / (1/k_i + 1/k_j) (= 2 k a for equal conductivities);
//   - intersection_area: H = 4 sqrt(A) / (1/k_i + 1/k_j) with A = pi a_g^2 the area of the
//     circle in which the undeformed spheres intersect, a_g^2 = 2 R* delta (to first order in
//     delta / R*): the form of LIGGGHTS' fix heat/gran/conduction, for side-by-side runs; it
//     gives sqrt(2 pi) = 2.51 times the conductance of batchelor_obrien.
// The grains' temperatures advance by explicit Euler steps, m c dT/dt = sum of the heat flows
// (Simulation::conduct_heat); no heat is exchanged with a fluid, and none is produced by
// friction or damping.
#pragma once

#include <cmath>
#include <span>
#include <string_view>
#include <vector>

#include "core/domain.hpp"
#include "core/host_device.hpp"
#include "core/registry.hpp"
#include "neighbor/verlet_list.hpp"
#include "particles/material.hpp"
#include "particles/particle_store.hpp"

namespace gf::contact {

struct BatchelorOBrien {
  static constexpr std::string_view key = "batchelor_obrien";
  static constexpr std::string_view summary =
      "contact conductance of the Hertz contact circle a = sqrt(R* delta): H = 4 a / (1/k_i + "
      "1/k_j)";
  static constexpr std::string_view equation =
      "Q_i = H (T_j - T_i),  H = 4 a / (1/k_i + 1/k_j),  a = sqrt(R* delta)";
  static constexpr std::string_view reference =
      "G. K. Batchelor, R. W. O'Brien, Thermal or electrical conduction through a granular "
      "material, Proc. R. Soc. Lond. A 355 (1977) 313-333";
  GF_HOST_DEVICE static double conductance(double overlap, double r_eff, double k_series) {
    return 4.0 * k_series * std::sqrt(r_eff * overlap);
  }
};

struct IntersectionArea {
  static constexpr std::string_view key = "intersection_area";
  static constexpr std::string_view summary =
      "conductance from the area A = 2 pi R* delta of the spheres' intersection circle: H = 4 "
      "sqrt(A) / (1/k_i + 1/k_j) (LIGGGHTS' form)";
  static constexpr std::string_view equation =
      "Q_i = H (T_j - T_i),  H = 4 sqrt(A) / (1/k_i + 1/k_j),  A = 2 pi R* delta";
  static constexpr std::string_view reference =
      "LIGGGHTS fix heat/gran/conduction (C. Kloss et al., Prog. Comput. Fluid Dyn. 12 (2012) "
      "140-152); the contact area of overlapping spheres as in Chaudhuri et al., Chem. Eng. Sci. "
      "61 (2006) 6348-6360";
  GF_HOST_DEVICE static double conductance(double overlap, double r_eff, double k_series) {
    constexpr double two_pi = 6.283185307179586;
    return 4.0 * k_series * std::sqrt(two_pi * r_eff * overlap);
  }
};

using ConductionModels = TypeList<BatchelorOBrien, IntersectionArea>;

/// The series conductivity of two materials, 1 / (1/k_i + 1/k_j), W/(m K): what the models take
/// (one number per material pair, computed once).
inline double series_conductivity(double k_i, double k_j) {
  return k_i * k_j / (k_i + k_j);
}

/// Conductance (W/K) of a contact by the model at index `model` of ConductionModels;
/// `k_series` = series_conductivity(k_i, k_j).
inline double contact_conductance(int model, double overlap, double r_eff, double k_series) {
  return dispatch_index(ConductionModels{}, model,
                        [&]<class M>() { return M::conductance(overlap, r_eff, k_series); });
}

struct ConductionInfo {
  std::string_view key, summary, equation, reference;
};
/// Every model of ConductionModels, in list order.
std::vector<ConductionInfo> conduction_infos();
/// Index in ConductionModels, or -1.
int conduction_index(std::string_view key);
const ConductionInfo* find_conduction(std::string_view key);

/// Adds the heat flows of the touching pairs of the list to q (W; H (T_j - T_i) to i, the
/// opposite to j) and their conductances to h (W/K, to both): `k_series` per material pair,
/// `temperature` per grain (K). Spheres and spherocylinders (3D). `entry_h`: scratch, the
/// conductance of each list entry (0 when apart) after the call; the sums are taken in list
/// order (the same bits at any thread count).
void pair_heat_flows(const ParticleStore& p, const Domain& domain, const VerletList& list,
                     int model, const PairTable<double>& k_series, const double* temperature,
                     double* q, double* h, std::vector<double>& entry_h);
/// The same for spheres from the overlap of each list entry that the force loop recorded
/// (ContactSink::overlaps; 0 when apart): no second pass over the neighbours' positions, and the
/// same bits as pair_heat_flows (the same overlaps, R* and order of the sums).
void pair_heat_flows_from_overlaps(const ParticleStore& p, const VerletList& list, int model,
                                   const PairTable<double>& k_series, const double* temperature,
                                   const double* overlaps, double* q, double* h);

}  // namespace gf::contact
