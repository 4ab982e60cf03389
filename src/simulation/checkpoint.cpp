// SPDX-License-Identifier: GPL-3.0-or-later
// Checkpoints (HDF5): the whole state, including neighbour lists, contact histories and the
// random-generator state, so that a restart continues bit-identically.
#include <fmt/format.h>

#include <chrono>
#include <limits>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/version.hpp"
#include "io/restart/h5.hpp"
#include "simulation/simulation.hpp"

namespace gf {

void Simulation::save_checkpoint(const std::filesystem::path& file) const {
  REQUIRE(!kick_pending_, "internal: a checkpoint of a step whose second half kick is deferred");
  io::write_checkpoint_atomically(file, [&](io::h5::File& h) {
    io::set_checkpoint_identity(h);
    h.set_attribute("/", "case", cfg_.name);
    h.set_attribute("/", "step", static_cast<std::int64_t>(step_));
    h.set_attribute("/", "dt", dt_);
    h.set_attribute("/", "time", time());
    h.set_attribute("/", "skin", skin_);
    h.set_attribute("/", "rng_state", rng_.state());
    h.set_attribute("/", "n_contacts", static_cast<std::int64_t>(n_contacts_));
    h.set_attribute("/", "n_wall_contacts", static_cast<std::int64_t>(n_wall_contacts_));
    // History over restarts: the runs so far, this one included, and their wall time.
    const double running =
        run_started_
            ? std::chrono::duration<double>(StageTimers::clock::now() - *run_started_).count()
            : 0.0;
    h.set_attribute("/", "runs", runs_before_ + (run_started_ ? 1 : 0));
    h.set_attribute("/", "wall_seconds", wall_seconds_before_ + running);
    io::save_particles(h, particles_);

    h.create_group("neighbor");
    h.write("neighbor/offsets", nlist_.offsets());
    h.write("neighbor/neighbors", nlist_.neighbors());
    h.write("neighbor/history", nlist_.history());
    h.write("neighbor/reference_positions", nlist_.reference_positions());
    h.set_attribute("neighbor", "n_builds", static_cast<std::int64_t>(nlist_.n_builds()));
    h.write("neighbor/slab_starts", nlist_.slab_starts());
    if (has_capsules_) h.write("neighbor/axis_reference", std::span<const Vec3>(axis_ref_));
    h.set_attribute("neighbor", "n_phases", static_cast<std::int64_t>(nlist_.n_phases()));
    h.set_attribute("neighbor", "shear_offset_at_build", nlist_.shear_offset_at_build());
    h.set_attribute("neighbor", "refs_follow_wraps",
                    static_cast<std::int64_t>(nlist_.refs_follow_wraps() ? 1 : 0));

    h.create_group("walls");
    const auto entries = wlist_.entries();
    std::vector<std::int32_t> ep(entries.size()), ew(entries.size()), ee(entries.size());
    for (std::size_t k = 0; k < entries.size(); ++k) {
      ep[k] = entries[k].particle;
      ew[k] = entries[k].wall;
      ee[k] = entries[k].element;
    }
    h.write("walls/contact_particle", std::span<const std::int32_t>(ep));
    h.write("walls/contact_wall", std::span<const std::int32_t>(ew));
    h.write("walls/contact_element", std::span<const std::int32_t>(ee));
    h.write("walls/contact_history", wlist_.history());
    h.write("walls/point_at_build", std::span<const Vec3>(wall_point_at_build_));
    h.write("walls/dir_at_build", std::span<const Vec3>(wall_dir_at_build_));
    std::vector<Vec3> wf, wt;
    for (const auto& w : walls_) {
      wf.push_back(w.force);
      wt.push_back(w.torque);
    }
    h.write("walls/force", std::span<const Vec3>(wf));
    h.write("walls/torque", std::span<const Vec3>(wt));
    std::vector<Vec3> so, sv;
    for (const auto& w : walls_) {
      so.push_back(w.servo_offset);
      sv.push_back(w.servo_velocity);
    }
    h.write("walls/servo_offset", std::span<const Vec3>(so));
    h.write("walls/servo_velocity", std::span<const Vec3>(sv));
    if (heat_model_ >= 0) {  // (the heat flows of the last step, for a row written again)
      std::vector<double> hf;
      for (const auto& w : walls_) hf.push_back(w.heat_flow);
      h.write("walls/heat_flow", std::span<const double>(hf));
    }
    // The series' wall means of the interval in progress (a continued run writes the row that
    // an uninterrupted one would).
    for (const auto& [s, name] :
         {std::pair{&wall_sums_[0], "series"}, std::pair{&wall_sums_[1], "rheology"}}) {
      std::vector<Vec3> fs = s->force, ts = s->torque;
      fs.resize(walls_.size());
      ts.resize(walls_.size());
      h.write(fmt::format("walls/{}_force_sum", name), std::span<const Vec3>(fs));
      h.write(fmt::format("walls/{}_torque_sum", name), std::span<const Vec3>(ts));
      h.set_attribute("walls", fmt::format("{}_sum_steps", name), s->steps);
      if (s->closed_force.size() == walls_.size()) {  // (none before the first interval closed)
        h.write(fmt::format("walls/{}_closed_force", name), std::span<const Vec3>(s->closed_force));
        h.write(fmt::format("walls/{}_closed_torque", name),
                std::span<const Vec3>(s->closed_torque));
      }
    }

    if (!outlet_tallies_.empty()) {
      // The grains each outlet has taken so far, for the series' outlet_mass / outlet_count.
      h.create_group("outlets");
      std::vector<std::int64_t> count;
      std::vector<double> mass;
      for (const auto& t : outlet_tallies_) {
        count.push_back(t.count);
        mass.push_back(t.mass);
      }
      h.write("outlets/count", std::span<const std::int64_t>(count));
      h.write("outlets/mass", std::span<const double>(mass));
    }

    if (!meter_tallies_.empty()) {
      // The flow meters' net tallies, and their marks at the last series row (flow_rate): per
      // meter the mass, the mass and time at that row and the rate it showed.
      h.create_group("flow_meters");
      std::vector<std::int64_t> count;
      std::vector<double> state;
      for (const auto& t : meter_tallies_) {
        count.push_back(t.count);
        state.insert(state.end(), {t.mass, t.mass_at_row, t.time_at_row, t.rate_at_row});
      }
      h.write("flow_meters/count", std::span<const std::int64_t>(count));
      h.write("flow_meters/state", std::span<const double>(state));
    }

    h.set_attribute("/", "next_id", next_id_);
    if (!inlets_.empty()) {
      // What each inlet has inserted, and its batches (the next one's time).
      h.create_group("inlets");
      std::vector<std::int64_t> inserted, batches;
      std::vector<double> inserted_mass;
      for (const auto& in : inlets_) {
        inserted.push_back(in.inserted);
        batches.push_back(in.batches);
        inserted_mass.push_back(in.inserted_mass);
      }
      h.write("inlets/inserted", std::span<const std::int64_t>(inserted));
      h.write("inlets/batches", std::span<const std::int64_t>(batches));
      h.write("inlets/inserted_mass", std::span<const double>(inserted_mass));
    }

    if (cfd_) {
      const auto st = cfd_->state();
      h.create_group("fluid");
      h.set_attribute("fluid", "time", st.time);
      h.set_attribute("fluid", "dt_prev", st.dt_prev);
      h.set_attribute("fluid", "n_steps", st.n_steps);
      h.set_attribute("fluid", "history", static_cast<std::int64_t>(st.history));
      for (const auto& [name, v] : st.arrays) h.write("fluid/" + name, std::span<const double>(v));
    }
  });
}

void Simulation::load_checkpoint(const std::filesystem::path& file) {
  contacts_step_ = -1;  // the records of the constructor's force evaluation are not this state's
  auto h = io::h5::File::open_read(file);
  if (const auto kind = io::checkpoint_kind(h, file); !kind.empty())
    throw InputError(fmt::format("{}: a {} checkpoint; continue it with its {} case", file.string(),
                                 kind, kind));
  const double dt = h.read_double_attribute("/", "dt");
  if (dt != dt_)
    throw InputError(
        fmt::format("{}: checkpoint time step {} s differs from the case's time.step {} s",
                    file.string(), dt, dt_));
  // The particles and lists built from the case file are about to be replaced: free them
  // first, so that a restart holds one copy of the state at its peak, not two.
  particles_.resize(0);
  particles_.shrink_to_fit();
  const bool follow = nlist_.follows_wraps();  // the case's policy (set by the constructor)
  nlist_ = VerletList{};
  nlist_.set_follow_wraps(follow);
  step_ = h.read_int_attribute("/", "step");
  skin_ = h.read_double_attribute("/", "skin");
  rng_.set_state(h.read_string_attribute("/", "rng_state"));
  n_contacts_ = h.read_int_attribute("/", "n_contacts");
  n_wall_contacts_ = h.read_int_attribute("/", "n_wall_contacts");
  // (checkpoints before 2026-12-01 did not record them: one run at least, of unknown length)
  runs_before_ = h.has_attribute("/", "runs") ? h.read_int_attribute("/", "runs") : 1;
  wall_seconds_before_ = h.has_attribute("/", "wall_seconds")
                             ? h.read_double_attribute("/", "wall_seconds")
                             : std::numeric_limits<double>::quiet_NaN();
  io::load_particles(h, particles_);
  // (HDF5 checks the datasets' checksums; files of builds before them are checked here)
  if (const auto bad = first_non_finite_grain(particles_))
    throw InputError(fmt::format(
        "{}: grain {} has a non-finite position, velocity or spin: the checkpoint is damaged, or "
        "the run that wrote it had diverged",
        file.string(), particles_.id()[*bad]));
  if (const std::int32_t* fixed = particles_.fixed()) {
    // Grains of moving fixed groups follow motion k of this case (its k-th moving group): a
    // checkpoint whose grains name a motion the case does not have was written by another case.
    const auto n_motions = static_cast<std::int32_t>(fixed_motions_.size());
    for (std::size_t i = 0; i < particles_.size(); ++i)
      if (fixed[i] < 0 || fixed[i] >= ParticleStore::kFixedMoving + n_motions)
        throw InputError(fmt::format(
            "{}: grain {} belongs to a fixed group with prescribed motion {} (field 'fixed' = "
            "{}), but the case has {} fixed group{} with a motion (fixed: {{translate, rotate}}); "
            "was the checkpoint written by another case?",
            file.string(), particles_.id()[i], fixed[i] - ParticleStore::kFixedMoving + 1, fixed[i],
            n_motions, n_motions == 1 ? "" : "s"));
  }

  nlist_.restore(h.read_int64("neighbor/offsets"), h.read_int32("neighbor/neighbors"),
                 h.read_vec3("neighbor/history"), h.read_vec3("neighbor/reference_positions"),
                 skin_, h.read_int_attribute("neighbor", "n_builds"),
                 h.read_int64("neighbor/slab_starts"),
                 static_cast<int>(h.read_int_attribute("neighbor", "n_phases")));
  if (h.has_attribute("neighbor", "shear_offset_at_build"))
    nlist_.set_shear_offset_at_build(h.read_double_attribute("neighbor", "shear_offset_at_build"));
  // (older checkpoints: references measured through the current offset, the wider allowance)
  if (h.has_attribute("neighbor", "refs_follow_wraps"))
    nlist_.set_refs_follow_wraps(h.read_int_attribute("neighbor", "refs_follow_wraps") != 0);
  domain_.set_shear_time(time());
  // Capsule ends at the last build (older checkpoints: none, which forces a rebuild).
  axis_ref_.clear();
  // The skip's gaps belong to the list of the constructor's build: none until the next build.
  pair_gap_.clear();
  end_moved_.clear();
  if (has_capsules_ && h.exists("neighbor/axis_reference"))
    axis_ref_ = h.read_vec3("neighbor/axis_reference");
  if (nlist_.n_particles() != particles_.size())
    throw InputError(
        fmt::format("{}: neighbour list does not match the particle count", file.string()));

  const auto ep = h.read_int32("walls/contact_particle");
  const auto ew = h.read_int32("walls/contact_wall");
  // (checkpoints from before mesh walls have no elements: all 0)
  const auto ee = h.exists("walls/contact_element") ? h.read_int32("walls/contact_element")
                                                    : std::vector<std::int32_t>(ep.size(), 0);
  if (ew.size() != ep.size() || ee.size() != ep.size())
    throw InputError(fmt::format("{}: inconsistent wall contact list", file.string()));
  std::vector<WallContactList::Entry> entries(ep.size());
  for (std::size_t k = 0; k < ep.size(); ++k) {
    entries[k] = {ep[k], ew[k], ee[k]};
    const bool bad_wall = ew[k] < 0 || static_cast<std::size_t>(ew[k]) >= walls_.size();
    const bool bad_element =
        !bad_wall && (ee[k] < 0 || (walls_[static_cast<std::size_t>(ew[k])].kind == WallKind::Mesh
                                        ? static_cast<std::size_t>(ee[k]) >=
                                              walls_[static_cast<std::size_t>(ew[k])].mesh.size()
                                        : ee[k] != 0));
    if (ep[k] < 0 || static_cast<std::size_t>(ep[k]) >= particles_.size() || bad_wall ||
        bad_element)
      throw InputError(fmt::format(
          "{}: wall contact {} (particle {}, wall {}, element {}) does not fit this case's {} "
          "particles and walls (was the checkpoint written by another case or mesh file?)",
          file.string(), k, ep[k], ew[k], ee[k], particles_.size(), walls_.size()));
  }
  wlist_.restore(std::move(entries), h.read_vec3("walls/contact_history"));
  wall_point_at_build_ = h.read_vec3("walls/point_at_build");
  wall_dir_at_build_ = h.read_vec3("walls/dir_at_build");
  const auto wf = h.read_vec3("walls/force");
  const auto wt = h.read_vec3("walls/torque");
  if (wf.size() != walls_.size() || wall_point_at_build_.size() != walls_.size())
    throw InputError(fmt::format("{}: checkpoint has {} walls, the case {}", file.string(),
                                 wf.size(), walls_.size()));
  // Servo displacements (absent in checkpoints of older builds: walls without servo).
  std::vector<Vec3> so(walls_.size()), sv(walls_.size());
  if (h.exists("walls/servo_offset")) {
    so = h.read_vec3("walls/servo_offset");
    sv = h.read_vec3("walls/servo_velocity");
    if (so.size() != walls_.size() || sv.size() != walls_.size())
      throw InputError(fmt::format("{}: checkpoint has servo data for {} walls, the case {}",
                                   file.string(), so.size(), walls_.size()));
  }
  if (cfd_) {
    // The fluid continues where it was (checkpoints of builds before the fluid was saved:
    // it restarts from its initial condition).
    if (h.exists("fluid")) {
      auto st = cfd_->state();  // the names and sizes this case needs
      st.time = h.read_double_attribute("fluid", "time");
      st.dt_prev = h.read_double_attribute("fluid", "dt_prev");
      st.n_steps = h.read_int_attribute("fluid", "n_steps");
      st.history = static_cast<int>(h.read_int_attribute("fluid", "history"));
      for (auto& [name, v] : st.arrays) {
        if (!h.exists("fluid/" + name))
          throw InputError(
              fmt::format("{}: the checkpoint's fluid state has no '{}'", file.string(), name));
        v = h.read_double("fluid/" + name);
      }
      try {
        cfd_->restore(st);
      } catch (const InputError&) {
        throw;
      } catch (const Error& e) {
        throw InputError(
            fmt::format("{}: {} (was it written by another case?)", file.string(), e.what()));
      }
    } else {
      log::warn(
          "{}: no fluid state in the checkpoint; the fluid restarts from its initial "
          "condition",
          file.string());
    }
  } else if (h.exists("fluid")) {
    throw InputError(fmt::format(
        "{}: the checkpoint has a fluid state but the case has no fluid: block", file.string()));
  }
  // Wall means of the series interval in progress (absent in checkpoints of older builds: the
  // interval restarts here), and of the one closed last (absent in those of older builds and
  // before the first closed: a row written again at this step shows the current force).
  for (auto [s, name] :
       {std::pair{&wall_sums_[0], "series"}, std::pair{&wall_sums_[1], "rheology"}}) {
    s->clear(walls_.size());
    s->closed_force.clear();
    s->closed_torque.clear();
    if (h.exists(fmt::format("walls/{}_closed_force", name))) {
      s->closed_force = h.read_vec3(fmt::format("walls/{}_closed_force", name));
      s->closed_torque = h.read_vec3(fmt::format("walls/{}_closed_torque", name));
      if (s->closed_force.size() != walls_.size() || s->closed_torque.size() != walls_.size())
        throw InputError(
            fmt::format("{}: checkpoint has closed wall means for {} walls, the case {}",
                        file.string(), s->closed_force.size(), walls_.size()));
    }
    if (!h.exists(fmt::format("walls/{}_force_sum", name))) continue;
    s->force = h.read_vec3(fmt::format("walls/{}_force_sum", name));
    s->torque = h.read_vec3(fmt::format("walls/{}_torque_sum", name));
    s->steps = h.read_int_attribute("walls", fmt::format("{}_sum_steps", name));
    if (s->force.size() != walls_.size() || s->torque.size() != walls_.size())
      throw InputError(fmt::format("{}: checkpoint has wall sums for {} walls, the case {}",
                                   file.string(), s->force.size(), walls_.size()));
  }
  // Outlet tallies (none in a checkpoint of a case without outlets: they start from zero).
  outlet_tallies_.assign(outlet_regions_.size(), OutletTally{});
  if (!outlet_tallies_.empty() && h.exists("outlets/count")) {
    const auto count = h.read_int64("outlets/count");
    const auto mass = h.read_double("outlets/mass");
    if (count.size() != outlet_tallies_.size() || mass.size() != outlet_tallies_.size())
      throw InputError(fmt::format("{}: checkpoint has {} outlets, the case {}", file.string(),
                                   count.size(), outlet_tallies_.size()));
    for (std::size_t k = 0; k < count.size(); ++k) outlet_tallies_[k] = {count[k], mass[k]};
  }
  // Flow meters (a checkpoint of a case without them: they start from zero, now). Their
  // crossings are counted from the positions restored.
  meter_tallies_.assign(cfg_.flow_meters.size(), FlowMeterTally{});
  for (auto& t : meter_tallies_) t.time_at_row = time();
  if (!meter_tallies_.empty() && h.exists("flow_meters/count")) {
    const auto count = h.read_int64("flow_meters/count");
    const auto state = h.read_double("flow_meters/state");
    if (count.size() != meter_tallies_.size() || state.size() != 4 * count.size())
      throw InputError(fmt::format("{}: checkpoint has {} flow meters, the case {}", file.string(),
                                   count.size(), meter_tallies_.size()));
    for (std::size_t k = 0; k < count.size(); ++k)
      meter_tallies_[k] = {count[k], state[4 * k], state[4 * k + 1], state[4 * k + 2],
                           state[4 * k + 3]};
  }
  meter_x_.clear();
  if (!meter_tallies_.empty()) meter_x_.assign(particles_.x(), particles_.x() + particles_.size());
  // The next inlet grain's id (older checkpoints: after the largest id present).
  next_id_ = 1;
  for (std::size_t i = 0; i < particles_.size(); ++i)
    next_id_ = std::max(next_id_, particles_.id()[i] + 1);
  if (h.has_attribute("/", "next_id")) next_id_ = h.read_int_attribute("/", "next_id");
  for (auto& in : inlets_) {
    in.inserted = in.batches = 0;
    in.inserted_mass = 0;
  }
  if (!inlets_.empty() && h.exists("inlets/inserted")) {
    const auto inserted = h.read_int64("inlets/inserted");
    const auto batches = h.read_int64("inlets/batches");
    // (checkpoints written before mass rates: none, and no inlet with a mass rate then)
    const auto mass = h.exists("inlets/inserted_mass") ? h.read_double("inlets/inserted_mass")
                                                       : std::vector<double>(inserted.size());
    if (inserted.size() != inlets_.size() || batches.size() != inlets_.size() ||
        mass.size() != inlets_.size())
      throw InputError(fmt::format("{}: checkpoint has {} inlets, the case {}", file.string(),
                                   inserted.size(), inlets_.size()));
    for (std::size_t k = 0; k < inlets_.size(); ++k) {
      inlets_[k].inserted = inserted[k];
      inlets_[k].batches = batches[k];
      inlets_[k].inserted_mass = mass[k];
    }
  }
  std::vector<double> heat_flow(walls_.size(), 0.0);
  if (heat_model_ >= 0 && h.exists("walls/heat_flow")) {
    heat_flow = h.read_double("walls/heat_flow");
    if (heat_flow.size() != walls_.size())
      throw InputError(fmt::format("{}: checkpoint has heat flows for {} walls, the case {}",
                                   file.string(), heat_flow.size(), walls_.size()));
  }
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    walls_[w].heat_flow = heat_flow[w];
    walls_[w].servo_offset = so[w];
    walls_[w].servo_velocity = sv[w];
    walls_[w].update_geometry(time());
    walls_[w].force = wf[w];
    walls_[w].torque = wt[w];
  }
}

}  // namespace gf
