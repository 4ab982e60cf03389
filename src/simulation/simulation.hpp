// SPDX-License-Identifier: GPL-3.0-or-later
// Simulation: the DEM state built from a validated case, and the time loop as named stages.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "analysis/mixing.hpp"
#include "analysis/rheology.hpp"
#include "boundaries/fill.hpp"
#include "boundaries/wall.hpp"
#include "contact/laws/contact_io.hpp"
#include "contact/pair_forces.hpp"
#include "core/domain.hpp"
#include "core/rng.hpp"
#include "core/timer.hpp"
#include "io/input/config.hpp"
#include "neighbor/verlet_list.hpp"
#include "particles/material.hpp"
#include "particles/particle_store.hpp"
#include "simulation/cfd_dem_coupling.hpp"
#include "simulation/output_folder.hpp"

namespace gf {

namespace gpu {
class SphereDem;
}

/// Where the DEM steps run: on the host's cores, or on a CUDA device (docs/gpu.md); HostMirror
/// runs the device's algorithm on the host (tests: it checks that algorithm where no GPU is).
enum class Device { Cpu, Cuda, HostMirror };

struct RunOptions {
  std::filesystem::path output;  ///< empty: the case's output.directory
  bool overwrite = false;        ///< allow writing into an existing, non-empty folder
  std::optional<std::filesystem::path> restart;
  /// With restart: continue in the existing output folder (series, rheology samples and
  /// ParaView series kept up to the checkpoint and continued) instead of a fresh one.
  bool append = false;
  std::optional<std::int64_t> steps;  ///< run this many steps instead of up to time.end
  bool quiet = false;                 ///< no progress output
  /// The case file, if any: --overwrite refuses a folder that holds it.
  std::filesystem::path case_file;
  Device device = Device::Cpu;
};

/// Summary of a finished run (also written as summary.json).
struct RunSummary {
  std::int64_t n_particles = 0;
  std::int64_t steps = 0;
  double loop_seconds = 0;
  double particle_steps_per_second = 0;
  std::int64_t peak_rss_bytes = 0;
  /// SIGINT / SIGTERM (or stop::kTimeLimit, --max-hours) that stopped the run before its end
  /// (see core/stop.hpp), else 0; the outputs were written and `checkpoint` continues the run.
  int stop_signal = 0;
  std::filesystem::path checkpoint;  ///< the checkpoint written at the run's last step
};

/// With opts.append: a checkpoint must be given, --overwrite not, and `dir` must exist
/// (InputError otherwise); without, nothing. Shared by DEM and FEM runs.
void check_append(const std::filesystem::path& dir, const RunOptions& opts);

class Simulation {
 public:
  /// Builds particles (fills, explicit lists), walls and per-pair tables from the case.
  explicit Simulation(const config::Case& cfg);

  /// Advances one time step. With `defer_kick` the second half kick may be left pending (grains
  /// without shapes, velocity Verlet, no fluid step due) and done by the next step's drift in
  /// the same pass: bit-identical, one pass over the particles fewer. Only for a caller that
  /// reads no velocity before the next step() or complete_step().
  void step(bool defer_kick = false);
  /// Completes a deferred half kick (no-op without one): velocities are those of the step's end.
  void complete_step();
  /// Runs to the end time (or opts.steps steps) with all outputs; returns the summary.
  RunSummary run(const RunOptions& opts);

  void save_checkpoint(const std::filesystem::path& file) const;
  void load_checkpoint(const std::filesystem::path& file);

  double time() const { return static_cast<double>(step_) * dt_; }
  std::int64_t step_count() const { return step_; }
  double dt() const { return dt_; }
  const Vec3& gravity() const { return gravity_; }
  std::int64_t n_contacts() const { return n_contacts_; }
  std::int64_t n_wall_contacts() const { return n_wall_contacts_; }

