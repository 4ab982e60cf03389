// SPDX-License-Identifier: GPL-3.0-or-later
// Runs of the DEM steps on the CUDA back end (`grainflow run --device cuda`, docs/gpu.md): which
// cases it takes, setting it up from the simulation's state, and copying its state back.
#include <algorithm>

#include "gpu/sphere_dem.hpp"
#include "simulation/simulation.hpp"

namespace gf {

std::string Simulation::device_unsupported() const {
  if (two_d_) return "the case is 2D (the CUDA back end runs 3D cases)";
  if (particles_.has_shapes())
    return "the case has spherocylinders or polygons (the CUDA back end runs spheres)";
  if (gear_) return "integrator: gear5 (the CUDA back end integrates with velocity_verlet)";
  if (cfg_.shear || domain_.sheared()) return "the case has a shear: block";
  if (cfd_) return "the case has a fluid (CFD-DEM)";
  if (cfg_.analysis.rheology) return "the case has analysis.rheology";
  if (!inlets_.empty())
    return "the case has an inlet (the CUDA back end runs a fixed set of grains)";
  if (!cfg_.outlets.empty())
    return fmt::format("the case has outlets ('{}': the CUDA back end keeps every grain)",
                       cfg_.outlets.front().name);
  if (cfg_.heat) return "the case has a heat: block (heat conduction runs on the host only)";
  if (!cfg_.flow_meters.empty())
    return fmt::format("the case has flow meters ('{}': counted on the host only)",
                       cfg_.flow_meters.front().name);
  if (cfg_.output.contacts_csv.every > 0 || cfg_.output.contacts_vtk.every > 0)
    return "the case writes contacts (output.contacts_csv / contacts_vtk)";
  for (const auto& w : walls_) {
    if (w.kind == WallKind::Mesh)
      return fmt::format(
          "wall '{}' is a mesh (the CUDA back end takes planes, boxes and cylinders)", w.group);
    if (w.servo) return fmt::format("wall '{}' has a servo", w.group);
  }
  for (const auto& q : cfg_.output.quantities)
    if (q.starts_with("wall_torque_mean") || q.starts_with("wall_force_mean"))
      return fmt::format(
          "series quantity '{}' (device runs report the walls' force and torque of the step)", q);
  return {};
}

std::shared_ptr<gpu::SphereDem> Simulation::start_device(Device device) {
  gpu::SphereDemSetup s;
  s.domain = domain_;
  s.gravity = gravity_;
  s.dt = dt_;
  s.skin = skin_;
  s.pairs = pairs_;
  s.first_step = step_;
  for (const auto& m : fixed_motions_) s.fixed_motions.push_back(m.motion);
  for (const auto& w : walls_) {
    gpu::DeviceWall p;
    p.kind = w.kind;
    p.point0 = w.point0;
    p.dir0 = w.dir0;
    p.radius = w.radius;
    p.inside = w.inside;
    p.motion = w.motion;
    p.moves = w.motion.velocity != Vec3{} || w.motion.rate != 0;
    p.material = w.material;
    p.point = w.point;  // (where the host has placed it now)
    p.dir = w.dir;
    s.walls.push_back(p);
  }
  // The contact histories of the current state (after the constructor's force evaluation, or a
  // restart's).
  const auto off = nlist_.offsets();
  const auto nb = nlist_.neighbors();
  const auto h = nlist_.history();
  for (std::size_t i = 0; i + 1 < off.size(); ++i)
    for (auto k = off[i]; k < off[i + 1]; ++k)
      if (h[static_cast<std::size_t>(k)] != Vec3{})
        s.pair_history.push_back(gpu::HistoryEntry{static_cast<std::int32_t>(i),
                                                   nb[static_cast<std::size_t>(k)],
                                                   h[static_cast<std::size_t>(k)]});
  const auto we = wlist_.entries();
  const auto wh = wlist_.history();
  for (std::size_t k = 0; k < we.size(); ++k)
    if (wh[k] != Vec3{})
      s.wall_history.push_back(gpu::HistoryEntry{we[k].particle, we[k].wall, wh[k]});
  return std::make_shared<gpu::SphereDem>(
      particles_, s, device == Device::Cuda ? gpu::Backend::Cuda : gpu::Backend::HostMirror);
}

void Simulation::sync_from_device(const gpu::SphereDem& d, bool lists) {
  d.download(particles_);
  for (auto& w : walls_) w.update_geometry(time());  // (the device placed them likewise)
  n_contacts_ = d.n_contacts();
  n_wall_contacts_ = d.n_wall_contacts();
  const auto wf = d.wall_forces();
  const auto wt = d.wall_torques();
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    walls_[k].force = wf[k];
    walls_[k].torque = wt[k];
  }
  // A diverged run keeps its lists: the run reports the divergence before it writes anything
  // (run.cpp, check_finite), and non-finite grains would not be in the host's lists.
  if (!lists || first_non_finite_grain(particles_)) return;
  // The lists in the device's (= the store's) order, their histories the device's: a checkpoint
  // then continues bit-identically on either back end, and the elastic energy sums the right
  // pairs.
  const std::size_t n = particles_.size();
  // (two fixed grains never meet: as update_neighbors, the list leaves their pairs out)
  PairFilter filter;
  if (const std::int32_t* fixed = particles_.fixed())
    filter = [fixed](std::int32_t i, std::int32_t j) { return fixed[i] == 0 || fixed[j] == 0; };
  nlist_.build(domain_, particles_.x(), particles_.radius(), n, skin_, filter);
  auto hist = nlist_.history();
  std::fill(hist.begin(), hist.end(), Vec3{});
  const auto off = nlist_.offsets();
  const auto nb = nlist_.neighbors();
  for (const auto& e : d.pair_history()) {
    // The list's rows hold j > i, ascending.
    const auto first = nb.begin() + off[static_cast<std::size_t>(e.i)];
    const auto last = nb.begin() + off[static_cast<std::size_t>(e.i) + 1];
    const auto it = std::lower_bound(first, last, e.j);
    REQUIRE(it != last && *it == e.j, "device contact ({}, {}) is not in the neighbour list", e.i,
            e.j);
    hist[static_cast<std::size_t>(it - nb.begin())] = e.h;
  }
  wlist_.build(walls_, particles_.x(), particles_.radius(), n, skin_, {}, nullptr,
               particles_.fixed());
  auto wh = wlist_.history();
  std::fill(wh.begin(), wh.end(), Vec3{});
  const auto we = wlist_.entries();  // by grain, then wall
  for (const auto& e : d.wall_history()) {
    const auto it = std::lower_bound(we.begin(), we.end(), e, [](const auto& a, const auto& b) {
      return a.particle < b.i || (a.particle == b.i && a.wall < b.j);
    });
    REQUIRE(it != we.end() && it->particle == e.i && it->wall == e.j,
            "device wall contact (grain {}, wall {}) is not in the wall list", e.i, e.j);
    wh[static_cast<std::size_t>(it - we.begin())] = e.h;
  }
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    wall_point_at_build_[w] = walls_[w].point;
    wall_dir_at_build_[w] = walls_[w].dir;
  }
}

}  // namespace gf
