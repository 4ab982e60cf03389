// SPDX-License-Identifier: GPL-3.0-or-later
// Checkpoint / restart continues bit-identically to an uninterrupted run.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "case_builder.hpp"
#include "core/files.hpp"
#include "core/stop.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"
#include "state_compare.hpp"
#include "temp_dir.hpp"

using namespace gf;

namespace {

config::Case settling_case() {
  auto c = test::base_case(2e-5, 1.0, {0, 0, 0}, {0.05, 0.05, 0.1});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_material(c, "steel", 7800, 2e7, 0.28);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}, {"rolling_friction", 0.02}});
  test::add_contact(c, "glass", "steel", "hooke",
                    {{"restitution", 0.6}, {"friction", 0.3}, {"stiffness", 2e3}});
  auto& f = test::add_box_fill(c, "glass", 0.002, 0.003, {0, 0, 0}, {0.05, 0.05, 0.06},
                               config::Fill::Lattice::Random);
  f.count = 250;
  f.seed = 11;
  f.velocity_jitter = 0.2;
  test::add_box(c, "box", {0, 0, 0}, {0.05, 0.05, 0.1}, {"zmax"}, "steel");
  config::Wall lid;  // a moving, rotating plane
  lid.name = "paddle";
  lid.kind = config::Wall::Kind::Plane;
  lid.point = {0.025, 0.025, 0.03};
  lid.normal = {0, 0, -1};
  lid.material = "steel";
  lid.motion.velocity = {0, 0, -0.05};
  c.walls.push_back(lid);
  return c;
}

/// Two runs of one case: a takes `before` steps, writes a checkpoint and takes `after` more; b
/// loads that checkpoint and takes `after` steps. The checkpoint is removed with the object.
struct RestartedPair {
  std::filesystem::path file;
  std::unique_ptr<Simulation> a, b;
  std::int64_t b_steps_at_load = 0;   // b's step count right after loading
  std::int64_t a_builds_at_save = 0;  // a's neighbour-list builds when it saved
  ~RestartedPair() { std::filesystem::remove(file); }
};

std::unique_ptr<RestartedPair> run_restarted(const config::Case& cfg, const std::string& tag,
                                             int before, int after) {
  auto r = std::make_unique<RestartedPair>();
  r->file = std::filesystem::temp_directory_path() /
            ("gf_restart_" + tag + "_" + std::to_string(::getpid()) + ".h5");
  r->a = std::make_unique<Simulation>(cfg);
  for (int s = 0; s < before; ++s) r->a->step();
  r->a->save_checkpoint(r->file);
  r->a_builds_at_save = r->a->neighbor_list().n_builds();
  for (int s = 0; s < after; ++s) r->a->step();
  r->b = std::make_unique<Simulation>(cfg);
  r->b->load_checkpoint(r->file);
  r->b_steps_at_load = r->b->step_count();
  for (int s = 0; s < after; ++s) r->b->step();
  return r;
}

}  // namespace

TEST(Restart, ContinuesBitIdentically) {
  const auto r = run_restarted(settling_case(), "settling", 1500, 1500);
  EXPECT_EQ(r->b_steps_at_load, 1500);
  EXPECT_GT(r->a->neighbor_list().n_builds(), 3);  // rebuilds happened after the checkpoint
  EXPECT_GT(r->a->n_contacts(), 50);
  test::expect_same_state(*r->a, *r->b);
}

