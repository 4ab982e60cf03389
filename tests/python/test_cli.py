#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Command-line behaviour: restart bit-identity through files, exit code 2 on bad input, and no
# output written or overwritten by a failed run.
"""Usage: test_cli.py GRAINFLOW SOURCE_DIR"""
import filecmp
import os
import subprocess
import sys
import tempfile

CASE = """name: cli_test
dimension: 3
time: {step: 2.0e-5, end: 0.04}
domain: {min: [0, 0, 0], max: [0.04, 0.04, 0.08], periodic: [true, false, false]}
gravity: [0, 0, -9.81]
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5, friction: 0.5}
particles:
  - shape: sphere
    radius: {distribution: uniform, min: 0.002, max: 0.003}
    material: glass
    fill: {box: {min: [0, 0, 0], max: [0.04, 0.04, 0.05]}, lattice: random, count: 120, seed: 5,
           velocity_jitter: 0.3}
walls:
  - {name: floor, plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
output:
  directory: out
  particles_csv: {every: 0.02}
  series: {every: 0.002, quantities: [kinetic_energy, wall_force.floor.z]}
  checkpoint: {every: 0.02}
"""

passed = failed = 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAIL:", what)


def run(*args):
    return subprocess.run([GF, *args], capture_output=True, text=True, cwd=TMP)


GF = os.path.abspath(sys.argv[1])
with tempfile.TemporaryDirectory() as TMP:
    case = os.path.join(TMP, "case.yaml")
    with open(case, "w") as f:
        f.write(CASE)
    r = run("run", case, "--output", "full", "--quiet")
    check(r.returncode == 0, f"full run failed: {r.stderr}")
    r = run("run", case, "--output", "second", "--quiet",
            "--restart", os.path.join(TMP, "full", "checkpoint_000001000.h5"))
    check(r.returncode == 0, f"restarted run failed: {r.stderr}")
    a = os.path.join(TMP, "full", "particles_000002000.csv")
    b = os.path.join(TMP, "second", "particles_000002000.csv")
    check(os.path.exists(a) and os.path.exists(b), "final particle CSV files exist")
    check(os.path.exists(a) and os.path.exists(b) and filecmp.cmp(a, b, shallow=False),
          "restart continues bit-identically (particle CSV at the end)")

    # An existing output folder is not overwritten unless asked.
    before = open(a).read()
    r = run("run", case, "--output", "full", "--quiet")
    check(r.returncode == 2, f"reusing an output folder must exit 2, got {r.returncode}")
    check("--overwrite" in r.stderr, "the error suggests --overwrite")
    check(open(a).read() == before, "earlier output untouched")

    # Bad input: exit code 2, file:line in the message, nothing written.
    bad = os.path.join(TMP, "bad.yaml")
    with open(bad, "w") as f:
        f.write(CASE.replace("restitution: 0.5", "restitution: 1.5"))
    r = run("run", bad, "--output", "bad_out")
    check(r.returncode == 2, f"bad case must exit 2, got {r.returncode}")
    check("bad.yaml:9:" in r.stderr and "restitution" in r.stderr, f"message names file:line and key: {r.stderr}")
    check(not os.path.exists(os.path.join(TMP, "bad_out")), "a failed validation writes nothing")
    r = run("run", bad, "--output", "full", "--overwrite")
    check(r.returncode == 2 and open(a).read() == before, "failed validation leaves --overwrite target intact")
    r = run("check", bad)
    check(r.returncode == 2, "check of a bad case exits 2")
    r = run("check", case)
    check(r.returncode == 0 and "particles" in r.stdout, "check of a good case prints derived numbers")
    r = run("describe", "nope")
    check(r.returncode == 2, "describe of an unknown key exits 2")
    r = run("run")
    check(r.returncode == 2, "missing argument exits 2")
    r = run("--version")
    check(r.returncode == 0 and "grainflow" in r.stdout, "--version")

print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
