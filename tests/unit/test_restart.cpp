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
#include <fstream>
#include <limits>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>

#include "case_builder.hpp"
#include "core/files.hpp"
#include "core/stop.hpp"
#include "fem_case_text.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/fem_case.hpp"
#include "simulation/rheology_output.hpp"
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

namespace {

/// A mesh wall: a vertical blade of 24 triangles turning about z in the box at 10 rad/s.
void add_turning_blade(config::Case& c) {
  std::vector<Vec3> pts;
  std::vector<std::array<int, 3>> tris;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 4; ++i) pts.push_back({0.008 + 0.0085 * i, 0.025, 0.01 * j});
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = j * 5 + i;
      tris.push_back({a, a + 1, a + 6});
      tris.push_back({a, a + 6, a + 5});
    }
  test::add_mesh(c, "blade", pts, tris, "steel");
  c.walls.back().motion.rotates = true;
  c.walls.back().motion.axis = {0, 0, 1};
  c.walls.back().motion.center = {0.025, 0.025, 0};
  c.walls.back().motion.rate = 10;
}

}  // namespace

// A rotating mesh wall (a vertical blade of 24 triangles turning about z in the box): the
// triangles' contact histories (moved between triangles as grains slide across them) and the
// re-placed vertices continue bit-identically.
TEST(Restart, MeshWallContinuesBitIdentically) {
  auto c = settling_case();
  c.walls.pop_back();  // no paddle
  c.particles[0].fill->region.min.z = 0.032;
  add_turning_blade(c);
  const auto r = run_restarted(c, "mesh", 3000, 2000);
  EXPECT_GT(norm(r->a->walls().back().force), 0.0);  // the grains reached the blade
  test::expect_same_state(*r->a, *r->b);
}

