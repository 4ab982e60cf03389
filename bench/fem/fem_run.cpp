// SPDX-License-Identifier: GPL-3.0-or-later
// Standalone runner of a `fluid_fem:` case until the grainflow command wires it in.
// Usage: gf_fem_run <case.yaml> <output dir> [max steps]; exit code 2 on input errors.
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <cstdlib>

#include "core/error.hpp"
#include "fluid/fem/case.hpp"

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: gf_fem_run <case.yaml> <output dir> [max steps]\n");
    return 2;
  }
  try {
    YAML::Node doc;
    try {
      doc = YAML::LoadFile(argv[1]);
    } catch (const YAML::Exception& e) {
      throw gf::InputError(std::string(argv[1]) + ":" + std::to_string(e.mark.line + 1) + ":" +
                           std::to_string(e.mark.column + 1) + ": " + e.msg);
    }
    if (!doc["fluid_fem"].IsDefined())
      throw gf::InputError(std::string(argv[1]) + ": no 'fluid_fem' block");
    const auto cfg = gf::fem::parse_fluid_fem(doc["fluid_fem"], argv[1]);
    gf::fem::run_fluid_fem(cfg, argv[2], argc == 4 ? std::atoi(argv[3]) : -1);
  } catch (const gf::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
