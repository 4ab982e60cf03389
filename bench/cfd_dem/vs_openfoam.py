#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""grainflow against OpenFOAM's DPMFoam on the same fluidised bed, in the same run.

The bed of cases/cfd_dem/fluidized_bed (3024 beads, air at 2.5 m/s, 8 x 2 x 30 cells), written
for DPMFoam by openfoam_case.py; grainflow runs the case with `coupling.drag: gidaspow`
(= DPMFoam's ErgunWenYuDrag), `coupling.interpolation: cell` (= the `cell` interpolation
schemes written for DPMFoam; `--interpolation trilinear` for grainflow's default) and the same
simulated time. Both on one thread. Prints the wall
time per simulated second of each (what a user waits for the same physics), the particle-steps
per second (DPMFoam: particles x its move-collide sub-cycles, summed from its log; grainflow:
particles x DEM steps), and the grains' kinetic energy (translational + rotational) averaged
over fifths of the run and the grains' mean height at the end (DPMFoam: from its final alpha.air),
as a check that both beds do the same thing (the lattice starts at 22 mm).

    /usr/bin/python3 bench/cfd_dem/vs_openfoam.py [--grainflow build/release/grainflow]
        [--end 0.1] [--interpolation cell|trilinear] [--append]

Needs Debian's `openfoam` (scripts/setup-debian.sh --bench) and `python3-yaml`. blockMesh is not
timed; DPMFoam's time is its own ExecutionTime (CPU) and the wall time of the process.
"""
import argparse, datetime, json, os, re, subprocess, sys, tempfile, time

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import openfoam_case  # noqa: E402
from run import machine  # noqa: E402

N_GRAINS = openfoam_case.NX * openfoam_case.NY * openfoam_case.NZ


def run_grainflow(grainflow, case_path, end, folder, interpolation):
    with open(case_path) as f:
        case = yaml.safe_load(f)
    case["time"]["end"] = end
    case["coupling"]["drag"] = "gidaspow"
    case["coupling"]["interpolation"] = interpolation
    out = case.setdefault("output", {})
    for k in ("vtk", "particles_csv", "checkpoint"):
        out.pop(k, None)
    out["directory"] = os.path.join(folder, "out")
    out["series"] = {"every": 1.0e-3, "quantities": ["kinetic_energy", "mean_z", "max_z"]}
    path = os.path.join(folder, "case.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(case, f)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    t0 = time.perf_counter()
    subprocess.run([grainflow, "run", path], check=True, capture_output=True, env=env, cwd=folder)
    wall = time.perf_counter() - t0
    with open(os.path.join(folder, "out", "summary.json")) as f:
        s = json.load(f)
    series, mean_z = [], float("nan")
    with open(os.path.join(folder, "out", "series.csv")) as f:
        head = f.readline().strip().split(",")
        it, ik, iz = head.index("time"), head.index("kinetic_energy"), head.index("mean_z")
        for line in f:
            v = line.split(",")
            series.append((float(v[it]), float(v[ik])))
            mean_z = float(v[iz])
    return {"wall": wall, "loop": s["loop_seconds"], "steps": s["steps"],
            "particles": s["n_particles"], "series": series, "mean_z": mean_z}


def run_openfoam(end, folder):
    openfoam_case.make(folder, end)
    env = dict(os.environ, WM_PROJECT_DIR="/usr/share/openfoam")
    subprocess.run(["blockMesh"], check=True, capture_output=True, cwd=folder, env=env)
    t0 = time.perf_counter()
    p = subprocess.run(["DPMFoam"], capture_output=True, text=True, cwd=folder, env=env)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(p.stdout[-2000:] + p.stderr[-2000:])
    log = p.stdout
    sub = sum(int(m) for m in re.findall(r"(\d+) move-collide subCycles", log))
    exec_s = float(re.findall(r"ExecutionTime = ([0-9.eE+-]+) s", log)[-1])
    # Cloud info per fluid step: "Time = t" then, after the cloud's evolve, its energies.
    series, t = [], 0.0
    lin = None
    for line in log.splitlines():
        m = re.match(r"^Time = ([0-9.eE+-]+)", line)
        if m:
            t = float(m.group(1))
        m = re.search(r"Linear kinetic energy\s+= ([0-9.eE+-]+)", line)
        if m:
            lin = float(m.group(1))
        m = re.search(r"Rotational kinetic energy\s+= ([0-9.eE+-]+)", line)
        if m and lin is not None:
            series.append((t, lin + float(m.group(1))))
    return {"wall": wall, "exec": exec_s, "substeps": sub, "series": series,
            "mean_z": solid_mean_height(folder, end)}


def solid_mean_height(folder, end):
    """Mean height of the solid from DPMFoam's final alpha.air: sum (1 - a) z / sum (1 - a) over
    the cells (blockMesh order: x fastest, then y, then z), the grains' mean height up to the
    cell size (6.3 mm)."""
    times = [d for d in os.listdir(folder) if re.fullmatch(r"[0-9.eE+-]+", d) and float(d) > 0]
    if not times:
        return float("nan")
    last = max(times, key=float)
    with open(os.path.join(folder, last, "alpha.air")) as f:
        text = f.read()
    m = re.search(r"internalField\s+nonuniform\s+List<scalar>\s*(\d+)\s*\((.*?)\)\s*;", text, re.S)
    if not m:
        return float("nan")
    alpha = [float(v) for v in m.group(2).split()]
    nx, ny, nz = openfoam_case.CELLS
    hz = openfoam_case.LZ / nz
    num = den = 0.0
    for c, a in enumerate(alpha):
        z = (c // (nx * ny) + 0.5) * hz
        num += (1 - a) * z
        den += 1 - a
    return num / den if den > 0 else float("nan")


def mean_ke(series, t0, t1):
    v = [k for t, k in series if t0 <= t <= t1]
    return sum(v) / len(v) if v else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--grainflow", default=os.path.join(ROOT, "build/release/grainflow"))
    ap.add_argument("--case", default=os.path.join(ROOT, "cases/cfd_dem/fluidized_bed/case.yaml"))
    ap.add_argument("--end", type=float, default=0.1, help="simulated time, s (default 0.1)")
    ap.add_argument("--interpolation", choices=["cell", "trilinear"], default="cell",
                    help="grainflow's coupling.interpolation (default cell, as DPMFoam's here)")
    ap.add_argument("--append", action="store_true", help="append a section to bench/RESULTS-cfd_dem.md")
    a = ap.parse_args()
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as t:
        os.makedirs(f"{t}/g"), os.makedirs(f"{t}/o")
        g = run_grainflow(os.path.abspath(a.grainflow), a.case, a.end, f"{t}/g", a.interpolation)
        o = run_openfoam(a.end, f"{t}/o")
    load1 = os.getloadavg()[0]
    model, cores = machine()
    g_ps = g["particles"] * g["steps"] / g["loop"]
    o_ps = N_GRAINS * o["substeps"] / o["exec"]
    rows = [
        "| code | wall s | wall s per simulated s | DEM steps | particle-steps/s |",
        "|---|---|---|---|---|",
        f"| grainflow | {g['wall']:.2f} | {g['wall'] / a.end:.4g} | {g['steps']} | {g_ps:.3g} |",
        f"| DPMFoam | {o['wall']:.2f} | {o['wall'] / a.end:.4g} | {o['substeps']} (sub-cycles) | {o_ps:.3g} |",
        "",
        "| grains' kinetic energy (J), mean over | grainflow | DPMFoam |",
        "|---|---|---|",
    ]
    for i in range(5):
        t0, t1 = i * a.end / 5, (i + 1) * a.end / 5
        rows.append(f"| {t0:.3g}-{t1:.3g} s | {mean_ke(g['series'], t0, t1):.3g} | "
                    f"{mean_ke(o['series'], t0, t1):.3g} |")
    rows.append(f"| mean height of the grains at the end (m; DPMFoam: of the solid in its cells) | "
                f"{g['mean_z']:.4g} | {o['mean_z']:.4g} |")
    text = "\n".join(rows) + (
        f"\n\nDPMFoam / grainflow wall time for the same {a.end} s of the bed: "
        f"**{o['wall'] / g['wall']:.1f}**; particle-steps/s grainflow / DPMFoam: "
        f"**{g_ps / o_ps:.1f}** (DPMFoam takes {o['substeps'] / max(g['steps'], 1):.2f} of "
        f"grainflow's DEM steps: its sub-step follows the current collision speed); "
        f"grainflow with `interpolation: {a.interpolation}`; "
        f"1 thread each; load average {load0:.2f} -> {load1:.2f}\n")
    print(text)
    if a.append:
        head = (f"\n## {datetime.date.today().isoformat()}: fluidized_bed against OpenFOAM "
                f"DPMFoam (v1912, Debian), {a.end} s\n\nMachine: {model}, {cores} CPUs (shared "
                f"machine). `bench/cfd_dem/vs_openfoam.py`; drag gidaspow = ErgunWenYuDrag.\n\n")
        with open(os.path.join(ROOT, "bench/RESULTS-cfd_dem.md"), "a") as f:
            f.write(head + text)


if __name__ == "__main__":
    main()