// The same with spherocylinders: their contacts with the blade's triangles (up to eight per
// triangle: the ends, and the axis at edges and corners) keep their histories across the restart.
TEST(Restart, MeshWallWithRodsContinuesBitIdentically) {
  auto c = settling_case();
  c.walls.pop_back();  // no paddle
  c.particles.clear();
  auto& f = test::add_capsule_fill(c, "glass", 0.0015, 3, {0, 0, 0.02}, {0.05, 0.05, 0.08},
                                   config::Fill::Lattice::Random);
  f.count = 60;
  f.seed = 12;
  f.velocity_jitter = 0.2;
  add_turning_blade(c);
  const auto r = run_restarted(c, "mesh_rods", 6000, 3000);
  EXPECT_GT(norm(r->a->walls().back().force), 0.0);  // the rods reached the blade
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

namespace {

/// Runs `cfg` whole and cut at step `cut_step` (2345: no output due there) then continued in its
/// own folder with --append; `files` must be the same in both folders.
void expect_append_matches_whole_run(const config::Case& cfg, const test::TempDir& tmp,
                                     std::initializer_list<const char*> files,
                                     std::int64_t cut_step = 2345) {
  RunOptions whole;
  whole.output = tmp / "whole";
  whole.quiet = true;
  Simulation(cfg).run(whole);
  RunOptions cut = whole;
  cut.output = tmp / "cut";
  cut.steps = cut_step;
  Simulation(cfg).run(cut);
  RunOptions rest = cut;
  rest.steps.reset();
  rest.restart = cut.output / "checkpoint_final.h5";
  rest.append = true;
  Simulation(cfg).run(rest);
  for (const char* f : files)
    EXPECT_EQ(read_text_file(whole.output / f), read_text_file(cut.output / f)) << f;
}

}  // namespace

// Shear between walls with the walls' interval means in the series (wall_force_mean,
// wall_torque_mean) and in the rheology samples (wall_sigma_xz, wall_sigma_zz): the cut falls
// inside an interval, whose sums the checkpoint keeps, so the continued run writes the rows
// and samples of the run that was never cut; or on a row's step (3000), whose row the
// continued run writes again with the means of the interval that row closed.
TEST(Restart, AppendContinuesTheWallMeans) {
  for (const std::int64_t cut_step : {2345, 3000}) {
    SCOPED_TRACE(cut_step);
    test::TempDir tmp;
    const auto cfg =
        input::load_case(std::string(GF_SOURCE_DIR) + "/cases/rheology/shear_box_spheres/case.yaml",
                         {{"particles[0].fill.volume_fraction", "0.3"},
                          {"shear.rate", "400"},
                          {"shear.strain", "2"},
                          {"time.step", "1.0e-6"},
                          {"analysis.rheology.every_strain", "0.2"},
                          {"output.series.every", "1.0e-3"},
                          {"output.series.quantities",
                           "[wall_force_mean.shear_bottom, wall_torque_mean.shear_bottom.y, "
                           "wall_force.shear_top.x]"},
                          {"output.vtk.every", "0"}});
    expect_append_matches_whole_run(
        cfg, tmp, {"series.csv", "rheology.csv", "rheology_summary.csv"}, cut_step);
    const std::string series = read_text_file(tmp / "whole" / "series.csv");
    EXPECT_EQ(series.substr(0, series.find('\n')),
              "time,wall_force_mean.shear_bottom.x,wall_force_mean.shear_bottom.y,"
              "wall_force_mean.shear_bottom.z,wall_torque_mean.shear_bottom.y,"
              "wall_force.shear_top.x");
    // (not a vacuous comparison: the row at the cut at 3000 steps has a mean force)
    const auto row = series.find("\n0.003,");
    ASSERT_NE(row, std::string::npos);
    EXPECT_NE(series.substr(row + 7, 2), "0,") << series.substr(row, 80);
    const auto s = read_rheology_summary(tmp / "whole" / "rheology_summary.csv");
    EXPECT_LT(s.at("wall_sigma_xz")[0], 0.0);
    EXPECT_GT(s.at("wall_sigma_zz")[0], 0.0);
  }
}

TEST(Restart, AppendContinuesTheOutputsOfTheRunInPlace) {
  // A sheared run cut at step 2345 (no output is due there) and continued in its own folder with
  // --append must leave the same series, rheology samples and summary and ParaView series as a
  // run that was never cut: the rows the cut run wrote at its last step are dropped, the
  // samples before it count in the steady-state averages.
  test::TempDir tmp;
  const auto cfg = input::load_case(
      std::string(GF_SOURCE_DIR) + "/cases/rheology/lees_edwards_spheres/case.yaml",
      {{"shear.rate", "400"},
       {"shear.strain", "2"},
       {"time.step", "1.0e-6"},
       {"output.series.every", "1.0e-4"},
       {"output.vtk.every", "5.0e-4"}});
  expect_append_matches_whole_run(cfg, tmp,
                                  {"series.csv", "rheology.csv", "rheology_summary.csv",
                                   "particles.pvd", "particles_000005000.vtp"});
  RunOptions rest;
  rest.output = tmp / "cut";
  rest.quiet = true;
  rest.append = true;
  RunOptions bad = rest;  // --append needs the checkpoint and an existing folder
  bad.restart.reset();
  EXPECT_THROW(Simulation(cfg).run(bad), InputError);
  bad = rest;
  bad.restart = tmp / "cut" / "checkpoint_final.h5";
  bad.output = tmp / "nowhere";
  EXPECT_THROW(Simulation(cfg).run(bad), InputError);
}

// --append with another rheology sampling than the run it continues (its resolved_case.yaml)
// is refused before anything is written (the steady averages would mix two samplings), as are
// other series columns; another interval of a file-per-step output or of the series is taken.
TEST(Restart, AppendRefusesAnotherRheologySampling) {
  test::TempDir tmp;
  const std::vector<input::Override> sets{{"shear.rate", "400"},
                                          {"shear.strain", "2"},
                                          {"time.step", "1.0e-6"},
                                          {"output.series.every", "1.0e-4"},
                                          {"output.vtk.every", "0"}};
  const std::string file =
      std::string(GF_SOURCE_DIR) + "/cases/rheology/lees_edwards_spheres/case.yaml";
  RunOptions cut;
  cut.output = tmp / "cut";
  cut.quiet = true;
  cut.steps = 2345;
  Simulation(input::load_case(file, sets)).run(cut);
  const std::string series = read_text_file(cut.output / "series.csv");
  const std::string resolved = read_text_file(cut.output / "resolved_case.yaml");
  RunOptions rest = cut;
  rest.steps.reset();
  rest.restart = cut.output / "checkpoint_final.h5";
  rest.append = true;
  for (const auto& [key, value, message] :
       {std::tuple{"analysis.rheology.every_strain", "0.1",
                   "analysis.rheology is every 0.00025 s in this case but every 0.000125 s"},
        std::tuple{"analysis.rheology.bins", "8", "analysis.rheology.bins is 8"},
        std::tuple{"output.series.quantities", "[kinetic_energy]", "series"}}) {
    auto changed = sets;
    changed.push_back({key, value});
    try {
      Simulation(input::load_case(file, changed)).run(rest);
      ADD_FAILURE() << key << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_text_file(cut.output / "series.csv"), series) << key;
    EXPECT_EQ(read_text_file(cut.output / "resolved_case.yaml"), resolved) << key;
  }
  auto sparser = sets;  // the same sampling, another series interval
  sparser.push_back({"output.series.every", "2.0e-4"});
  EXPECT_NO_THROW(Simulation(input::load_case(file, sparser)).run(rest));
}

TEST(Restart, AppendContinuesTheRheologyOfAnEarlierBuild) {
  // A run of a build that wrote rheology.csv without the contact columns (coordination number,
  // fabric), continued with --append by this build: its rows get nan there, and the summary
  // averages those columns over the samples that have them.
  test::TempDir tmp;
  const auto cfg = input::load_case(
      std::string(GF_SOURCE_DIR) + "/cases/rheology/lees_edwards_spheres/case.yaml",
      {{"particles[0].fill.volume_fraction", "0.3"},
       {"shear.rate", "400"},
       {"shear.strain", "2"},
       {"time.step", "1.0e-6"},
       {"output.vtk.every", "0"}});
  RunOptions cut;
  cut.output = tmp / "cut";
  cut.quiet = true;
  cut.steps = 2345;
  Simulation(cfg).run(cut);
  // Drop the last eight columns (the contacts' six and the walls' two), as the earlier build
  // wrote the file.
  const std::filesystem::path csv = cut.output / "rheology.csv";
  std::istringstream in(read_text_file(csv));
  std::string text, line;
  std::size_t kept_rows = 0;
  while (std::getline(in, line)) {
    for (int k = 0; k < 8; ++k) line.erase(line.rfind(','));
    text += line + '\n';
    ++kept_rows;
  }
  ASSERT_GT(kept_rows, 5u);
  std::ofstream(csv) << text;

  RunOptions rest = cut;
  rest.steps.reset();
  rest.restart = cut.output / "checkpoint_final.h5";
  rest.append = true;
  Simulation(cfg).run(rest);
  const std::string after = read_text_file(csv);
  EXPECT_NE(after.find("grains,coordination_number,F_xx,F_yy,F_zz,F_xz,fabric_angle,wall_sigma_xz,"
                       "wall_sigma_zz\n"),
            std::string::npos);
  EXPECT_NE(after.find(",nan,nan,nan,nan,nan,nan,nan,nan\n"), std::string::npos);
  const auto s = read_rheology_summary(cut.output / "rheology_summary.csv");
  EXPECT_GT(s.at("coordination_number")[0], 0.0);
  EXPECT_NEAR(s.at("F_xx")[0] + s.at("F_yy")[0] + s.at("F_zz")[0], 1.0, 1e-9);
  EXPECT_TRUE(std::isfinite(s.at("fabric_angle")[0]));
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

TEST(Restart, CfdDemDerivativeRateContinuesBitIdentically) {
  // The smoothed deposit with its time derivative as the rate: the rate is rebuilt from the
  // grains every fluid step and only its relaxed value is state, kept like the flux rate's.
  const std::vector<input::Override> sets = {{"coupling.fluid_fraction", "smoothed"},
                                             {"coupling.fluid_fraction_rate", "derivative"}};
  const auto cfg =
      input::load_case(std::string(GF_SOURCE_DIR) + "/cases/cfd_dem/fluidized_bed/case.yaml", sets);
  ASSERT_EQ(cfg.coupling->fluid_fraction_rate, "derivative");
  const auto r = run_restarted(cfg, "cfd_derivative", 510, 500);
  test::expect_same_state(*r->a, *r->b);
  const auto pa = r->a->cfd_dem()->fluid().pressure(), pb = r->b->cfd_dem()->fluid().pressure();
  ASSERT_EQ(pa.size(), pb.size());
  EXPECT_EQ(0, std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(double)));
}

TEST(Restart, CfdDemHeatTransferContinuesBitIdentically) {
  // The heated bed: the grains' temperatures and conductances travel as particle fields, the
  // fluid's temperature in the coupling's state.
  const auto cfg = input::load_case(std::string(GF_SOURCE_DIR) +
                                    "/cases/cfd_dem/fluidized_bed_heating/case.yaml");
  const auto r = run_restarted(cfg, "cfd_heat", 510, 500);
  const Simulation& a = *r->a;
  const Simulation& b = *r->b;
  test::expect_same_state(a, b);
  ASSERT_TRUE(a.cfd_dem() && b.cfd_dem() && a.cfd_dem()->heat() && b.cfd_dem()->heat());
  const auto ta = a.cfd_dem()->heat()->temperature(), tb = b.cfd_dem()->heat()->temperature();
  ASSERT_EQ(ta.size(), tb.size());
  EXPECT_EQ(0, std::memcmp(ta.data(), tb.data(), ta.size() * sizeof(double)));
  EXPECT_GT(*std::max_element(ta.begin(), ta.end()), 300.0);  // the hot air came in (373 K)
  for (const char* field : {"temperature", "fluid_temperature", "fluid_heat_conductance"}) {
    const auto fa = a.particles().get<double>(a.particles().find_field(field));
    const auto fb = b.particles().get<double>(b.particles().find_field(field));
    ASSERT_EQ(fa.size(), fb.size());
    EXPECT_EQ(0, std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(double))) << field;
  }
}

