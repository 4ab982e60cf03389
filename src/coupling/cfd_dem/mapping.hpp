// SPDX-License-Identifier: GPL-3.0-or-later
// Particle <-> grid mapping of unresolved CFD-DEM: which cells a particle covers and with what
// weights (its "footprint"), the deposit of per-particle quantities onto cells (solid volume,
// reaction forces, implicit drag coefficients), and the interpolation of cell-centred fields to
// particle positions. Works on plain arrays, so it knows nothing of Simulation.
//
// Determinism: footprints are computed in parallel; the sums into cells are done in particle
// order, by cell ranges owned by one thread each, so every cell adds its contributions in the
// same order whatever the thread count (1 and N threads give bit-identical fields).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/vec3.hpp"
#include "coupling/cfd_dem/stencil.hpp"
#include "fluid/fv/grid.hpp"

namespace gf {
class ParticleStore;
}

namespace gf::cfd_dem {

/// How a particle's volume (or force) is spread over cells.
enum class DepositScheme {
  CentreInCell,  ///< everything into the cell containing the centre (jumps when it crosses)
  Divided,       ///< fixed sample points filling the body, each with its share (see below)
  Trilinear,     ///< the centre's trilinear stencil (the adjoint of `interpolate`)
  /// Divided's sample points, each spread over its trilinear stencil between cell centres: the
  /// weights are continuous, piecewise linear functions of the grains' positions (no steps as
  /// points cross faces), so their time derivative exists (footprint_rates).
  Smoothed,
};

/// The schemes' names in the case file (coupling.fluid_fraction), in the enum's order.
inline constexpr std::array<std::string_view, 4> kDepositSchemeNames = {"centre", "divided",
                                                                        "trilinear", "smoothed"};

/// The scheme of a name in kDepositSchemeNames; nullopt for any other.
inline std::optional<DepositScheme> deposit_scheme(std::string_view name) {
  for (std::size_t k = 0; k < kDepositSchemeNames.size(); ++k)
    if (kDepositSchemeNames[k] == name) return static_cast<DepositScheme>(k);
  return std::nullopt;
}

/// Whether the scheme's weights are continuous in the grains' positions, so that their time
/// derivative exists (footprint_rates; coupling.fluid_fraction_rate: derivative).
inline bool has_time_derivative(DepositScheme s) {
  return s == DepositScheme::Trilinear || s == DepositScheme::Smoothed;
}

/// Particles as plain arrays: spheres (half_length / axis empty) or spherocylinders.
struct ParticleGeometry {
  std::span<const Vec3> x;              ///< centres, m
  std::span<const double> radius;       ///< sphere radius, or the capsule's cap radius r, m
  std::span<const double> half_length;  ///< half the cylinder length l/2, m; empty: all spheres
  std::span<const Vec3> axis;           ///< unit axes (needed with half_length); else empty

