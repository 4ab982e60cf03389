#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Command-line behaviour: restart bit-identity through files, exit code 2 on bad input, no
# output written or overwritten by a failed run, and a run stopped by SIGTERM that ends with its
# outputs and a checkpoint to continue from.
"""Usage: test_cli.py GRAINFLOW SOURCE_DIR"""
import filecmp
import glob
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import FEM_CHANNEL_BLOCK, Checks  # noqa: E402

check = Checks()


def run(*args):
    return subprocess.run([GF, *args], capture_output=True, text=True, cwd=TMP)


GF = os.path.abspath(sys.argv[1])
SOURCE = os.path.abspath(sys.argv[2])
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
    # --device cuda (docs/gpu.md): a case the CUDA back end cannot run, or a build without it,
    # stops with exit 2 before anything is written; a machine without a GPU, with exit 1.
    gear = os.path.join(TMP, "gear.yaml")
    with open(gear, "w") as f:
        f.write(CASE + "integrator: gear5\n")
    r = run("run", gear, "--output", "gear_out", "--device", "cuda")
    check(r.returncode == 2 and "--device cuda" in r.stderr and "gear.yaml" in r.stderr,
          f"--device cuda on a gear5 case exits 2 naming the file: {r.returncode} {r.stderr}")
    check(not os.path.exists(os.path.join(TMP, "gear_out")), "a refused device run writes nothing")
    r = run("run", case, "--output", "cuda_out", "--device", "cuda", "--quiet")
    if r.returncode == 0:
        check(os.path.exists(os.path.join(TMP, "cuda_out", "checkpoint_final.h5")),
              "a device run writes its checkpoint")
    else:
        check(r.returncode in (1, 2) and "--device cuda" in r.stderr,
              f"no CUDA build or no device: exit 2 or 1 with the reason: {r.returncode} {r.stderr}")
        check(not os.path.exists(os.path.join(TMP, "cuda_out")), "a refused device run writes nothing")
    r = run("run", case, "--output", "gpu_out", "--device", "gpu")
    check(r.returncode == 2 and not os.path.exists(os.path.join(TMP, "gpu_out")),
          f"an unknown --device exits 2: {r.returncode}")
    r = run("check", bad)
    check(r.returncode == 2, "check of a bad case exits 2")
    r = run("check", case)
    check(r.returncode == 0 and "particles" in r.stdout, "check of a good case prints derived numbers")
    r = run("describe", "nope")
    check(r.returncode == 2, "describe of an unknown key exits 2")
    r = run("describe", "intersection_area")
    check(r.returncode == 0 and "heat conduction model" in r.stdout and "LIGGGHTS" in r.stdout,
          "describe of a conduction model")
    r = run("list-models")
    check(r.returncode == 0 and "heat conduction models (heat.model)" in r.stdout
          and "batchelor_obrien" in r.stdout, "list-models lists the conduction models")
    r = run("run")
    check(r.returncode == 2, "missing argument exits 2")
    r = run("--version")
    check(r.returncode == 0 and "grainflow" in r.stdout, "--version")

    # SIGTERM in the middle of a long run: the run ends its step, writes its outputs and a
    # checkpoint named by the step, exits 128 + 15, and the checkpoint continues it bit-identically.
    long_case = os.path.join(TMP, "long.yaml")
    with open(long_case, "w") as f:
        f.write(CASE.replace("end: 0.04", "end: 1000.0"))
    proc = subprocess.Popen([GF, "run", long_case, "--output", "stopped", "--quiet"], cwd=TMP,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first = os.path.join(TMP, "stopped", "checkpoint_000001000.h5")
    deadline = time.monotonic() + 60
    while not os.path.exists(first) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=120)
    check(proc.returncode == 128 + signal.SIGTERM, f"a stopped run exits 143, got {proc.returncode}: {err}")
    summary = json.load(open(os.path.join(TMP, "stopped", "summary.json")))
    k = summary["steps"]
    check(not summary["completed"] and summary["stopped_by"] == "SIGTERM", f"summary.json: {summary}")
    stop_ckpt = os.path.join(TMP, "stopped", f"checkpoint_{k:09d}.h5")
    check(os.path.exists(stop_ckpt), f"checkpoint of the stop step {k} written")
    check("--restart" in err and os.path.basename(stop_ckpt) in err,
          f"the message says how to continue: {err}")
    rows = open(os.path.join(TMP, "stopped", "series.csv")).read().split("\n")
    rows = [r for r in rows if r]
    check(abs(float(rows[-1].split(",")[0]) - summary["time"]) < 1e-12,
          "series.csv ends at the stop time")
    n = (k // 1000 + 2) * 1000  # a step with a particle CSV, past the stop
    r = run("run", long_case, "--output", "resumed", "--quiet", "--restart", stop_ckpt,
            "--steps", str(n - k))
    check(r.returncode == 0, f"run continued from the stop checkpoint: {r.stderr}")
    r = run("run", long_case, "--output", "straight", "--quiet", "--steps", str(n))
    check(r.returncode == 0, f"uninterrupted run: {r.stderr}")
    a = os.path.join(TMP, "straight", f"particles_{n:09d}.csv")
    b = os.path.join(TMP, "resumed", f"particles_{n:09d}.csv")
    check(os.path.exists(a) and os.path.exists(b) and filecmp.cmp(a, b, shallow=False),
          "stopped + continued equals uninterrupted (particle CSV)")
    # --append continues in the stopped run's own folder (the default with --append): its
    # series.csv then equals the uninterrupted run's (the stop's extra last row is dropped).
    r = run("run", long_case, "--quiet", "--restart", stop_ckpt, "--append", "--steps", str(n - k))
    check(r.returncode == 0, f"--append run: {r.stderr}")
    # Its summary.json counts both runs: the step reached, 2 runs, their wall time together.
    appended = json.load(open(os.path.join(TMP, "stopped", "summary.json")))
    check(appended["completed"] and appended["step"] == n and appended["steps"] == n - k and
          appended["runs"] == 2 and summary["runs"] == 1 and
          # (the first run's share is its time up to the checkpoint: its loop at least, its
          # whole wall time at most)
          summary["loop_seconds"] + appended["wall_seconds"] <= appended["wall_seconds_all_runs"]
          <= summary["wall_seconds"] + appended["wall_seconds"] + 1e-6,
          f"summary.json totals over the restart: {summary} then {appended}")
    check(filecmp.cmp(os.path.join(TMP, "stopped", "series.csv"),
                      os.path.join(TMP, "straight", "series.csv"), shallow=False),
          "stopped + appended series.csv equals the uninterrupted one")
    r = run("run", long_case, "--quiet", "--restart", stop_ckpt, "--append", "--overwrite")
    check(r.returncode == 2, f"--append with --overwrite exits 2, got {r.returncode}")

    # --max-hours: the run stops at its time limit as on SIGTERM (outputs, checkpoint) and
    # exits 3; its summary says why.
    t0 = time.monotonic()
    r = run("run", long_case, "--output", "limited", "--quiet", "--max-hours", "0.0003")
    summary = json.load(open(os.path.join(TMP, "limited", "summary.json"))) if r.returncode == 3 else {}
    check(r.returncode == 3 and summary.get("stopped_by") == "time limit" and not summary["completed"]
          and os.path.exists(os.path.join(TMP, "limited", f"checkpoint_{summary['steps']:09d}.h5")),
          f"--max-hours stops with a checkpoint and exit 3: {r.returncode} {summary} {r.stderr}")
    check(time.monotonic() - t0 < 30, "--max-hours 0.0003 (1.1 s) ends the run in seconds")

    # SIGTERM to a sweep: it starts no more runs, passes the signal on to the running ones
    # (each in its own process group, so a terminal's Ctrl-C reaches only the sweep), waits for
    # them to write their outputs and exits 143.
    rods = os.path.join(os.path.abspath(sys.argv[2]), "cases", "rheology", "shear_box_rods", "case.yaml")
    proc = subprocess.Popen([GF, "sweep", rods, "-o", "sweep", "-j", "2", "--no-plots",
                             "--set", "sweep.volume_fraction=[0.1, 0.2, 0.3]",
                             "--set", "sweep.shear_rate=[100]"], cwd=TMP,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    started = [os.path.join(TMP, "sweep", f"phi_{p}_rate_100", "resolved_case.yaml") for p in ("0.1", "0.2")]
    deadline = time.monotonic() + 60
    while not all(map(os.path.exists, started)) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    time.sleep(0.2)
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=120)
    check(proc.returncode == 143, f"a stopped sweep exits 143, got {proc.returncode}: {err}")
    for p in ("0.1", "0.2"):
        f = os.path.join(TMP, "sweep", f"phi_{p}_rate_100", "summary.json")
        check(os.path.exists(f) and json.load(open(f))["stopped_by"] == "SIGTERM",
              f"run phi = {p} stopped with its outputs")
    check(not os.path.exists(os.path.join(TMP, "sweep", "phi_0.3_rate_100")), "no run started after the stop")
    check("1 not started" in err, f"the sweep reports what it did: {err}")
    # Every run of a sweep is checked before any starts: at 2e6 1/s the case's series interval
    # (0.1 strain) is below one time step; check and sweep both stop with exit 2 naming the run.
    for cmd in ("check", "sweep"):
        r = subprocess.run([GF, cmd, rods, "--set", "sweep.shear_rate=[100, 2.0e6]", "--set",
                            "sweep.volume_fraction=[0.1]"] + (["-o", "toofast"] if cmd == "sweep" else []),
                           cwd=TMP, capture_output=True, text=True)
        check(r.returncode == 2 and "sweep run phi_0.1_rate_2e+06" in r.stderr and
              "output.series.every_strain" in r.stderr and
              not os.path.exists(os.path.join(TMP, "toofast", "phi_0.1_rate_100")),
              f"{cmd}: an invalid sweep run stops it before it starts: {r.returncode} {r.stderr}")
    # ... and --continue finishes it in place: the stopped runs continue from their checkpoints
    # (run --append), the one not started starts; the table then has all three.
    r = subprocess.run([GF, "sweep", rods, "-o", "sweep", "-j", "2", "--no-plots", "--continue",
                        "--steps", "2500",
                        "--set", "sweep.volume_fraction=[0.1, 0.2, 0.3]",
                        "--set", "sweep.shear_rate=[100]"], cwd=TMP, capture_output=True, text=True)
    table = open(os.path.join(TMP, "sweep", "sweep.csv")).read().split("\n") if r.returncode == 0 else []
    check(r.returncode == 0 and len([l for l in table if l]) == 4,
          f"sweep --continue completes the table: {r.returncode} {r.stderr}")
    check(r.stderr.count("continues from checkpoint_") == 2, f"two runs continued: {r.stderr}")
    r = subprocess.run([GF, "sweep", rods, "-o", "sweep", "--no-plots", "--continue",
                        "--set", "sweep.volume_fraction=[0.1, 0.2, 0.3]",
                        "--set", "sweep.shear_rate=[100]"], cwd=TMP, capture_output=True, text=True)
    check(r.returncode == 0 and r.stderr.count("finished before; kept") == 3,
          f"a finished sweep continued again runs nothing: {r.stderr}")
    # ... but --continue with other lists or another case would drop runs from the table or mix
    # two sweeps in it: refused (exit 2) naming the difference, the table left as it was.
    table_before = open(os.path.join(TMP, "sweep", "sweep.csv")).read()
    for sets, what in ((["sweep.volume_fraction=[0.1, 0.3]", "sweep.shear_rate=[100]"], "runs: "),
                       (["sweep.volume_fraction=[0.1,0.2,0.3]", "sweep.shear_rate=[100]",
                         "contacts[0].friction=0.3"], "friction: 0.3")):
        r = subprocess.run([GF, "sweep", rods, "-o", "sweep", "--no-plots", "--continue"] +
                           [a for s in sets for a in ("--set", s)], cwd=TMP, capture_output=True, text=True)
        check(r.returncode == 2 and "holds another sweep" in r.stderr and what in r.stderr and
              open(os.path.join(TMP, "sweep", "sweep.csv")).read() == table_before,
              f"sweep --continue of another sweep is refused ({what}): {r.returncode} {r.stderr}")
    # A plan written by a build that wrote fewer default keys is the same sweep: its case is
    # compared as this build writes it.
    plan = os.path.join(TMP, "sweep", "sweep_plan.txt")
    text = open(plan).read()
    check("  integrator: velocity_verlet\n" in text, "the plan holds the resolved case")
    open(plan, "w").write(text.replace("  integrator: velocity_verlet\n", ""))
    r = subprocess.run([GF, "sweep", rods, "-o", "sweep", "--no-plots", "--continue",
                        "--set", "sweep.volume_fraction=[0.1, 0.2, 0.3]",
                        "--set", "sweep.shear_rate=[100]"], cwd=TMP, capture_output=True, text=True)
    check(r.returncode == 0 and r.stderr.count("finished before; kept") == 3,
          f"a plan without a defaulted key continues: {r.returncode} {r.stderr}")

    # A sweep killed outright (SIGKILL: no chance to pass anything on) does not leave its runs
    # going on alone: the kernel signals each one, and it stops with its outputs and a
    # checkpoint ("sweep ended"), which --continue then carries on. Killed after it has passed a
    # SIGTERM on (a batch system's SIGTERM, then SIGKILL), its runs are not cut short by that
    # second notice: they finish stopping on the SIGTERM.
    def killed_sweep(name, term_first):
        proc = subprocess.Popen([GF, "sweep", rods, "-o", name, "-j", "2", "--no-plots",
                                 "--set", "sweep.volume_fraction=[0.1, 0.2]",
                                 "--set", "sweep.shear_rate=[100]"], cwd=TMP,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        runs = [os.path.join(TMP, name, f"phi_{p}_rate_100") for p in ("0.1", "0.2")]
        deadline = time.monotonic() + 60
        while (not all(os.path.exists(os.path.join(d, "resolved_case.yaml")) for d in runs)
               and proc.poll() is None and time.monotonic() < deadline):
            time.sleep(0.02)
        time.sleep(0.2)
        if term_first:
            proc.send_signal(signal.SIGTERM)
            time.sleep(0.15)  # the sweep passes it on within 50 ms
        proc.kill()
        proc.wait()
        summaries = [os.path.join(d, "summary.json") for d in runs]
        deadline = time.monotonic() + 60
        while not all(map(os.path.exists, summaries)) and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(0.2)
        # (after a SIGTERM the sweep passes it on within 50 ms; on a loaded machine its death
        # may come first, and the run then stops on that: either way with its outputs)
        expected = ("SIGTERM", "sweep ended") if term_first else ("sweep ended",)
        for d, f in zip(runs, summaries):
            s = json.load(open(f)) if os.path.exists(f) else {}
            check(s.get("stopped_by") in expected and
                  os.path.exists(os.path.join(d, f"checkpoint_{s['steps']:09d}.h5")),
                  f"a run of a killed sweep stops with its outputs and a checkpoint "
                  f"({expected}): {d} {s}")
    killed_sweep("killed", False)
    killed_sweep("killed_after_term", True)
    r = subprocess.run([GF, "sweep", rods, "-o", "killed", "-j", "2", "--no-plots", "--continue",
                        "--steps", "2500",
                        "--set", "sweep.volume_fraction=[0.1, 0.2]",
                        "--set", "sweep.shear_rate=[100]"], cwd=TMP, capture_output=True, text=True)
    check(r.returncode == 0 and r.stderr.count("continues from checkpoint_") == 2,
          f"--continue carries on the runs of a killed sweep: {r.returncode} {r.stderr}")
    # The run checks that the sweep it names is its parent: one whose named sweep is gone
    # already when it starts stops at once; one started by the named process runs.
    env = dict(os.environ)
    r = subprocess.run([GF, "run", long_case, "--output", "orphan", "--quiet"], cwd=TMP,
                       capture_output=True, text=True, env=dict(env, GRAINFLOW_SWEEP_PARENT="1"))
    check(r.returncode == 143, f"a run whose sweep is gone stops at once: {r.returncode} {r.stderr}")
    r = subprocess.run([GF, "run", long_case, "--output", "child", "--quiet", "--steps", "50"],
                       cwd=TMP, capture_output=True, text=True,
                       env=dict(env, GRAINFLOW_SWEEP_PARENT=str(os.getpid())))
    check(r.returncode == 0, f"a run of a living sweep runs: {r.returncode} {r.stderr}")

    # fluid_fem from the command line: a checkpoint at the end, --restart continues it, and a
    # particle checkpoint given to a fluid_fem case is refused with exit code 2.
    fem_case = os.path.join(TMP, "fem.yaml")
    with open(fem_case, "w") as f:
        f.write(FEM_CHANNEL_BLOCK)
    r = run("run", fem_case, "--output", "fem_a", "--quiet", "--steps", "4")
    fem_ckpt = os.path.join(TMP, "fem_a", "fem_checkpoint_final.h5")
    check(r.returncode == 0 and os.path.exists(fem_ckpt), f"fluid_fem run writes a checkpoint: {r.stderr}")
    r = run("run", fem_case, "--output", "fem_b", "--quiet", "--steps", "3", "--restart", fem_ckpt)
    summary = open(os.path.join(TMP, "fem_b", "fem_summary.txt")).read() if r.returncode == 0 else ""
    check("continued from t = 0.04 s (step 4)" in summary and "(over restarts): 7" in summary,
          f"fluid_fem --restart continues: {r.stderr} {summary}")
    r = run("run", fem_case, "--output", "fem_c", "--quiet", "--restart", stop_ckpt)
    check(r.returncode == 2 and "fluid_fem" in r.stderr, f"a particle checkpoint is refused: {r.returncode} {r.stderr}")
    check(not os.path.exists(os.path.join(TMP, "fem_c")), "a refused restart writes nothing")
    # --set reaches fluid_fem cases too (it used to be ignored there), and check derives Re.
    r = run("run", fem_case, "--output", "fem_d", "--quiet", "--set", "fluid_fem.time.end=0.02")
    summary = open(os.path.join(TMP, "fem_d", "fem_summary.txt")).read() if r.returncode == 0 else ""
    check("steps 2 " in summary, f"--set fluid_fem.time.end=0.02 gives 2 steps: {r.stderr} {summary}")
    r = run("run", fem_case, "--output", "fem_e", "--set", "fluid_fem.time.end=-1")
    check(r.returncode == 2 and "fluid_fem.time.end" in r.stderr, f"a bad --set exits 2: {r.stderr}")
    r = run("check", fem_case, "--set", "fluid_fem.fluid.viscosity=0.001")
    check(r.returncode == 0 and "Reynolds number" in r.stdout and " 33.33 " in r.stdout,
          f"check of a fluid_fem case derives Re = U D / nu: {r.stdout}")

    # A run that fails after it has started writing leaves an earlier output folder as it was,
    # with --overwrite and with --append; what it wrote goes to <folder>.failed-<time>. (The
    # fluidized bed with a fluid step 200 DEM steps long stops at its first fluid step with a
    # Courant number above 1: a failure mid-run, after the folder was prepared.)
    bed = os.path.join(SOURCE, "cases", "cfd_dem", "fluidized_bed", "case.yaml")

    def snapshot(d):
        out = {}
        for root, _, files in os.walk(d):
            for f in files:
                p = os.path.join(root, f)
                out[os.path.relpath(p, d)] = open(p, "rb").read()
        return out

    r = run("run", bed, "--output", "bed", "--quiet", "--threads", "1", "--steps", "20")
    check(r.returncode == 0, f"fluidized bed, 20 steps: {r.stderr}")
    earlier = snapshot(os.path.join(TMP, "bed"))
    for extra in (["--overwrite"],
                  ["--restart", os.path.join(TMP, "bed", "checkpoint_final.h5"), "--append"]):
        r = run("run", bed, "--output", "bed", "--quiet", "--threads", "1", "--steps", "400",
                "--set", "coupling.interval=200", *extra)
        failed = glob.glob(os.path.join(TMP, "bed.failed-*"))
        # (said in the case's terms, when and what to change, without a source location)
        check(r.returncode == 1 and "Courant" in r.stderr and "at t = " in r.stderr and
              "lower coupling.interval to" in r.stderr and ".cpp" not in r.stderr,
              f"{extra[-1]}: the run fails: {r.stderr}")
        check(snapshot(os.path.join(TMP, "bed")) == earlier,
              f"{extra[-1]}: a failed run leaves the earlier folder as it was")
        check(len(failed) == 1 and os.path.exists(os.path.join(failed[0], "series.csv")) and
              "the run failed" in r.stderr and not os.path.exists(os.path.join(TMP, ".bed.grainflow-earlier")),
              f"{extra[-1]}: its own files are kept aside and said where: {failed} {r.stderr}")
        for f in failed:
            subprocess.run(["rm", "-rf", f])
    # A folder left set aside by a killed run is not run over.
    os.mkdir(os.path.join(TMP, ".bed.grainflow-earlier"))
    r = run("run", bed, "--output", "bed", "--quiet", "--steps", "2", "--overwrite")
    check(r.returncode == 2 and ".bed.grainflow-earlier" in r.stderr and
          snapshot(os.path.join(TMP, "bed")) == earlier, f"set-aside files are not lost: {r.stderr}")
    os.rmdir(os.path.join(TMP, ".bed.grainflow-earlier"))
    # --overwrite replaces only an output folder, and never one that holds the case file.
    own = os.path.join(TMP, "own")
    os.mkdir(own)
    with open(os.path.join(own, "case.yaml"), "w") as f:
        f.write(CASE)
    with open(os.path.join(own, "notes.txt"), "w") as f:
        f.write("keep")
    r = subprocess.run([GF, "run", "case.yaml", "-o", ".", "--overwrite", "--steps", "2"], cwd=own,
                       capture_output=True, text=True)
    check(r.returncode == 2 and "holds the case file" in r.stderr and
          sorted(os.listdir(own)) == ["case.yaml", "notes.txt"], f"-o . --overwrite refused: {r.stderr}")
    r = run("run", case, "-o", "own", "--overwrite", "--steps", "2")
    check(r.returncode == 2 and "holds no grainflow output" in r.stderr and
          sorted(os.listdir(own)) == ["case.yaml", "notes.txt"], f"a foreign folder is refused: {r.stderr}")
    # An output folder that cannot be made is bad input too.
    r = run("run", case, "--output", "/proc/grainflow_cannot_be_here", "--quiet", "--steps", "2")
    check(r.returncode == 2 and "cannot be created" in r.stderr, f"an impossible --output: {r.stderr}")
    # A damaged checkpoint is refused (HDF5's checksums), exit 2, nothing written.
    damaged = os.path.join(TMP, "damaged.h5")
    data = bytearray(open(os.path.join(TMP, "full", "checkpoint_000001000.h5"), "rb").read())
    at = len(data) * 15 // 100
    data[at:at + 4096] = b"\xff" * 4096
    open(damaged, "wb").write(bytes(data))
    r = run("run", case, "--output", "from_damaged", "--quiet", "--restart", damaged)
    check(r.returncode == 2 and "--restart" in r.stderr and "damaged" in r.stderr and
          not os.path.exists(os.path.join(TMP, "from_damaged")),
          f"a damaged checkpoint is refused: {r.returncode} {r.stderr}")

check.exit()