namespace {

// The shared channel case with automatic BDF order, adaptive steps and the chord method (the
// LU kept across steps): every piece of state a continuation needs.
std::string fem_case() {
  const std::string unsteady = test::replaced(
      test::kFemChannelCase, "time: {mode: unsteady, scheme: bdf2, step: 0.05, end: 0.2}",
      "time: {mode: unsteady, scheme: auto, step: 0.005, end: 0.5,\n"
      "         adaptive: {rtol: 1.0e-4, dt_max: 0.02}}\n"
      "  newton: {reuse_factorization: true}");
  return test::replaced(unsteady, "output: {", "output: {checkpoint_every: 0.1, ");
}

std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

void expect_same_flow(const fem::FemCheckpoint& a, const fem::FemCheckpoint& b) {
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.flow.t, b.flow.t);
  EXPECT_TRUE(test::same_bits(std::span(a.flow.x), std::span(b.flow.x)));
  ASSERT_EQ(a.flow.hist_x.size(), b.flow.hist_x.size());
  for (std::size_t k = 0; k < a.flow.hist_x.size(); ++k)
    EXPECT_TRUE(test::same_bits(std::span(a.flow.hist_x[k]), std::span(b.flow.hist_x[k])));
  EXPECT_EQ(a.loop.dt, b.loop.dt);
  EXPECT_EQ(a.loop.order, b.loop.order);
}

}  // namespace

