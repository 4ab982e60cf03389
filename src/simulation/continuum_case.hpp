// SPDX-License-Identifier: GPL-3.0-or-later
// Dispatch of `continuum:` cases (SPH) from the grainflow command line: check, run, outputs.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/input/parse_case.hpp"
#include "io/input/parse_continuum.hpp"
#include "simulation/simulation.hpp"

namespace gf {

/// Reads `file` if it is a continuum case (a `continuum:` block at the top), else nullopt.
/// `output_dir` receives output.directory (default out/<case folder name>). Top-level keys other
/// than name, continuum and output are refused with their line.
std::optional<input::ContinuumCase> load_continuum_case(
    const std::filesystem::path& file, std::filesystem::path& output_dir,
    const std::vector<input::Override>& overrides);

/// Derived numbers for `grainflow check` (label, value): particles, h, c0, the time step and its
/// limits, steps to the end, the Mach number of a free fall over the fluid's height.
std::vector<std::pair<std::string, std::string>> describe_continuum_case(
    const input::ContinuumCase& c);

/// Runs the case, writing into `default_dir` (or opts.output): sph_particles_NNNNN.vtp +
/// sph_particles.pvd (fluid and wall particles, ParaView series), sph_series.csv (time series:
/// energy, extent of the fluid, force on each wall), sph_summary.txt, and HDF5 checkpoints
/// sph_checkpoint_NNNNNNNNN.h5 (every output.checkpoint_every, named by step) and
/// sph_checkpoint_final.h5 (at the end or a stop). opts.restart continues from a checkpoint
/// bit-identically; with opts.append in the folder of the run it continues (its series kept up
/// to the checkpoint), else in a new folder. opts.steps: steps of this run. Everything is checked
/// and built before the folder is touched. Returns the SIGINT / SIGTERM that ended it early
/// (outputs and a final checkpoint written), else 0.
int run_continuum_case(const input::ContinuumCase& c, const std::filesystem::path& default_dir,
                       const RunOptions& opts);

}  // namespace gf
