#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# fluid_fem cases from the command line: the resolved case in the output folder, --set errors
# named by the option, body names refused where they would break fem_forces.csv, narrow gaps
# (error / warning), a diverging run stopped with exit status 1 and no non-finite rows, a free
# body settling on a moving mesh (the shipped settling_disk), and the shipped cases checked.
"""Usage: test_cli_fem.py GRAINFLOW SOURCE_DIR"""
import glob
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import FEM_CHANNEL_BLOCK, Checks  # noqa: E402

CASE = "name: fem_cli\n" + FEM_CHANNEL_BLOCK + "  output: {probes: [[0.9, 0.2]]}\n"

check = Checks()
GF = os.path.abspath(sys.argv[1])
SOURCE = os.path.abspath(sys.argv[2])


def run(*args):
    return subprocess.run([GF, *args], capture_output=True, text=True, cwd=TMP)


def write(name, text):
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def finite_rows(path):
    """Whether every row after the header of a CSV file is numbers, all finite."""
    with open(path) as f:
        rows = f.read().splitlines()[1:]
    return all(re.fullmatch(r"[-+0-9.eE,]+", row) for row in rows), len(rows)


with tempfile.TemporaryDirectory() as TMP:
    case = write("case.yaml", CASE)

    # 1. The resolved case with the program version, written with the outputs; it reads back
    # (check and run) and gives the same first steps.
    r = run("run", case, "--output", "a", "--quiet", "--steps", "3")
    check(r.returncode == 0, f"fluid_fem run: {r.returncode} {r.stderr}")
    resolved = os.path.join(TMP, "a", "resolved_case.yaml")
    text = open(resolved).read() if os.path.exists(resolved) else ""
    version = run("--version").stdout.split()[-1]
    check(text.startswith(f"# grainflow {version}: resolved configuration of {case}"),
          f"resolved_case.yaml opens with the version: {text[:120]!r}")
    for default in ("name: fem_cli", "min_angle: 25", "grading: 0.3", "nested: true",
                    "reuse_factorization: true", "{edges: [0], type: wall}", "initial: rest"):
        check(default in text, f"the resolved case gives '{default}': {text}")
    r = run("check", resolved)
    check(r.returncode == 0 and "OK (fluid_fem case)" in r.stdout, f"check of the resolved case: {r.stderr}")
    r = run("run", resolved, "--output", "b", "--quiet", "--steps", "3")
    same = (r.returncode == 0 and
            open(os.path.join(TMP, "a", "fem_forces.csv")).read() ==
            open(os.path.join(TMP, "b", "fem_forces.csv")).read())
    check(same, f"a run of the resolved case repeats the run: {r.stderr}")
    check(os.path.exists(os.path.join(TMP, "b", "resolved_case.yaml")) and
          open(os.path.join(TMP, "b", "resolved_case.yaml")).read().split("\n", 1)[1] ==
          text.split("\n", 1)[1], "the resolved case of the resolved case is the same")
    # a steady run writes it too
    r = run("run", case, "--output", "steady", "--quiet", "--set", "fluid_fem.time={mode: steady}")
    check(r.returncode == 0 and "mode: steady" in open(os.path.join(TMP, "steady", "resolved_case.yaml")).read(),
          f"a steady run echoes its case: {r.stderr}")

    # 2. --set errors are named by the option, as in the other kinds of case; errors in the
    # file keep their line and column.
    r = run("run", case, "--output", "c", "--set", "fluid_fem.fluid.viscosity=abc")
    check(r.returncode == 2, f"a bad --set value exits 2: {r.returncode}")
    check(r.stderr.startswith(f"{case} (--set fluid_fem.fluid.viscosity=abc): error: "
                              "fluid_fem.fluid.viscosity: expected a number"),
          f"the --set error names the option: {r.stderr}")
    check(not os.path.exists(os.path.join(TMP, "c")), "a refused case writes nothing")
    r = run("check", case, "--set", "fluid_fem.mesh={h_max: 0.08, h_bdy: 0.03}")
    check(r.returncode == 2 and f"{case} (--set fluid_fem.mesh={{h_max: 0.08, h_bdy: 0.03}}): error: "
          "fluid_fem.mesh.h_bdy: expected one of the keys" in r.stderr,
          f"an unknown key inside a --set map names the option: {r.stderr}")
    r = run("check", case, "--set", "fluid_fem.time.end=-1")
    check(r.returncode == 2 and "(--set fluid_fem.time.end=-1): error: fluid_fem.time.end:" in r.stderr,
          f"--set of an existing key: {r.stderr}")
    bad = write("bad_viscosity.yaml", CASE.replace("viscosity: 0.01", "viscosity: abc"))
    r = run("check", bad)
    check(r.returncode == 2 and r.stderr.startswith(f"{bad}:3:36: error: fluid_fem.fluid.viscosity: expected a number"),
          f"an error in the file names line and column: {r.stderr}")
    bad = write("bad_top.yaml", CASE + "colour: red\n")
    r = run("check", bad)
    check(r.returncode == 2 and f"{bad}:14:1: error: " in r.stderr and "colour" in r.stderr,
          f"an unknown top-level key is located: {r.stderr}")

    # 4. Body names that would break the CSV header are refused where they are written.
    for name, found in (('"a,b"', "'a,b'"), ("'q\"x'", "'q\"x'"), ('"x\\ny"', "'x\\ny'")):
        bad = write("bad_name.yaml", CASE.replace("name: disk", f"name: {name}"))
        r = run("run", bad, "--output", "d")
        check(r.returncode == 2 and r.stderr.startswith(
            f"{bad}:10:14: error: fluid_fem.bodies[0].name: expected a name of letters, digits, '_' "
            f"and '-', starting with a letter or '_'") and f"found {found}" in r.stderr,
            f"body name {name} is refused: {r.returncode} {r.stderr}")
        check(not os.path.exists(os.path.join(TMP, "d")), "a refused name writes nothing")

    # 5. Gaps narrower than the mesh size: an error below 0.1 x h, a warning in check below h.
    near = write("near.yaml", CASE.replace("centre: [0.3, 0.2]", "centre: [0.3, 0.348]"))
    r = run("check", near)
    check(r.returncode == 2 and r.stderr.startswith(f"{near}:10:7: error: fluid_fem.bodies[0]: expected a body clear of the domain outline")
          and "found a gap of 0.002 m" in r.stderr, f"a gap of 0.002 m with h 0.03 is refused: {r.stderr}")
    close = write("close.yaml", CASE.replace("centre: [0.3, 0.2]", "centre: [0.3, 0.34]"))
    r = run("check", close)
    check(r.returncode == 0 and f"warning: {close}:10:7: fluid_fem.bodies[0]: the gap of 0.01 m between 'disk'" in r.stdout,
          f"a gap of 0.01 m with h 0.03 is a warning in check: {r.stdout} {r.stderr}")
    # ... named by the --set option that placed the body
    r = run("check", near, "--set", "fluid_fem.bodies=[{name: disk, circle: {centre: [0.3, 0.34], radius: 0.05}}]")
    check(r.returncode == 0 and "(--set fluid_fem.bodies=" in r.stdout and "the gap of 0.01 m" in r.stdout,
          f"a gap warning names the --set option: {r.stdout} {r.stderr}")
    # The size in a gap is that at its surfaces: a large grading (cells growing fast away from the
    # bodies) does not make a gap of 15 h_body narrow.
    graded = write("graded.yaml", CASE.replace("mesh: {h_max: 0.08, h_body: 0.03}",
                                               "mesh: {h_max: 0.4, h_body: 0.002, grading: 25}")
                   .replace("centre: [0.3, 0.2]", "centre: [0.3, 0.08]"))
    r = run("check", graded)
    check(r.returncode == 0 and "gap" not in r.stdout, f"a 0.03 m gap with h_body 0.002 is fine at grading 25: {r.stdout} {r.stderr}")
    r = run("run", close, "--output", "close", "--steps", "1")
    check(r.returncode == 0 and "the gap of 0.01 m" in r.stderr, f"and in the log of a run: {r.stderr}")

    # 3. A run that diverges (inflow ramped to 1e6 m/s over 20 s, steps of 1 s) stops with exit
    # status 1, naming the time and the step, after the steps that converged; its files (in its
    # new folder) hold those steps' rows and no non-finite number.
    wild = write("wild.yaml", CASE.replace(
        "u_max: 0.5", "u_max: 1.0e6, time_function: {type: ramp, duration: 20.0}").replace(
        "viscosity: 0.01", "viscosity: 1.0e-6").replace("step: 0.01, end: 1.0", "step: 1.0, end: 20.0"))
    r = run("run", wild, "--output", "wild")
    check(r.returncode == 1 and "fluid_fem: the run diverged at t = " in r.stderr and "(step " in r.stderr
          and "(step 1)" not in r.stderr,
          f"a diverging run stops with exit status 1 after some steps: {r.returncode} {r.stderr}")
    for f in ("fem_forces.csv", "fem_probes.csv"):
        path = os.path.join(TMP, "wild", f)
        ok, n = finite_rows(path) if os.path.exists(path) else (False, 0)
        check(ok and n > 0, f"{f} of the diverged run holds its converged steps ({n} rows), all finite")
    for vtu in glob.glob(os.path.join(TMP, "wild", "*.vtu")):
        check("nan" not in open(vtu, errors="replace").read().lower(), f"{vtu} holds no nan")

    # 6. Free bodies: the shipped settling disk runs a few steps on a moving mesh; the forces CSV
    # gains each body's pose and velocity, and the disk falls. check derives its settling numbers.
    settling = os.path.join(SOURCE, "cases", "fluid_fem", "settling_disk", "case.yaml")
    r = run("check", settling)
    check(r.returncode == 0 and "settling speed estimate U (m/s)" in r.stdout and "0.09501" in r.stdout
          and "Archimedes number" in r.stdout, f"check of the settling disk: {r.stdout} {r.stderr}")
    r = run("run", settling, "--output", "settle", "--quiet", "--steps", "5")
    check(r.returncode == 0, f"settling disk run: {r.returncode} {r.stderr}")
    forces = os.path.join(TMP, "settle", "fem_forces.csv")
    rows = open(forces).read().splitlines() if os.path.exists(forces) else [""]
    cols = rows[0].split(",")
    want = ["disk.x", "disk.y", "disk.angle", "disk.vx", "disk.vy", "disk.omega"]
    check(all(c in cols for c in want), f"fem_forces.csv has the pose columns: {rows[0]}")
    if all(c in cols for c in want) and len(rows) == 6:
        y = [float(row.split(",")[cols.index("disk.y")]) for row in rows[1:]]
        vy = [float(row.split(",")[cols.index("disk.vy")]) for row in rows[1:]]
        # (the first step's pose is predicted from the velocity at rest: it moves from step 2)
        check(all(b < a for a, b in zip(y, y[1:])) and y[-1] < 0.5 and all(v < 0 for v in vy),
              f"the disk falls: y = {y}, vy = {vy}")
    else:
        check(False, f"5 rows in fem_forces.csv: {len(rows) - 1}")
    summary = os.path.join(TMP, "settle", "fem_summary.txt")
    check(os.path.exists(summary) and "moving mesh: remeshes" in open(summary).read(),
          "the summary reports the remeshes")
    check(os.path.exists(os.path.join(TMP, "settle", "fem_checkpoint_final.h5")),
          "a moving run writes its final checkpoint")
    resolved = os.path.join(TMP, "settle", "resolved_case.yaml")
    text = open(resolved).read() if os.path.exists(resolved) else ""
    check("density: 1.5" in text and "gravity: [0, -100]" in text and "remesh_ratio: 0.5" in text,
          f"the resolved case echoes the free body: {text}")
    # adaptive steps: a dt_max the explicit contact loads may not follow is a warning at the key
    r = run("run", settling, "--output", "settle_ad", "--quiet", "--steps", "3",
            "--set", "fluid_fem.time.adaptive={rtol: 1.0e-3}")
    check(r.returncode == 0 and "fluid_fem.time.adaptive.dt_max: 1 s is more than 1/6 of the fastest "
          "contact period" in r.stderr, f"adaptive steps of a moving run, warned: {r.stderr}")
    # checkpoints: periodic ones, and a run cut short continued in its folder gives the rows of
    # the run that was never cut
    r = run("run", settling, "--output", "settle_ck", "--quiet", "--steps", "8",
            "--set", "fluid_fem.output.checkpoint_every=0.05")
    ck = sorted(glob.glob(os.path.join(TMP, "settle_ck", "fem_checkpoint_0*.h5")))
    check(r.returncode == 0 and len(ck) >= 1, f"periodic checkpoints of a moving run: {ck} {r.stderr}")
    r = run("run", settling, "--output", "settle", "--quiet", "--steps", "3",
            "--restart", os.path.join(TMP, "settle", "fem_checkpoint_final.h5"), "--append")
    rows8 = open(os.path.join(TMP, "settle_ck", "fem_forces.csv")).read().splitlines()
    check(r.returncode == 0 and open(forces).read().splitlines() == rows8,
          f"--restart --append continues the moving run as if never cut: {r.stderr}")
    # a checkpoint of another case (the channel's) does not fit (exit 2, no series written)
    r = run("run", settling, "--output", "settle_r", "--restart", os.path.join(TMP, "a", "fem_checkpoint_final.h5"))
    check(r.returncode == 2 and "--restart: the checkpoint belongs to another mesh" in r.stderr and
          not os.path.exists(os.path.join(TMP, "settle_r", "fem_forces.csv")),
          f"--restart of another case refused: {r.stderr}")

    # The shipped cases pass check.
    for c in sorted(glob.glob(os.path.join(SOURCE, "cases", "fluid_fem", "*", "case.yaml"))):
        r = run("check", c)
        check(r.returncode == 0 and "OK (fluid_fem case)" in r.stdout and "warning" not in r.stdout,
              f"check {c}: {r.stdout} {r.stderr}")

check.exit()
