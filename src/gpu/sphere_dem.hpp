// SPDX-License-Identifier: GPL-3.0-or-later
// The CUDA back end of the sphere DEM step: the grains, their contact histories and the walls
// live on the GPU, which runs whole time steps (velocity Verlet, neighbour lists, contact laws)
// without the host; the host reads the state back only when it writes output.
//
// What it runs is the CPU step of Simulation for the same case: the same contact kernels
// (contact/laws, host/device), the same integrator, so the two agree to rounding (the order in
// which a grain's contact forces are summed differs). It takes the cases of spheres with
// velocity Verlet, any contact models of the registry (rolling resistance and cohesion
// included), plane, box and cylinder walls, fixed or with prescribed rigid motion, fixed groups
// (at rest or with a prescribed motion), gravity, and periodic axes; the Simulation refuses the
// others before it starts (Simulation::device_unsupported).
//
// The CUDA back end is built with -DGF_ENABLE_CUDA=ON (CMake preset `cuda`). Every build has the
// host mirror: the same orchestration and per-grain bodies (engine.hpp, kernels.hpp) run in
// plain loops on the host, so that the device's algorithm is tested against the host step
// where no GPU is (tests/unit/test_device_engine.cpp). This header is plain C++.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "boundaries/motion.hpp"
#include "boundaries/wall_surface.hpp"
#include "contact/laws/contact_io.hpp"
#include "core/domain.hpp"
#include "particles/material.hpp"
#include "particles/particle_store.hpp"

namespace gf::gpu {

/// Whether this build has the CUDA back end (GF_ENABLE_CUDA).
bool cuda_built();
/// Whether this build has the CUDA back end and a device is there; `why` gets the reason when
/// not (no CUDA in the build, no device, a driver error).
bool device_available(std::string* why = nullptr);

/// Where a SphereDem runs: the CUDA device, or the host mirror of the device's algorithm.
enum class Backend { Cuda, HostMirror };

namespace detail {
class EngineBase;
}

/// A plane or cylinder wall (as boundaries/wall.hpp's Wall): at time t its point is
/// motion.point_at(point0, t) and its direction (a plane's unit normal towards the grains, a
/// cylinder's unit axis) motion.rotate(dir0, t); `point` and `dir` hold the current ones (set by
/// the engine each step when the wall moves).
struct DeviceWall {
  WallKind kind = WallKind::Plane;
  Vec3 point0, dir0;
  double radius = 0;   ///< cylinder, m
  bool inside = true;  ///< cylinder: the grains are inside
  RigidMotion motion;
  bool moves = false;
  int material = 0;
  Vec3 point, dir;
};

/// The tangential history of a touching pair (i, j) as i sees it (j's is its negative), or of
/// grain i against wall `j` (an index into SphereDemSetup::walls).
struct HistoryEntry {
  std::int32_t i = 0, j = 0;
  Vec3 h;
};

struct SphereDemSetup {
  Domain domain;
  Vec3 gravity;
  double dt = 0;                ///< s
  std::int64_t first_step = 0;  ///< the step the run starts from (time = step dt)
  /// Neighbour slots per grain of the first list (more are taken when a grain needs them).
  int initial_slots = 32;
  double skin = 0;  ///< m: pairs closer than r_i + r_j + skin are listed
  PairTable<contact::PairCoeffs> pairs;
  std::vector<DeviceWall> walls;
  /// The prescribed motions of the fixed groups that move (motion k for the grains with
  /// ParticleStore::fixed = kFixedMoving + k; their fixed_x0 the positions at t = 0).
  std::vector<RigidMotion> fixed_motions;
  /// Histories of the contacts at the start (a run continued from a state with contacts): each
  /// grain pair once, in either order; grain-wall pairs.
  std::vector<HistoryEntry> pair_history, wall_history;
};

/// Counters of the device run.
struct DeviceCounts {
  std::int64_t steps = 0;
  std::int64_t list_builds = 0;  ///< during the steps (not counting the first, at set-up)
  int list_capacity = 0;         ///< neighbour slots per grain now (grows when a grain needs more)
  std::size_t bytes = 0;         ///< memory the engine holds on its device now
};

class SphereDem {
 public:
  /// Copies the grains (positions, velocities, spins, forces of the last evaluation) and the
  /// contact histories to the device. The forces must be those of the current positions (as
  /// after a step or after Simulation's construction).
  SphereDem(const ParticleStore& p, const SphereDemSetup& setup, Backend backend = Backend::Cuda);
  ~SphereDem();
  SphereDem(const SphereDem&) = delete;
  SphereDem& operator=(const SphereDem&) = delete;

  /// Runs n time steps on the device, fewer when a stop is requested (core/stop.hpp; checked
  /// every 64 steps); returns the steps taken.
  std::int64_t advance(std::int64_t n);
  /// Copies positions, velocities, spins, forces and torques back into p (same grains, same
  /// order as given to the constructor).
  void download(ParticleStore& p) const;
  /// Touching grain pairs and grain-wall contacts at the last force evaluation.
  std::int64_t n_contacts() const;
  std::int64_t n_wall_contacts() const;
  /// Force of the grains on each wall at the last force evaluation, N (setup.walls' order).
  std::vector<Vec3> wall_forces() const;
  /// Their torques about each wall's point, N m.
  std::vector<Vec3> wall_torques() const;
  /// The histories of the touching contacts now: grain pairs once each (i < j), grain-wall
  /// pairs; zero histories left out.
  std::vector<HistoryEntry> pair_history() const;
  std::vector<HistoryEntry> wall_history() const;
  DeviceCounts counts() const;

 private:
  std::unique_ptr<detail::EngineBase> engine_;
};

}  // namespace gf::gpu