TEST(Restart, StoppedRunContinuesBitIdentically) {
  // A SIGTERM arrives while run() is in its time loop (deferred half kicks and all): the run
  // ends its step, writes checkpoint_<step>.h5 and says so; continuing from that checkpoint must
  // give the bits of a run that was never stopped.
  test::TempDir tmp;
  const auto cfg = settling_case();
  RunOptions opts;
  opts.output = tmp / "stopped";
  opts.quiet = true;
  opts.steps = 2'000'000;  // ~minutes: the signal must come first
  stop::install_handlers();
  std::thread sender([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(::getpid(), SIGTERM);
  });
  Simulation a(cfg);
  const RunSummary s = a.run(opts);
  sender.join();
  stop::reset();
  ASSERT_EQ(s.stop_signal, SIGTERM);
  ASSERT_GT(s.steps, 0);
  ASSERT_LT(s.steps, *opts.steps);
  EXPECT_EQ(s.checkpoint, opts.output / fmt::format("checkpoint_{:09d}.h5", s.steps));
  ASSERT_TRUE(std::filesystem::exists(s.checkpoint));
  EXPECT_FALSE(std::filesystem::exists(opts.output / "checkpoint_final.h5"));
  const std::string summary = read_text_file(opts.output / "summary.json");
  EXPECT_NE(summary.find("\"completed\": false"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"stopped_by\": \"SIGTERM\""), std::string::npos) << summary;

  const int more = 700;
  Simulation b(cfg);
  b.load_checkpoint(s.checkpoint);
  EXPECT_EQ(b.step_count(), s.steps);
  for (int k = 0; k < more; ++k) b.step();
  Simulation c(cfg);
  for (std::int64_t k = 0; k < s.steps + more; ++k) c.step();
  test::expect_same_state(b, c);
}

TEST(Restart, RejectsForeignFileAndMismatchedTimeStep) {
  auto cfg = settling_case();
  const auto file = std::filesystem::temp_directory_path() /
                    ("gf_restart_test2_" + std::to_string(::getpid()) + ".h5");
  Simulation a(cfg);
  a.step();
  a.save_checkpoint(file);
  cfg.time.step = 1e-5;
  Simulation b(cfg);
  EXPECT_THROW(b.load_checkpoint(file), InputError);
  std::filesystem::remove(file);
}

TEST(Restart, LeesEdwardsContinuesBitIdentically) {
  // Dense spheres sheared between sliding images: grains cross the z boundary (position and
  // velocity remapped) and the list is rebuilt as the offset moves; the restart must keep the
  // offset at the last build.
  const auto cfg = input::load_case(
      std::string(GF_SOURCE_DIR) + "/cases/rheology/lees_edwards_spheres/case.yaml",
      {{"particles[0].fill.volume_fraction", "0.35"},
       {"shear.rate", "400"},
       {"time.step", "1.0e-6"}});
  const auto r = run_restarted(cfg, "le", 3000, 3000);
  EXPECT_GT(r->a->neighbor_list().n_builds(), r->a_builds_at_save + 2);
  EXPECT_GT(r->a->n_contacts(), 5);
  test::expect_same_state(*r->a, *r->b);
}

TEST(Restart, CfdDemContinuesBitIdentically) {
  // The fluidized bed, checkpointed between two fluid steps (510 is not a multiple of the
  // coupling interval 25): grains, exchange fields and the fluid (velocities of two steps,
  // pressure, solver guesses, fluid fraction of the last fluid step) must all carry over.
  const auto cfg =
      input::load_case(std::string(GF_SOURCE_DIR) + "/cases/cfd_dem/fluidized_bed/case.yaml");
  const auto r = run_restarted(cfg, "cfd", 510, 500);
  const Simulation& a = *r->a;
  const Simulation& b = *r->b;
  test::expect_same_state(a, b);
  ASSERT_TRUE(a.cfd_dem() && b.cfd_dem());
  const auto& fa = a.cfd_dem()->fluid();
  const auto& fb = b.cfd_dem()->fluid();
  EXPECT_EQ(fa.step_count(), fb.step_count());
  EXPECT_EQ(fa.time(), fb.time());
  for (int k = 0; k < 3; ++k) {
    const auto ua = fa.face_velocity(k), ub = fb.face_velocity(k);
    ASSERT_EQ(ua.size(), ub.size());
    EXPECT_EQ(0, std::memcmp(ua.data(), ub.data(), ua.size() * sizeof(double))) << "u" << k;
  }
  const auto pa = fa.pressure(), pb = fb.pressure();
  EXPECT_EQ(0, std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(double)));
  double umax = 0;
  for (double u : fa.face_velocity(2)) umax = std::max(umax, std::abs(u));
  EXPECT_GT(umax, 1.0);  // the fluid is moving (inlet 2.5 m/s)

  // A checkpoint with a fluid state refused by a case without fluid.
  auto dry = cfg;
  dry.fluid.reset();
  dry.coupling.reset();
  dry.output.quantities.clear();
  Simulation c(dry);
  EXPECT_THROW(c.load_checkpoint(r->file), InputError);
}