  ParticleStore& particles() { return particles_; }
  const ParticleStore& particles() const { return particles_; }
  const Domain& domain() const { return domain_; }
  std::vector<Wall>& walls() { return walls_; }
  const std::vector<Wall>& walls() const { return walls_; }
  const PairTable<contact::PairCoeffs>& pairs() const { return pairs_; }
  const VerletList& neighbor_list() const { return nlist_; }
  const WallContactList& wall_list() const { return wlist_; }
  const StageTimers& timers() const { return timers_; }
  const config::Case& config() const { return cfg_; }
  /// The CFD-DEM fluid and its coupling (cases with fluid: and coupling:), else nullptr.
  const CfdDemCoupling* cfd_dem() const { return cfd_.get(); }

  /// The grains taken by each outlet so far (the case's outlets, in order).
  struct OutletTally {
    std::int64_t count = 0;
    double mass = 0;  ///< kg
  };
  std::span<const OutletTally> outlet_tallies() const { return outlet_tallies_; }
  /// Grains the particle groups' inlets have inserted so far (all inlets).
  std::int64_t inserted_grains() const;
  /// What each flow meter (the case's flow_meters, in order) has counted so far: the net number
  /// and mass of grains that crossed its plane along its normal; and the mass and time at the
  /// previous series row (flow_rate: the net mass per time since then), and the rate that row
  /// showed (a run continued from a checkpoint of that step writes the row again).
  struct FlowMeterTally {
    std::int64_t count = 0;
    double mass = 0;  ///< kg
    double mass_at_row = 0, time_at_row = 0;
    double rate_at_row = 0;  ///< kg/s
    /// flow_rate now: the net mass per time since the previous row; at that row's time, the rate
    /// it showed.
    double rate(double now) const {
      return now > time_at_row ? (mass - mass_at_row) / (now - time_at_row) : rate_at_row;
    }
  };
  std::span<const FlowMeterTally> flow_meter_tallies() const { return meter_tallies_; }
  /// The Lacey mixing index of analysis.mixing's two materials now (free grains only).
  analysis::LaceyIndex lacey_index() const;

  /// Why this case cannot run its steps on the CUDA back end (`grainflow run --device cuda`,
  /// docs/gpu.md): what it has that the back end lacks; empty when it can.
  std::string device_unsupported() const;

  /// Total energy (kinetic + gravitational + elastic in contacts), J.
  double total_energy() const;
  /// Value of a series quantity by name (see the case-file reference), at the current state.
  double quantity(const std::string& name) const;
  /// Values of several series columns, sharing the O(N) reductions.
  std::vector<double> series_row(const std::vector<std::string>& columns) const;
  /// Series column names for the configured quantities (wall_force.X expands to .x/.y/.z).
  std::vector<std::string> series_columns() const;
  /// Who reads the walls' forces and torques averaged over the steps of an interval: the
  /// series (wall_force_mean, wall_torque_mean; interval: since the previous row) and the
  /// rheology samples (wall tractions; since the previous sample).
  enum class WallMeans { Series, Rheology };
  /// Mean force (torque) on wall k over the steps of `who`'s interval so far; when the interval
  /// has no step yet, the mean of the interval the reset at this step closed (a row written
  /// again at a restart's step shows what it showed), else (no interval yet) the current one.
  Vec3 wall_mean_force(WallMeans who, std::size_t k) const;
  Vec3 wall_mean_torque(WallMeans who, std::size_t k) const;
  /// Closes `who`'s interval and starts the next.
  void reset_wall_means(WallMeans who) { wall_sums_[static_cast<int>(who)].close(walls_.size()); }
  /// A series row was written now: the interval quantities (wall_force_mean, wall_torque_mean,
  /// flow_rate) start their next interval.
  void series_row_written();