  std::size_t size() const { return x.size(); }
  double half(std::size_t i) const { return half_length.empty() ? 0.0 : half_length[i]; }
  /// Body volume pi r^2 l + 4/3 pi r^3, m^3.
  double volume(std::size_t i) const;
};

/// Owns the arrays a ParticleStore view needs (cap radii, axes) between calls.
struct StoreGeometry {
  std::vector<double> radius, half_length;
  std::vector<Vec3> axis;
};

/// One grain of a store as the coupling sees it: cap radius (sphere radius), half cylinder
/// length (0 for a sphere) and unit axis (the orientation applied to e_z; e_z without shapes).
struct GrainShape {
  double radius = 0;
  double half_length = 0;
  Vec3 axis{0, 0, 1};
};
GrainShape grain_shape(const ParticleStore& store, std::size_t i);

/// View of a ParticleStore's spheres and spherocylinders (cap radius = bounding radius -
/// half_length; axis = orientation applied to e_z). Other shapes: gf::Error.
ParticleGeometry geometry_of(const ParticleStore& store, StoreGeometry& buffers);

/// One (cell, weight) pair of a footprint.
struct CellShare {
  std::int64_t cell;
  double weight;
};

/// The footprints of a set of particles, compacted: particle i's pairs are
/// shares[offsets[i] .. offsets[i + 1]), one per distinct cell (in no promised order: each
/// cell occurs once, so the order changes no deposit), weights summed per cell. Built by
/// `compute_footprints` and read by every deposit of one coupling step (the grains do not move in
/// between), so the sample points of the divided scheme (48+ per grain) are placed once per step,
/// not once per deposit, and a deposit adds one value per cell touched (a grain inside one cell: a
/// single pair). Memory: 16 bytes per pair + 16 per particle, plus one block's raw footprints (8192
/// grains). The buffers are kept between calls: a time loop allocates only while the counts grow.
struct Footprints {
  std::vector<CellShare> shares;
  std::vector<std::int64_t> offsets;  ///< n + 1 entries
  std::vector<double> volume;         ///< body volume per particle, m^3
  std::int64_t n_cells = 0;           ///< cells of the grid the footprints were built on
  double cell_volume = 0.0;           ///< m^3
  std::size_t size() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  // Block buffers of compute_footprints.
  std::vector<CellShare> raw;
  std::vector<std::int64_t> raw_offsets;
  std::vector<int> counts;
};
/// The name the deposit functions below take their reusable buffers by.
using DepositScratch = Footprints;

/// The divided scheme's sample points of the unit sphere (48 points of equal volume share):
/// 3 shells of equal volume x 4 polar bands of equal area (z split at 0 and +-1/2) x 4
/// azimuthal sectors (turned by a golden-ratio offset per shell and band). Each point is the
/// centroid of its piece, so the set's centre of volume is the sphere's. Spheres use this set
/// turned by a fixed rotation, so that no two points share a coordinate along x, y or z (a
/// sphere moving along an axis moves one point at a time across a face). As a quadrature of the
/// volume cut off by a plane it is within 0.1 V_p for every offset and direction tried (48
/// points; other layouts of 48-64 points tried gave 0.08-0.11).
std::span<const Vec3> sphere_sample_points();
/// The turned set a sphere's divided footprint uses (points c + r s, each weight 1/48).
std::span<const Vec3> turned_sphere_sample_points();

/// The divided scheme's points of a spherocylinder (frame: axis u and two normals): the
/// unturned sphere set split at its equator onto the two caps (shifted by +-l/2 along u), plus
/// the cylinder in n_seg = clamp(ceil(l / r), 1, 64) slabs, each of 8 thin sub-slabs with one
/// point each, at the sub-slab's mid-plane and one of the 8 centroids of the cross-section's
/// pieces (2 rings of equal area x 4 sectors); every point carries its share of the volume.
/// Returns n_seg (0 for a sphere).
int cylinder_slabs(double r, double half_length);

/// Throws gf::Error unless the geometry has one radius (> 0) per particle, one half length
/// (>= 0) and one unit axis per particle when half lengths are given, and the grid has cells.
void check_geometry(const fluid::Grid& g, const ParticleGeometry& p);

/// Number of (cell, weight) pairs of particle i under `scheme`.
int footprint_size(const fluid::Grid& g, const ParticleGeometry& p, std::size_t i,
                   DepositScheme scheme);
/// Writes particle i's footprint into out[0 .. footprint_size): weights sum to 1 (to round-off).
void footprint(const fluid::Grid& g, const ParticleGeometry& p, std::size_t i, DepositScheme scheme,
               CellShare* out);

/// Builds the compacted footprints of all particles under `scheme` into fp (checks the
/// geometry). With the divided scheme a grain whose bounding box lies inside one cell gets the
/// single pair (cell, 1) without placing its sample points: every point would fall there.
void compute_footprints(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                        Footprints& fp);

/// The time derivatives dw_pc/dt (1/s) of the Smoothed or Trilinear footprints (the others
/// move in steps: gf::Error) of grains moving at v (and, for spherocylinders, turning at
/// omega; empty: not turning), in the layout of Footprints (each particle's pairs sum to
/// zero; volume filled). A point at x moving at v_s changes its weights by grad(w) . v_s:
/// exact while the points stay between the same cell centres, so the deposited fraction
/// changes over a step by dt times the deposit of these rates up to O(dt^2) (the weights are
/// linear in each point's coordinates there). Sphere points translate with the sphere; a rod's
/// turn with its axis (the spin about it moves none); Trilinear's one point is the centre.
void footprint_rates(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                     std::span<const Vec3> v, std::span<const Vec3> omega, Footprints& rates);

/// compute_footprints(fp) and footprint_rates(rates) of a continuous scheme at once, bit for bit
/// the same results: with Smoothed each sample point is placed and its cells found once for
/// both (the separate calls walk the points twice).
void footprints_with_rates(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                           std::span<const Vec3> v, std::span<const Vec3> omega, Footprints& fp,
                           Footprints& rates);

/// per_cell[c] += scale * sum_p w_pc value[p] with footprints built by compute_footprints
/// (adds; the caller zeroes). value has one entry per particle, per_cell one per cell.
void deposit(const Footprints& fp, std::span<const double> value, std::span<double> per_cell,
             double scale = 1.0);
void deposit(const Footprints& fp, std::span<const Vec3> value, std::span<Vec3> per_cell,
             double scale = 1.0);

/// per_cell[c] += scale * sum_p w_pc value[p] (adds; the caller zeroes). per_cell has
/// g.cell_count() entries, value one per particle. Builds the footprints into *scratch (or a
/// local set): to deposit several quantities of the same particles, call compute_footprints
/// once and the overloads above.
void deposit(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
             std::span<const double> value, std::span<double> per_cell, double scale = 1.0,
             DepositScratch* scratch = nullptr);
/// Vector version (forces, beta v_p, ...).
void deposit(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
             std::span<const Vec3> value, std::span<Vec3> per_cell, double scale = 1.0,
             DepositScratch* scratch = nullptr);

/// The fluid's share of the particle-fluid forces: cell_force[c] -= sum_p w_pc force[p] (N per
/// cell; divide by the cell volume for a source density). Momentum is conserved: the sum over
/// cells equals minus the sum over particles to round-off.
void deposit_reaction_forces(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                             std::span<const Vec3> force, std::span<Vec3> cell_force,
                             DepositScratch* scratch = nullptr);

/// The particles' momentum source for the fluid in the semi-implicit form the fluid solver
/// takes, S = s_explicit - k u (src/fluid/fv/navier_stokes.hpp): with the drag on particle p
/// F_p = beta_p (u_f - v_p), the fluid receives -F_p = beta_p v_p - beta_p u_f, spread with the
/// footprint weights w_pc, so k_c = sum_p w_pc beta_p / V_c [kg/(m^3 s)] and s_explicit_c =
/// sum_p w_pc beta_p v_p / V_c [N/m^3]. Overwrites both (g.cell_count() entries each). For a
/// uniform u_f, sum_c (s_explicit_c - k_c u_f) V_c = -sum_p F_p to round-off.
void drag_exchange_source(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                          std::span<const double> beta, std::span<const Vec3> v,
                          std::span<Vec3> s_explicit, std::span<double> k,
                          DepositScratch* scratch = nullptr);
/// The same with footprints built by compute_footprints.
void drag_exchange_source(const Footprints& fp, std::span<const double> beta,
                          std::span<const Vec3> v, std::span<Vec3> s_explicit, std::span<double> k);
/// The consistent form for grains that read the fluid elsewhere than in the cells they are
/// deposited in (trilinear reads): u_seen[p] is the fluid velocity particle p's drag used,
/// read from cell_u. s_explicit_c = sum_p w_pc beta_p (v_p - u_seen_p) / V_c + K_c cell_u_c, so
/// S = s_explicit - K u is exactly -sum_p w_pc F_p at u = cell_u (the reaction of the drag the
/// grains felt) and still implicit in the change of u over the fluid step. The plain form
/// instead gives the fluid sum_p w_pc beta_p (v_p - u_c): a grain carried along at the
/// interpolated velocity (F_p = 0) would still push its cell towards its own velocity.
void drag_exchange_source(const Footprints& fp, std::span<const double> beta,
                          std::span<const Vec3> v, std::span<const Vec3> u_seen,
                          std::span<const Vec3> cell_u, std::span<Vec3> s_explicit,
                          std::span<double> k);

/// out[i] = cell-centred `field` interpolated (trilinear between cell centres, periodic wrap,
/// constant beyond the outermost centres at walls) to x[i].
void interpolate_to_points(const fluid::Grid& g, std::span<const double> field,
                           std::span<const Vec3> x, std::span<double> out);
void interpolate_to_points(const fluid::Grid& g, std::span<const Vec3> field,
                           std::span<const Vec3> x, std::span<Vec3> out);
/// How the grains read cell-centred fluid fields.
enum class PointRead {
  Trilinear,  ///< trilinear between cell centres (continuous as a grain crosses a face)
  CellValue,  ///< the value of the cell containing the point (steps at faces)
};

/// The compact stencils of the points x, for reading several fields at points that stay put
/// (a fluid step reads the fluid before and after it at the same grain positions).
void point_stencils(const fluid::Grid& g, std::span<const Vec3> x, std::span<LerpStencil> out,
                    PointRead read = PointRead::Trilinear);
/// Two fields at the points of stencils s (from point_stencils on grid g), one stencil read
/// for both (the coupling reads the fluid's velocity with its fraction or its pressure
/// gradient): bit-identical to interpolate_to_points at those points.
void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const Vec3> field_a, std::span<Vec3> out_a,
                    std::span<const double> field_b, std::span<double> out_b);
void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const Vec3> field_a, std::span<Vec3> out_a,
                    std::span<const Vec3> field_b, std::span<Vec3> out_b);
/// One field at the points of stencils s.
void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const Vec3> field, std::span<Vec3> out);
void interpolate_at(const fluid::Grid& g, std::span<const LerpStencil> s,
                    std::span<const double> field, std::span<double> out);

}  // namespace gf::cfd_dem
