// SPDX-License-Identifier: GPL-3.0-or-later
// Dispatch of `two_fluid:` cases (Eulerian-Eulerian fluid + granular phase) from the grainflow
// command line: check, run, outputs, checkpoints.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/input/parse_case.hpp"
#include "io/input/parse_two_fluid.hpp"
#include "simulation/simulation.hpp"

namespace gf {

/// Reads `file` if it is a two-fluid case (a `two_fluid:` block at the top), else nullopt.
/// `output_dir` receives output.directory (default out/<case folder name>). Top-level keys other
/// than name, two_fluid and output are refused with their line.
std::optional<input::TwoFluidCase> load_two_fluid_case(
    const std::filesystem::path& file, std::filesystem::path& output_dir,
    const std::vector<input::Override>& overrides);

/// Derived numbers for `grainflow check` (label, value): cells and their size in grain
/// diameters, the solids inventory, the grains' terminal velocity and Reynolds number, Ergun's
/// minimum fluidisation velocity at the densest initial fraction, the first time step.
std::vector<std::pair<std::string, std::string>> describe_two_fluid_case(
    const input::TwoFluidCase& c);

/// Runs the case, writing into `default_dir` (or opts.output): two_fluid_NNNNN.vti +
/// two_fluid.pvd (cell fields, ParaView series), two_fluid_series.csv, two_fluid_summary.txt,
/// resolved_case.yaml and HDF5 checkpoints two_fluid_checkpoint_NNNNNNNNN.h5 (every
/// output.checkpoint_every) and two_fluid_checkpoint_final.h5. opts.restart continues from a
/// checkpoint bit-identically (with opts.append in the run's folder, its series kept up to the
/// checkpoint). Everything is checked and built before the folder is touched. Returns the
/// SIGINT / SIGTERM that ended it early (outputs and a final checkpoint written), else 0.
int run_two_fluid_case(const input::TwoFluidCase& c, const std::filesystem::path& default_dir,
                       const RunOptions& opts);

}  // namespace gf
