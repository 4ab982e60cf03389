#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Instructions (callgrind Ir) per particle-step, per stage of the DEM time step.
# Runs `grainflow run CASE --restart CHECKPOINT` under callgrind, collecting only inside
# Simulation::step() (setup, restart reading and output excluded), then splits the inclusive
# counts by stage. Counts are independent of machine load (wall times are not).
# Usage: callgrind_stages.py GRAINFLOW CASE.yaml CHECKPOINT.h5 N_PARTICLES [OUT_PREFIX]
#   steps = (time.end - checkpoint time) / dt, read from the run's summary.json.
import json
import os
import re
import subprocess
import sys
import tempfile

STAGES = [
    ("step (total)", r"gf::Simulation::step\(\)"),
    ("neighbor: needs_rebuild", r"gf::VerletList::needs_rebuild\("),
    ("neighbor: sort_and_build", r"gf::VerletList::sort_and_build\("),
    ("neighbor: update_neighbors (all)", r"gf::Simulation::update_neighbors\("),
    ("force: reset_forces", r"gf::reset_forces\("),
    ("force: compute_pair_forces", r"gf::contact::compute_pair_forces\("),
    ("walls: compute_wall_forces", r"gf::compute_wall_forces\("),
    ("integrate: pre_force", r"gf::VelocityVerlet::pre_force\("),
    ("integrate: post_force", r"gf::VelocityVerlet::post_force\("),
]


def main():
    gf, case, ckpt, n = sys.argv[1:5]
    n = int(n)
    prefix = sys.argv[5] if len(sys.argv) > 5 else None
    work = tempfile.mkdtemp(prefix="gf_cg_")
    out = prefix + ".cg" if prefix else os.path.join(work, "cg.out")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                    "--toggle-collect=gf::Simulation::step()", gf, "run", case, "--restart", ckpt,
                    "--output", os.path.join(work, "run"), "--overwrite", "--threads", "1"],
                   env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(work, "run", "summary.json")) as f:
        summary = json.load(f)
    steps = summary["steps"]
    ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", out],
                         capture_output=True, text=True).stdout
    incl = {}
    for line in ann.splitlines():
        m = re.match(r"\s*([\d,]+) \([^)]*\)\s+(.*)", line)
        if not m:
            continue
        ir = int(m.group(1).replace(",", ""))
        # "file:function [object]": the function part must start with the stage's function
        # (lambdas and loops inlined into it are listed as "file:function::{lambda...}" too,
        # with smaller counts; the largest entry is the function's inclusive cost).
        fn = m.group(2).split(":", 1)[-1]
        for label, pat in STAGES:
            if re.match(pat, fn):
                incl[label] = max(incl.get(label, 0), ir)
    ps = n * steps
    print(f"# {steps} steps x {n} particles = {ps} particle-steps (callgrind Ir, step() only)")
    for label, _ in STAGES:
        ir = incl.get(label, 0)
        print(f"{label:36s} {ir:15,d}  {ir / ps:9.1f} Ir/particle-step")
    step = incl.get("step (total)", 0)
    other = step - sum(incl.get(l, 0) for l, _ in STAGES
                       if l not in ("step (total)", "neighbor: needs_rebuild",
                                    "neighbor: sort_and_build"))
    print(f"{'other (timers, wall motion, ...)':36s} {other:15,d}  {other / ps:9.1f} Ir/particle-step")


main()
