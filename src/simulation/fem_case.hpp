// SPDX-License-Identifier: GPL-3.0-or-later
// Cases whose physics is the resolved 2D FEM flow (a `fluid_fem:` block): detection and run.
#pragma once

#include <filesystem>
#include <optional>

#include "fluid/fem/case.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"

namespace gf {

/// Reads the case file; if it holds a `fluid_fem:` block, returns the parsed FEM case (strict:
/// the only other top-level keys allowed are `name` and `output: {directory}`), else nothing.
/// YAML syntax errors and wrong keys throw gf::InputError with file:line:column.
/// `overrides` (--set KEY.PATH=VALUE) are applied to the YAML before it is read.
std::optional<fem::FemCaseConfig> load_fem_case(const std::filesystem::path& file,
                                                std::filesystem::path& output_dir,
                                                const std::vector<input::Override>& overrides = {});

/// Runs a FEM case with the same output-folder policy as DEM runs (refuses a non-empty folder
/// without --overwrite); opts.steps limits the number of time steps; opts.restart continues an
/// unsteady run from a fem_checkpoint_*.h5 bit-identically. Returns the SIGINT / SIGTERM that
/// stopped the run early (outputs and a checkpoint written), else 0.
int run_fem_case(const fem::FemCaseConfig& cfg, const std::filesystem::path& default_dir,
                 const RunOptions& opts);

/// Writes / reads a fluid_fem checkpoint (HDF5, written atomically). Reading a file that is not
/// a grainflow fluid_fem checkpoint throws InputError.
void save_fem_checkpoint(const std::filesystem::path& file, const fem::FemCheckpoint& c);
fem::FemCheckpoint load_fem_checkpoint(const std::filesystem::path& file);

}  // namespace gf