TEST(Restart, FluidFemContinuesBitIdentically) {
  test::TempDir tmp;
  const auto file = tmp.write("case.yaml", fem_case());
  std::filesystem::path unused;
  const auto cfg = load_fem_case(file, unused);
  ASSERT_TRUE(cfg);
  RunOptions a;
  a.output = tmp / "a";
  ASSERT_EQ(run_fem_case(*cfg, unused, a), 0);
  std::vector<std::filesystem::path> ckpts;
  for (const auto& e : std::filesystem::directory_iterator(a.output))
    if (e.path().filename().string().rfind("fem_checkpoint_0", 0) == 0) ckpts.push_back(e.path());
  std::sort(ckpts.begin(), ckpts.end());
  ASSERT_EQ(ckpts.size(), 4u);  // t = 0.1, 0.2, 0.3, 0.4 (the end has fem_checkpoint_final.h5)
  const auto end_a = load_fem_checkpoint(a.output / "fem_checkpoint_final.h5");
  const auto mid = load_fem_checkpoint(ckpts[1]);
  EXPECT_NEAR(mid.flow.t, 0.2, 0.02);
  EXPECT_TRUE(mid.flow.factorized);
  EXPECT_GE(mid.loop.order, 2);

  // Continued from t ~ 0.2: the same final bits, and the same force rows after the restart.
  RunOptions b;
  b.output = tmp / "b";
  b.restart = ckpts[1];
  ASSERT_EQ(run_fem_case(*cfg, unused, b), 0);
  expect_same_flow(end_a, load_fem_checkpoint(b.output / "fem_checkpoint_final.h5"));
  const auto rows_a = lines_of(a.output / "fem_forces.csv");
  const auto rows_b = lines_of(b.output / "fem_forces.csv");
  ASSERT_GT(rows_b.size(), 5u);
  ASSERT_LT(rows_b.size(), rows_a.size());
  EXPECT_EQ(rows_b[0], rows_a[0]);  // the header
  EXPECT_TRUE(std::equal(rows_b.begin() + 1, rows_b.end(), rows_a.end() - (rows_b.size() - 1)));

  // Cut after 30 steps and continued in its folder (--append): the same CSV series.
  RunOptions e;
  e.output = tmp / "e";
  e.steps = 30;
  ASSERT_EQ(run_fem_case(*cfg, unused, e), 0);
  e.steps.reset();
  e.restart = e.output / "fem_checkpoint_final.h5";
  e.append = true;
  ASSERT_EQ(run_fem_case(*cfg, unused, e), 0);
  for (const char* f : {"fem_forces.csv", "fem_probes.csv"})
    EXPECT_EQ(read_text_file(a.output / f), read_text_file(e.output / f)) << f;
  // ... and the same field series: the cut's extra data set (its last state, off the schedule)
  // is dropped and the numbering goes on as in the uncut run, so the .pvd and every .vtu match.
  EXPECT_EQ(read_text_file(a.output / "fem_fields.pvd"),
            read_text_file(e.output / "fem_fields.pvd"));
  auto vtus = [](const std::filesystem::path& dir) {
    std::vector<std::string> out;
    for (const auto& f : std::filesystem::directory_iterator(dir))
      if (f.path().extension() == ".vtu") out.push_back(f.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  };
  const auto vtus_a = vtus(a.output);
  EXPECT_EQ(vtus_a, vtus(e.output));
  EXPECT_GE(vtus_a.size(), 6u);  // t = 0, 0.1, ..., 0.5 and the mesh
  for (const auto& f : vtus_a)
    EXPECT_EQ(read_text_file(a.output / f), read_text_file(e.output / f)) << f;
  // Its checkpoints count the runs and their wall time.
  const auto end_e = load_fem_checkpoint(e.output / "fem_checkpoint_final.h5");
  EXPECT_EQ(end_a.runs, 1);
  EXPECT_EQ(end_e.runs, 2);
  EXPECT_GT(end_e.wall_seconds, 0.0);
  // A checkpoint of an older build (no schedule time, run count or wall time): still continued,
  // with everything up to its time kept (the cut's extra data set too) and the wall time unknown.
  RunOptions g;
  g.output = tmp / "g";
  g.steps = 30;
  ASSERT_EQ(run_fem_case(*cfg, unused, g), 0);
  auto old = load_fem_checkpoint(g.output / "fem_checkpoint_final.h5");
  old.fields_until.reset();
  ++old.n_fields;  // an older build took the checkpoint after the cut's extra data set
  old.runs = 1;
  old.wall_seconds = std::numeric_limits<double>::quiet_NaN();
  save_fem_checkpoint(tmp / "old.h5", old);
  EXPECT_FALSE(load_fem_checkpoint(tmp / "old.h5").fields_until);
  g.steps.reset();
  g.restart = tmp / "old.h5";
  g.append = true;
  ASSERT_EQ(run_fem_case(*cfg, unused, g), 0);
  expect_same_flow(end_a, load_fem_checkpoint(g.output / "fem_checkpoint_final.h5"));
  auto data_sets = [](const std::string& pvd) {
    std::size_t n = 0;
    for (auto at = pvd.find("<DataSet"); at != std::string::npos; at = pvd.find("<DataSet", at + 1))
      ++n;
    return n;
  };
  EXPECT_EQ(data_sets(read_text_file(g.output / "fem_fields.pvd")),
            data_sets(read_text_file(a.output / "fem_fields.pvd")) + 1);
  const std::string summary = read_text_file(g.output / "fem_summary.txt");
  EXPECT_NE(summary.find("runs over restarts: 2\n"), std::string::npos) << summary;

  // Stopped by a signal (here before its first step): the checkpoint is named by the step and
  // holds the restored state, LU iterate included; continuing it gives the same bits again.
  RunOptions c;
  c.output = tmp / "c";
  c.restart = ckpts[1];
  stop::install_handlers();
  std::raise(SIGTERM);
  EXPECT_EQ(run_fem_case(*cfg, unused, c), SIGTERM);
  stop::reset();
  const auto stopped = c.output / fmt::format("fem_checkpoint_{:07d}.h5", mid.steps);
  ASSERT_TRUE(std::filesystem::exists(stopped));
  EXPECT_FALSE(std::filesystem::exists(c.output / "fem_checkpoint_final.h5"));
  RunOptions d;
  d.output = tmp / "d";
  d.restart = stopped;
  ASSERT_EQ(run_fem_case(*cfg, unused, d), 0);
  expect_same_flow(end_a, load_fem_checkpoint(d.output / "fem_checkpoint_final.h5"));
}

TEST(Restart, FluidFemRefusesForeignCheckpoints) {
  test::TempDir tmp;
  std::filesystem::path unused;
  const auto cfg = load_fem_case(tmp.write("case.yaml", fem_case()), unused);
  ASSERT_TRUE(cfg);
  RunOptions a;
  a.output = tmp / "a";
  a.steps = 3;
  ASSERT_EQ(run_fem_case(*cfg, unused, a), 0);
  const auto fem_ckpt = a.output / "fem_checkpoint_final.h5";

  // Another mesh (the case's mesh sizes changed).
  const std::string other = test::replaced(fem_case(), "h_max: 0.08", "h_max: 0.07");
  const auto cfg2 = load_fem_case(tmp.write("other.yaml", other), unused);
  RunOptions b;
  b.output = tmp / "b";
  b.restart = fem_ckpt;
  try {
    run_fem_case(*cfg2, unused, b);
    ADD_FAILURE() << "a checkpoint of another mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another mesh"), std::string::npos) << e.what();
  }
  // A particle case refuses the fluid_fem checkpoint, and the fluid_fem case a particle one.
  Simulation dem(settling_case());
  EXPECT_THROW(dem.load_checkpoint(fem_ckpt), InputError);
  const auto dem_ckpt = tmp / "dem.h5";
  dem.save_checkpoint(dem_ckpt);
  b.restart = dem_ckpt;
  b.overwrite = true;
  EXPECT_THROW(run_fem_case(*cfg, unused, b), InputError);
}