  /// Rheology (analysis.rheology): the measured layer, one grain length (2 x the largest
  /// bounding radius) or analysis.rheology.margin away from walls.
  const analysis::RheologyRegion& rheology_region() const { return rheo_region_; }
  /// Whether the next force stages collect the contact virial of the measured layer.
  void collect_virial(bool on) { collect_virial_ = on; }
  /// A sample of the current state; the last force stage must have collected the virial.
  analysis::RheologySample rheology_sample() const;
  /// For tests: whether the capsules' force loop may skip list entries that cannot touch
  /// (contact::PairSkip; on by default; the forces are the same either way), and whether it does
  /// now (capsules, a list built by this run).
  void use_pair_skip(bool on) { pair_skip_on_ = on; }
  bool pair_skip_active() const { return pair_skip_on_ && !pair_gap_.empty(); }
  /// Whether the next force stages record every touching grain pair and grain-wall contact
  /// (output.contacts_csv, output.contacts_vtk).
  void collect_contacts(bool on) { collect_contacts_ = on; }
  /// The touching pairs of the last force stage that recorded them, in neighbour-list order
  /// (records with i < 0 are list entries whose pair was apart); empty if none did.
  std::span<const contact::ContactRecord> contact_records() const { return contact_records_; }
  /// The grain-wall contacts of that stage, slots() records per wall-list entry (j: the wall's
  /// index in walls(); see compute_wall_forces); empty without walls.
  std::span<const contact::ContactRecord> wall_contact_records() const { return wall_records_; }
  /// Writes the contacts of the last force stage that recorded them (docs/output.md):
  /// contacts_NNNNNNNNN.csv (grain pairs) and, in a run with walls, wall_contacts_NNNNNNNNN.csv
  /// into `dir`; false (nothing written) if that stage did not record them.
  bool write_contacts_csv(const std::filesystem::path& dir) const;
  /// The same network as line cells (pairs and walls), contacts_NNNNNNNNN.vtp in `dir`; false
  /// (nothing written) if the last force stage did not record it. `file` gets the file's name.
  bool write_contacts_vtp(const std::filesystem::path& dir, std::string& file) const;

 private:
  void build_materials_and_pairs();
  void build_particles();
  void build_walls();
  void update_neighbors(bool force);
  /// Removes the free grains whose centre lies in an outlet's region and counts them there (the
  /// first outlet that holds a grain takes it); an outlet with a reinsert region puts its grains
  /// back there instead (reinsert_grains). Returns, for each grain left, its index before the
  /// removal, -1 for a grain put back (new to the list build: no contact history); empty when
  /// none was removed or put back (the indices are unchanged).
  std::vector<std::int64_t> take_outlet_grains();
  /// Drops the outlines no grain refers to any more (those of grains the outlets took) once they
  /// are most of the table, and renumbers the grains' `polygon` indices (order kept).
  void compact_polygon_table();
  /// Counts the free grains whose centres crossed a flow meter's plane (within its radius)
  /// since the last count, at each step after the drift (before any list build changes the
  /// store): the displacement from meter_x_ (minimum image: a wrap through a periodic boundary
  /// is the short step it is), the side of the plane's nearest image before and after.
  void count_meter_crossings();
  /// Places each grain of `grains` (indices) at rest at a uniformly random place of `region`
  /// where it lies wholly inside and overlaps no other grain (bounding spheres); Error when 1000
  /// tries find none.
  void reinsert_grains(std::span<const std::int64_t> grains, const FillRegion& region,
                       const std::string& outlet);
  /// The grains whose centre lies within `reach` of `region`'s bounds.
  std::vector<std::size_t> grains_near(const FillRegion& region, double reach) const;
  /// A uniformly random place of `region` where a grain of radius r lies wholly inside and
  /// meets none of `near` but `self` (bounding spheres); nullopt when 1000 tries find none.
  std::optional<Vec3> free_place(const FillRegion& region, double r,
                                 const std::vector<std::size_t>& near, std::size_t self);
  /// Whether an inlet's batch is due now.
  bool inlets_due() const;
  /// Appends the grains of the inlets' batches due now at the end of the store; returns how
  /// many.
  std::size_t insert_inlet_grains();
  /// Whether an end of some spherocylinder moved more than skin/2 since the last build.
  bool capsule_ends_moved() const;
  /// h u of every grain now when spherocylinders meet mesh walls (the wall list then lists
  /// triangles by their distance from the axes), else null.
  const Vec3* wall_half_axes();
  /// pair_gap_ of the list just built (capsules), and the Lees-Edwards offset it was built at.
  void build_pair_gaps();
  /// Target force of servo wall w: pressure x the current area between its span walls, N.
  double servo_target_force(std::size_t w) const;
  /// Moves the servo walls after a force evaluation (Wall::servo_step).
  void update_servos();
  /// Places the grains of fixed groups with prescribed motion at time t: position
  /// motion.carry(fixed_x0, t) wrapped into the periodic box, orientation motion.turn(fixed_q0,
  /// t), velocity and angular velocity of the rigid motion there (and the angular momentum of
  /// spherocylinders that goes with it). Analytic, so without drift. Within a step (drift_max_d2_
  /// >= 0) it adds their displacements since the list build to the rebuild test.
  void place_fixed_groups(double t);
  /// Torque on the grains of the rotating fixed groups about their (common) rotation centre now,
  /// N m: sum of (x_i - c(t)) x (f_i - m_i g) + torque_i, x_i not wrapped.
  Vec3 fixed_group_torque() const;
  void compute_forces();
  /// Device runs (device_run.cpp): the CUDA engine set up from the current state (grains,
  /// walls, contact histories), and its state copied back: grains, contact counts and wall
  /// forces; with `lists`, also the neighbour and wall lists, rebuilt in the current order with
  /// the device's contact histories (for checkpoints and the elastic energy).
  std::shared_ptr<gpu::SphereDem> start_device(Device device);
  void sync_from_device(const gpu::SphereDem& d, bool lists);

