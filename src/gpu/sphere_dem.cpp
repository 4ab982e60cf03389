// SPDX-License-Identifier: GPL-3.0-or-later
// SphereDem: forwards to the engine of its back end (engine.hpp).
#include "gpu/sphere_dem.hpp"

#include "core/error.hpp"
#include "gpu/engine.hpp"

namespace gf::gpu {

namespace detail {
std::unique_ptr<EngineBase> make_host_engine(const ParticleStore& p, const SphereDemSetup& s);
#if defined(GF_HAVE_CUDA)
std::unique_ptr<EngineBase> make_cuda_engine(const ParticleStore& p, const SphereDemSetup& s);
#endif
}  // namespace detail

#if !defined(GF_HAVE_CUDA)
bool cuda_built() {
  return false;
}
bool device_available(std::string* why) {
  if (why) *why = "this grainflow was built without CUDA (CMake preset 'cuda', docs/gpu.md)";
  return false;
}
#endif

SphereDem::SphereDem(const ParticleStore& p, const SphereDemSetup& setup, Backend backend) {
  if (backend == Backend::HostMirror) {
    engine_ = detail::make_host_engine(p, setup);
    return;
  }
#if defined(GF_HAVE_CUDA)
  engine_ = detail::make_cuda_engine(p, setup);
#else
  throw Error("the CUDA back end is not in this build (CMake preset 'cuda', docs/gpu.md)");
#endif
}

SphereDem::~SphereDem() = default;

std::int64_t SphereDem::advance(std::int64_t n) {
  return engine_->advance(n);
}
void SphereDem::download(ParticleStore& p) const {
  engine_->download(p);
}
std::int64_t SphereDem::n_contacts() const {
  return engine_->n_contacts();
}
std::int64_t SphereDem::n_wall_contacts() const {
  return engine_->n_wall_contacts();
}
std::vector<Vec3> SphereDem::wall_forces() const {
  return engine_->wall_forces();
}
std::vector<Vec3> SphereDem::wall_torques() const {
  return engine_->wall_torques();
}
std::vector<HistoryEntry> SphereDem::pair_history() const {
  return engine_->pair_history();
}
std::vector<HistoryEntry> SphereDem::wall_history() const {
  return engine_->wall_history();
}
DeviceCounts SphereDem::counts() const {
  return engine_->counts();
}

}  // namespace gf::gpu