namespace {

// Two squares and a disk settling in a closed box onto the floor and onto each other: free
// bodies on a moving mesh that is rebuilt once between t = 0.1 and 0.2 (its cells degrade), with
// friction springs on the films between them, and the chord method's LU kept across steps.
constexpr const char* kFemMovingCase = R"(fluid_fem:
  fluid: {density: 1000.0, viscosity: 5.0e-4}
  gravity: [0, -9.81]
  domain:
    outline: [[0, 0], [0.02, 0], [0.02, 0.015], [0, 0.015]]
    boundaries:
      - {edges: [0, 1, 2, 3], type: wall}
  bodies:
    - {name: a, polygon: [[0.006, 0.0012], [0.010, 0.0012], [0.010, 0.0052], [0.006, 0.0052]], density: 2500}
    - {name: b, polygon: [[0.0075, 0.0067], [0.0115, 0.0064], [0.0118, 0.0104], [0.0078, 0.0107]], density: 2500}
    - {name: c, circle: {centre: [0.015, 0.004], radius: 0.002}, density: 2500}
  mesh: {h_max: 0.003, h_body: 0.0008, grading: 0.3}
  moving_mesh: {repulsion: {range: 0.0012, force: 0.6, friction: 0.5, tangential_stiffness: 400,
                            rolling_friction: 0.1}}
  time: {mode: unsteady, scheme: bdf2, step: 0.005, end: 0.3}
  newton: {reuse_factorization: true}
  output: {vtk_every: 0.1, checkpoint_every: 0.1}
)";