  config::Case cfg_;
  ParticleStore particles_;
  Domain domain_;
  Vec3 gravity_;
  double dt_ = 0;
  double skin_ = 0;
  std::int64_t step_ = 0;
  std::vector<Material> materials_;
  PairTable<contact::PairCoeffs> pairs_;
  std::vector<Wall> walls_;
  std::vector<FillRegion> outlet_regions_;  ///< cfg_.outlets' regions
  /// Where outlet k puts its grains back (cfg_.outlets[k].reinsert), else nullopt: removed.
  std::vector<std::optional<FillRegion>> outlet_reinsert_;
  std::vector<OutletTally> outlet_tallies_;
  std::vector<FlowMeterTally> meter_tallies_;  ///< per cfg_.flow_meters entry
  /// The grains' centres at the last crossing count (the store's order; set anew after every
  /// list build, which may re-order, remove or insert grains, and at a restart).
  std::vector<Vec3> meter_x_;
  mutable std::vector<std::int32_t> mixing_kind_;  ///< scratch of lacey_index()
  /// A particle group's inlet (config::Inlet) and what it has done.
  struct InletState {
    std::size_t group = 0;
    FillRegion region;
    int material = 0;
    double rate = 0, start = 0, stop = 0, every = 0;  ///< stop: infinity without one
    double mass_rate = 0;                             ///< kg/s (0: `rate` grains per second)
    Vec3 velocity;
    std::int64_t inserted = 0, batches = 0;
    double inserted_mass = 0;  ///< kg
    /// Whether its next batch is due at time t (before the stop).
    bool due(double t) const;
  };
  std::vector<InletState> inlets_;
  std::int64_t next_id_ = 1;  ///< the id of the next grain an inlet inserts
  bool inlet_short_warned_ = false;
  std::vector<Vec3> wall_point_at_build_, wall_dir_at_build_;
  VerletList nlist_;
  WallContactList wlist_;
  Rng rng_;
  StageTimers timers_;
  std::int64_t n_contacts_ = 0, n_wall_contacts_ = 0;
  bool two_d_ = false;  ///< dimension: 2 (grains in z = 0, rotation about z)
  bool has_capsules_ = false;
  std::vector<Vec3> axis_ref_;   ///< h * axis of each grain at the last build (capsules)
  std::vector<Vec3> half_axes_;  ///< h * axis now, for the wall list (capsules with mesh walls)
  bool has_mesh_walls_ = false;
  /// Capsules: per list entry, the axes' distance at the last build less the radii; per grain,
  /// the largest move of an axis end since (contact::PairSkip); the Lees-Edwards offset of that
  /// build (m). Empty: no skip.
  std::vector<double> pair_gap_;
  double gap_offset_ = 0.0;
  bool pair_skip_on_ = true;
  mutable std::vector<double> end_moved_;
  bool gear_ = false;  ///< integrator: gear5
  /// Prescribed motions of the fixed groups that move (`fixed: {translate, rotate}`), in case
  /// order: motion k carries the grains whose `fixed` is ParticleStore::kFixedMoving + k.
  /// `rotates`: the group has a rotate: motion (fixed_torque is about its centre).
  struct FixedMotion {
    RigidMotion motion;
    bool rotates = false;
  };
  std::vector<FixedMotion> fixed_motions_;
  analysis::RheologyRegion rheo_region_;
  bool collect_virial_ = false;
  bool collect_contacts_ = false;
  std::int64_t contacts_step_ = -1;  ///< the step whose force stage recorded contact_records_
  std::vector<contact::ContactRecord> contact_records_, wall_records_;
  /// Sums of each wall's force and torque over the steps of an interval, and their number, and
  /// the means of the interval closed last (empty before the first); one per WallMeans reader,
  /// kept in checkpoints.
  struct WallSums {
    std::vector<Vec3> force, torque;
    std::int64_t steps = 0;
    std::vector<Vec3> closed_force, closed_torque;
    void clear(std::size_t n) {
      force.assign(n, Vec3{});
      torque.assign(n, Vec3{});
      steps = 0;
    }
    /// Keeps the interval's means (unless it had no step: then those of the one before) and
    /// starts the next.
    void close(std::size_t n) {
      if (steps > 0) {
        const double w = 1.0 / static_cast<double>(steps);
        closed_force.resize(force.size());
        closed_torque.resize(torque.size());
        for (std::size_t k = 0; k < force.size(); ++k) {
          closed_force[k] = w * force[k];
          closed_torque[k] = w * torque[k];
        }
      }
      clear(n);
    }
  };
  std::array<WallSums, 2> wall_sums_;
  // Heat conduction (heat:): the conduction model's index (-1: none), the series conductivity
  // per material pair (W/(m K)) and the heat capacity per material (J/(kg K)), the grains'
  // fields of temperature, net heat flow of the last step (W) and heat source (W; -1: none),
  // and the step's per-grain sums of the conductances (W/K) and per-entry conductances.
  int heat_model_ = -1;
  PairTable<double> k_series_;
  std::vector<double> heat_capacity_;
  int f_temperature_ = -1, f_heat_flow_ = -1, f_heat_source_ = -1;
  std::vector<double> heat_h_, heat_entry_h_;
  // Spheres: each list entry's overlap, recorded by the force loop for conduct_heat (sized to
  // the list at the step's compute_forces; empty with shapes, which take the visitor).
  std::vector<double> heat_overlap_;
  /// Heat flows through the contacts of this step's positions, then the explicit step of the
  /// grains' temperatures.
  void conduct_heat();
  /// Sums over the grains whose centre `in(x)` accepts: x: heat capacity m c (J/K), y: thermal
  /// energy m c T (J).
  template <class In>
  Vec3 heat_sums(In&& in) const;
  // Set by the drift of this step (VelocityVerlet with DriftExtras): the forces are already
  // m g, and the largest squared displacement since the last list build (< 0: not measured).
  bool forces_reset_ = false;
  double drift_max_d2_ = -1;
  bool kick_pending_ = false;      ///< the last step's second half kick is deferred (step())
  std::vector<Mat3> virial_rows_;  ///< per row of the force loop (no races), summed in order
  std::vector<Mat3> normal_rows_;  ///< the same for the contact normals' n (x) n
  analysis::ContactSums contact_sums_;
  std::unique_ptr<CfdDemCoupling> cfd_;  ///< unresolved CFD-DEM (optional)
  // The runs that led to the state a checkpoint continues (summary.json's totals over restarts):
  // their number and wall time (NaN: a checkpoint of a build that did not record it), and when
  // the current run's time loop started.
  std::int64_t runs_before_ = 0;
  double wall_seconds_before_ = 0;
  std::optional<StageTimers::clock::time_point> run_started_;
};

}  // namespace gf
