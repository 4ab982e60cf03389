// SPDX-License-Identifier: GPL-3.0-or-later
// Fluid fraction from deposited solid volume.
#include "coupling/cfd_dem/fluid_fraction.hpp"

#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "core/exec.hpp"

namespace gf::cfd_dem {

void deposit_solid_volume(const Footprints& fp, std::span<double> solid) {
  deposit(fp, std::span<const double>(fp.volume), solid);
}

void deposit_solid_volume(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                          std::span<double> solid, DepositScratch* scratch) {
  Footprints local;
  Footprints& fp = scratch ? *scratch : local;
  compute_footprints(g, p, scheme, fp);  // checks the geometry before the volumes read it
  deposit_solid_volume(fp, solid);
}

FluidFractionStats fluid_fraction_from_solid(const fluid::Grid& g, std::span<const double> solid,
                                             double min_fraction, std::span<double> eps) {
  REQUIRE(min_fraction > 0.0 && min_fraction <= 1.0,
          "fluid fraction: min_fraction = {} is outside (0, 1]", min_fraction);
  REQUIRE(solid.size() == eps.size() && static_cast<std::int64_t>(eps.size()) == g.cell_count(),
          "fluid fraction: {} solid and {} eps values for {} cells", solid.size(), eps.size(),
          g.cell_count());
  const double inv_cell = 1.0 / g.cell_volume();
  FluidFractionStats st;
  // Serial: one pass over cells, cheap next to the deposit, and the sums are then in cell order.
  for (std::size_t c = 0; c < eps.size(); ++c) {
    const double vs = solid[c];
    const double e = 1.0 - vs * inv_cell;
    st.solid_volume += vs;
    st.min_unclamped = std::min(st.min_unclamped, e);
    if (e < min_fraction) {
      eps[c] = min_fraction;
      ++st.n_clamped;
    } else {
      eps[c] = e;
    }
  }
  return st;
}

FluidFractionStats fluid_fraction(const fluid::Grid& g, const Footprints& fp, double min_fraction,
                                  std::span<double> eps) {
  REQUIRE(static_cast<std::int64_t>(eps.size()) == g.cell_count(),
          "fluid fraction: {} values for {} cells", eps.size(), g.cell_count());
  std::fill(eps.begin(), eps.end(), 0.0);
  deposit_solid_volume(fp, eps);
  return fluid_fraction_from_solid(g, eps, min_fraction, eps);
}

FluidFractionStats fluid_fraction(const fluid::Grid& g, const ParticleGeometry& p,
                                  const FluidFractionOptions& options, std::span<double> eps,
                                  DepositScratch* scratch) {
  REQUIRE(static_cast<std::int64_t>(eps.size()) == g.cell_count(),
          "fluid fraction: {} values for {} cells", eps.size(), g.cell_count());
  Footprints local;
  Footprints& fp = scratch ? *scratch : local;
  compute_footprints(g, p, options.scheme, fp);
  return fluid_fraction(g, fp, options.min_fraction, eps);
}

void fluid_fraction_rate_from_flux(const fluid::Grid& g, const Footprints& fp,
                                   std::span<const Vec3> v, std::span<double> rate,
                                   SolidFluxScratch& scratch) {
  const auto nc = static_cast<std::size_t>(g.cell_count());
  REQUIRE(v.size() == fp.size(), "solid flux: {} velocities for footprints of {}", v.size(),
          fp.size());
  REQUIRE(rate.size() == nc, "solid flux: {} rates for {} cells", rate.size(), nc);
  auto& vol_v = scratch.volume_velocity;
  auto& q = scratch.flux;
  vol_v.resize(v.size());
  q.resize(nc);
  exec::parallel_for(static_cast<exec::index_t>(v.size()),
                     [&](exec::index_t i) { vol_v[i] = fp.volume[i] * v[i]; });
  std::fill(q.begin(), q.end(), Vec3{});
  deposit(fp, std::span<const Vec3>(vol_v), q, 1.0 / g.cell_volume());
  const int dims = g.dimension == 2 ? 2 : 3;
  exec::parallel_for(static_cast<exec::index_t>(nc), [&](exec::index_t c) {
    const std::array<int, 3> idx = g.cell_coords(c);
    double div = 0.0;
    for (int a = 0; a < dims; ++a) {
      for (int side : {-1, 1}) {  // the lower and the upper face of the cell along a
        std::array<int, 3> nb = idx;
        nb[a] += side;
        const bool inside = nb[a] >= 0 && nb[a] < g.n[a];
        if (!inside && !g.periodic[a]) continue;  // a wall: no solid crosses it
        nb[a] = g.fold(a, nb[a]);
        div += side * 0.5 * (q[c][a] + q[g.index(nb[0], nb[1], nb[2])][a]) / g.h[a];
      }
    }
    rate[c] = div;  // d eps/dt = -d(1 - eps)/dt = div((1 - eps) v)
  });
}

}  // namespace gf::cfd_dem