void expect_same_moving(const fem::FemCheckpoint& a, const fem::FemCheckpoint& b) {
  expect_same_flow(a, b);
  ASSERT_TRUE(a.moving && b.moving);
  EXPECT_TRUE(test::same_bits(std::span(a.moving->poses), std::span(b.moving->poses)));
  EXPECT_EQ(a.moving->remeshes, b.moving->remeshes);
  EXPECT_EQ(a.moving->history_keys, b.moving->history_keys);
  EXPECT_TRUE(
      test::same_bits(std::span(a.moving->history_stretch), std::span(b.moving->history_stretch)));
  EXPECT_TRUE(
      test::same_bits(std::span(a.moving->history_roll), std::span(b.moving->history_roll)));
  ASSERT_EQ(a.flow.nodes.size(), b.flow.nodes.size());
  for (std::size_t k = 0; k < a.flow.nodes.size(); ++k)
    ASSERT_TRUE(a.flow.nodes[k].x == b.flow.nodes[k].x && a.flow.nodes[k].y == b.flow.nodes[k].y)
        << "node " << k;
}

}  // namespace

// A run with free bodies continues from its checkpoints as if never stopped: from before the
// remesh (the continuation meshes again as the run did) and after it (the kept mesh is
// rebuilt, the nodes put where they were, the LU refactorised where it was assembled).
TEST(Restart, FluidFemMovingBodiesContinueBitIdentically) {
  test::TempDir tmp;
  std::filesystem::path unused;
  const auto cfg = load_fem_case(tmp.write("case.yaml", kFemMovingCase), unused);
  ASSERT_TRUE(cfg);
  RunOptions a;
  a.output = tmp / "a";
  ASSERT_EQ(run_fem_case(*cfg, unused, a), 0);
  const auto end_a = load_fem_checkpoint(a.output / "fem_checkpoint_final.h5");
  const auto at20 = load_fem_checkpoint(a.output / "fem_checkpoint_0000020.h5");
  const auto at40 = load_fem_checkpoint(a.output / "fem_checkpoint_0000040.h5");
  ASSERT_TRUE(at20.moving && at40.moving && end_a.moving);
  // what the continuation must restore: a remesh behind it, friction springs, kept factors
  EXPECT_EQ(at20.moving->remeshes, 0);
  EXPECT_EQ(at40.moving->remeshes, 1);
  EXPECT_GT(at40.moving->history_keys.size(), 2u);
  EXPECT_TRUE(std::any_of(at40.moving->history_roll.begin(), at40.moving->history_roll.end(),
                          [](double r) { return r != 0; }));  // rolling springs loaded
  EXPECT_TRUE(at40.flow.factorized && at40.flow.moving);
  EXPECT_NE(at40.flow.factor_x, at40.flow.x);  // factors of an earlier iterate

  for (const char* from : {"fem_checkpoint_0000020.h5", "fem_checkpoint_0000040.h5"}) {
    // into its own folder: the same end state, the same rows after the restart
    RunOptions b;
    b.output = tmp / (std::string("b") + from);
    b.restart = a.output / from;
    ASSERT_EQ(run_fem_case(*cfg, unused, b), 0);
    expect_same_moving(end_a, load_fem_checkpoint(b.output / "fem_checkpoint_final.h5"));
    const auto rows_a = lines_of(a.output / "fem_forces.csv");
    const auto rows_b = lines_of(b.output / "fem_forces.csv");
    ASSERT_GT(rows_b.size(), 20u);
    EXPECT_TRUE(std::equal(rows_b.begin() + 1, rows_b.end(), rows_a.end() - (rows_b.size() - 1)))
        << from;
  }
  // Cut after 45 steps and continued in its folder (--append): the same CSV and field series.
  RunOptions e;
  e.output = tmp / "e";
  e.steps = 45;
  ASSERT_EQ(run_fem_case(*cfg, unused, e), 0);
  e.steps.reset();
  e.restart = e.output / "fem_checkpoint_final.h5";
  e.append = true;
  ASSERT_EQ(run_fem_case(*cfg, unused, e), 0);
  EXPECT_EQ(read_text_file(a.output / "fem_forces.csv"),
            read_text_file(e.output / "fem_forces.csv"));
  for (const char* f : {"fem_fields.pvd", "fem_fields_00003.vtu", "fem_mesh.vtu"})
    EXPECT_EQ(read_text_file(a.output / f), read_text_file(e.output / f)) << f;
  EXPECT_NE(read_text_file(e.output / "fem_summary.txt").find("moving mesh: remeshes 1\n"),
            std::string::npos);

  // Stopped by a signal right after the restore: its checkpoint holds the restored state, and
  // continuing that gives the same bits again.
  RunOptions c;
  c.output = tmp / "c";
  c.restart = a.output / "fem_checkpoint_0000040.h5";
  stop::install_handlers();
  std::raise(SIGTERM);
  EXPECT_EQ(run_fem_case(*cfg, unused, c), SIGTERM);
  stop::reset();
  RunOptions d;
  d.output = tmp / "d";
  d.restart = c.output / "fem_checkpoint_0000040.h5";
  ASSERT_EQ(run_fem_case(*cfg, unused, d), 0);
  expect_same_moving(end_a, load_fem_checkpoint(d.output / "fem_checkpoint_final.h5"));

  // From the step right before the remesh (checkpoints at every step): the remesh interpolates
  // the restored velocities, the free bodies' surface nodes included, which must be the saved
  // bits (not the rigid motion imposed again).
  const auto cfg_each = load_fem_case(
      tmp.write("each.yaml",
                test::replaced(kFemMovingCase, "checkpoint_every: 0.1", "checkpoint_every: 0.005")),
      unused);
  ASSERT_TRUE(cfg_each);
  RunOptions k;
  k.output = tmp / "k";
  k.steps = 40;
  ASSERT_EQ(run_fem_case(*cfg_each, unused, k), 0);
  std::filesystem::path before_remesh;
  for (int step = 1; step <= 40; ++step) {
    const auto file = k.output / fmt::format("fem_checkpoint_{:07d}.h5", step);
    if (!std::filesystem::exists(file)) continue;
    if (load_fem_checkpoint(file).moving->remeshes > 0) break;
    before_remesh = file;
  }
  ASSERT_FALSE(before_remesh.empty());
  RunOptions m;
  m.output = tmp / "m";
  m.restart = before_remesh;
  ASSERT_EQ(run_fem_case(*cfg, unused, m), 0);
  expect_same_moving(end_a, load_fem_checkpoint(m.output / "fem_checkpoint_final.h5"));

  // Adaptive steps and automatic BDF order (the controller's state is in the checkpoint too):
  // continued in its folder from its last periodic checkpoint, the same rows.
  const auto cfg_adaptive = load_fem_case(
      tmp.write("adaptive.yaml",
                test::replaced(kFemMovingCase,
                               "time: {mode: unsteady, scheme: bdf2, step: 0.005, end: 0.3}",
                               "time: {mode: unsteady, scheme: auto, step: 0.002, end: 0.3,\n"
                               "         adaptive: {rtol: 1.0e-3, atol: 1.0e-5, dt_max: 0.0035}}")),
      unused);
  ASSERT_TRUE(cfg_adaptive);
  RunOptions g;
  g.output = tmp / "g";
  ASSERT_EQ(run_fem_case(*cfg_adaptive, unused, g), 0);
  std::vector<std::filesystem::path> periodic;
  for (const auto& p : std::filesystem::directory_iterator(g.output))
    if (p.path().filename().string().rfind("fem_checkpoint_0", 0) == 0)
      periodic.push_back(p.path());
  std::sort(periodic.begin(), periodic.end());
  ASSERT_GE(periodic.size(), 2u);
  const auto end_g = load_fem_checkpoint(g.output / "fem_checkpoint_final.h5");
  EXPECT_EQ(end_g.moving->remeshes, 1);
  // (from the first, before the remesh, and the last, after it)
  for (const auto& from : {periodic.front(), periodic.back()}) {
    RunOptions h;
    h.output = tmp / ("h" + from.filename().string());
    std::filesystem::copy(g.output, h.output);
    h.restart = h.output / from.filename();
    h.append = true;
    ASSERT_EQ(run_fem_case(*cfg_adaptive, unused, h), 0);
    EXPECT_EQ(read_text_file(g.output / "fem_forces.csv"),
              read_text_file(h.output / "fem_forces.csv"))
        << from;
    expect_same_moving(end_g, load_fem_checkpoint(h.output / "fem_checkpoint_final.h5"));
  }
  EXPECT_EQ(load_fem_checkpoint(periodic.front()).moving->remeshes, 0);

  // A checkpoint of bodies with other densities does not fit, nor one of the same geometry
  // with the bodies fixed (or free).
  const auto cfg_heavier = load_fem_case(
      tmp.write("heavier.yaml", test::replaced(kFemMovingCase, "[0.0078, 0.0107]], density: 2500",
                                               "[0.0078, 0.0107]], density: 2600")),
      unused);
  ASSERT_TRUE(cfg_heavier);
  RunOptions n;
  n.output = tmp / "n";
  n.restart = a.output / "fem_checkpoint_0000020.h5";
  try {
    run_fem_case(*cfg_heavier, unused, n);
    ADD_FAILURE() << "a checkpoint of lighter bodies was accepted";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("other densities"), std::string::npos) << err.what();
  }
  const std::string fixed_bodies =
      std::regex_replace(std::string(kFemMovingCase), std::regex(", density: 2500"), "");
  const std::string no_gravity =
      test::replaced(test::replaced(fixed_bodies, "  gravity: [0, -9.81]\n", ""),
                     "  moving_mesh: {repulsion: {range: 0.0012, force: 0.6, friction: 0.5, "
                     "tangential_stiffness: 400,\n"
                     "                            rolling_friction: 0.1}}\n",
                     "");
  const auto cfg_fixed = load_fem_case(tmp.write("fixed.yaml", no_gravity), unused);
  ASSERT_TRUE(cfg_fixed);
  RunOptions f;
  f.output = tmp / "f";
  f.restart = a.output / "fem_checkpoint_0000020.h5";
  try {
    run_fem_case(*cfg_fixed, unused, f);
    ADD_FAILURE() << "a moving run's checkpoint continued a case without free bodies";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("with free bodies and this case has none"),
              std::string::npos)
        << err.what();
  }
}
