#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Coupled CFD-DEM step cost against DEM-only step cost for cases/cfd_dem/fluidized_bed.

Runs the case twice with the same grains and steps: as given (fluid + coupling) and with its
`fluid` and `coupling` blocks removed (and the fluid series quantities dropped), no VTK output.
Reads grainflow's summary.json (loop_seconds, steps, n_particles, stages) and prints
particle-steps/s, fluid cell-steps/s and the ratio coupled / DEM-only. With --append, adds a
dated section to bench/RESULTS-cfd_dem.md. Target (issue): fluid + coupling add < 50 %.
The peer run against OpenFOAM DPMFoam is vs_openfoam.py.
"""
import argparse, datetime, json, os, platform, subprocess, sys, tempfile

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLUID_Q = {"fluid_pressure_drop", "superficial_velocity", "fluid_kinetic_energy",
           "min_fluid_fraction"}


def machine():
    model, cores = "n/a", "n/a"
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
            if line.startswith("CPU(s):"):
                cores = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return model, cores


def run(grainflow, case, folder, steps, threads, sets=()):
    path = os.path.join(folder, "case.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(case, f)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    cmd = [grainflow, "run", path, "--steps", str(steps), "--set", f"output.directory={folder}/out"]
    for s in sets:
        cmd += ["--set", s]
    try:
        subprocess.run(cmd, check=True, capture_output=True, env=env, cwd=folder)
        with open(os.path.join(folder, "out", "summary.json")) as f:
            return json.load(f)
    except (OSError, subprocess.CalledProcessError, ValueError) as e:
        print(f"grainflow failed: {e}", file=sys.stderr)
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--grainflow", default=os.path.join(ROOT, "build/release/grainflow"))
    ap.add_argument("--case", default=os.path.join(ROOT, "cases/cfd_dem/fluidized_bed/case.yaml"))
    ap.add_argument("--steps", type=int, default=10000, help="DEM steps per run (default 10000 = 0.1 s)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override of the coupled run (repeatable), e.g. coupling.fluid_fraction=smoothed")
    ap.add_argument("--append", action="store_true", help="append a section to bench/RESULTS-cfd_dem.md")
    a = ap.parse_args()
    a.grainflow = os.path.abspath(a.grainflow)

    with open(a.case) as f:
        coupled = yaml.safe_load(f)
    out = coupled.setdefault("output", {})
    out.pop("vtk", None)
    out.pop("particles_csv", None)
    out.pop("checkpoint", None)
    dem = json.loads(json.dumps(coupled))
    dem.pop("fluid", None)
    dem.pop("coupling", None)
    if "series" in dem.get("output", {}):
        q = [x for x in dem["output"]["series"]["quantities"] if x not in FLUID_Q]
        dem["output"]["series"]["quantities"] = q

    cells = 1
    for n in coupled["fluid"]["cells"]:
        cells *= n
    interval = coupled["coupling"].get("interval", 100)
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as t:
        os.makedirs(f"{t}/c"), os.makedirs(f"{t}/d")
        sc = run(a.grainflow, coupled, f"{t}/c", a.steps, a.threads, a.set)
        sd = run(a.grainflow, dem, f"{t}/d", a.steps, a.threads)
    load1 = os.getloadavg()[0]
    model, cores = machine()
    rows = []

    def fmt(s, label):
        if s is None:
            return f"| {label} | n/a | n/a | n/a | n/a | n/a |"
        ps = s["n_particles"] * s["steps"] / s["loop_seconds"]
        fl = s.get("stages", {}).get("fluid", 0.0)
        fsteps = s["steps"] // interval + 1
        cs = cells * fsteps / fl if fl > 0 else float("nan")
        return (f"| {label} | {s['n_particles']} | {s['steps']} | {s['loop_seconds']:.3f} | "
                f"{ps:.3g} | " + (f"{fl:.3f} s, {cs:.3g} cell-steps/s |" if fl > 0 else "- |"))

    rows.append("| run | particles | steps | loop s | particle-steps/s | fluid stage |")
    rows.append("|---|---|---|---|---|---|")
    rows.append(fmt(sc, "coupled"))
    rows.append(fmt(sd, "DEM only"))
    ratio = sc["loop_seconds"] / sd["loop_seconds"] if sc and sd else float("nan")
    verdict = "n/a" if ratio != ratio else ("meets" if ratio < 1.5 else "misses")
    # The two runs do different DEM work (a fluidised bed has fewer contacts than a settled
    # one), so two further readings: the fluid stage against the DEM-only loop (what fluid and
    # coupling add to a DEM step of this bed), and against the DEM part of the coupled run.
    fl = sc.get("stages", {}).get("fluid", 0.0) if sc else float("nan")
    added = fl / sd["loop_seconds"] if sc and sd else float("nan")
    own = fl / (sc["loop_seconds"] - fl) if sc else float("nan")
    both = "n/a" if own != own else ("meets" if max(added, own) < 0.5 else "misses")
    text = "\n".join(rows) + (
        f"\n\ncoupled / DEM-only loop time: **{ratio:.2f}** (target < 1.5: {verdict}); fluid "
        f"stage / DEM-only loop: **{added:.2f}**; fluid stage / DEM part of the coupled loop: "
        f"**{own:.2f}** (target < 0.5 for both: {both}); fluid grid "
        f"{'x'.join(map(str, coupled['fluid']['cells']))} = {cells} cells, one fluid step every "
        f"{interval} DEM steps; threads {a.threads}; load average {load0:.2f} -> {load1:.2f}"
        + (f"; coupled run with {', '.join(a.set)}" if a.set else "") + "\n")
    print(text)
    if a.append:
        variant = f" ({', '.join(a.set)})" if a.set else ""
        head = (f"\n## {datetime.date.today().isoformat()}: fluidized_bed, {a.steps} steps{variant}\n\n"
                f"Machine: {model}, {cores} CPUs (shared machine), "
                f"grainflow {a.grainflow}. Peer: see vs_openfoam.py.\n\n")
        res = os.path.join(ROOT, "bench/RESULTS-cfd_dem.md")
        new = not os.path.exists(res)
        with open(res, "a") as f:
            if new:
                f.write("# CFD-DEM benchmark results\n\nSee [cfd_dem/README.md](cfd_dem/README.md). "
                        "One dated section per run, newest last.\n")
            f.write(head + text)


if __name__ == "__main__":
    main()
