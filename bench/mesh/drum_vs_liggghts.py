#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Side-by-side speed of STL mesh walls: a turning drum with lifters, grainflow vs LIGGGHTS.

The case mirrors cases/dem/drum_lifters and is built for both codes by this script: a closed
drum (R = 0.1 m, 0.06 m long along y, 96 barrel panels, two end plates as fans of triangles
about the axis, six lifter bars 15 mm high and 6 mm thick) written once as an ASCII STL from
scripts/make_drum_stl.py's triangles, turning about the y axis through the origin at 20 rpm
(counter-clockwise about +y in both codes: grainflow `rotate: {axis: [0, 1, 0], rpm: 20}`,
LIGGGHTS `fix move/mesh ... rotate origin 0 0 0 axis 0 1 0 period 3.0`). N glass beads
(default 2500; 2500 kg/m^3, E 1e7 Pa, nu 0.3, e 0.5, mu 0.5, NO rolling friction so that the
two contact models are the same: Hertz-Mindlin with tangential history), radii uniform in
[2.7, 3.3] mm (seeded), placed on the N lowest sites of a simple cubic lattice (spacing
6.8 mm, inside radius 0.078 m, y in [0.004, 0.056] m) at rest; both codes read these exact
positions and radii (grainflow: a CSV particle file x,y,z,radius; LIGGGHTS: read_data,
atom_style granular). Wall material: the same E and nu (type 2 in LIGGGHTS). dt 2e-5 s,
gravity -9.81 along z, neighbour skin 1.5 mm.

Per code, two timed phases (like bench/terrain_settling/run.py and bench/shapes/peers.py,
whose helpers are reused): (1) fill: the first --fill-time s from the lattice (the beads fall
and start to tumble), (2) run: --run-time further s (LIGGGHTS: a second `run` in the same
input; grainflow: `--restart` from the checkpoint at the end of (1)). Rate = N x steps / loop
time, with the load average during the run and the CPU share each process got (the machine is
shared), and the ratio grainflow / LIGGGHTS per phase.

Physics cross-check (the two codes must simulate the same thing): means over the last
--avg-window s of the run of the drum's torque about y (the torque the beads exert on the mesh
about the origin; grainflow series `wall_torque.drum.y`, LIGGGHTS `fix mesh/surface/stress`
global vector component 5), the x coordinate of the bed's centre of mass (grainflow: from the
particles CSV snapshots; LIGGGHTS: `compute com`), the translational and rotational kinetic
energy, and the bed's gravitational torque M g x_cm that the wall torque should balance.

Unless --no-record is given, a dated section is appended to bench/RESULTS.md.

Examples (from the repository root):
  /usr/bin/python3 bench/mesh/drum_vs_liggghts.py
  /usr/bin/python3 bench/mesh/drum_vs_liggghts.py --n 1500 --no-record --keep
  /usr/bin/python3 bench/mesh/drum_vs_liggghts.py --codes liggghts --curvature 4 --no-record
"""

from __future__ import annotations

import argparse
import csv
import datetime as _dt
import importlib.util
import json
import math
import os
import random
import re
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCH = HERE.parent
ROOT = BENCH.parent


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # dataclasses look their module up there
    spec.loader.exec_module(mod)
    return mod


# Measurement helpers (time -v, load sampling, CPU share) shared with the sphere benchmark
# (bench/ is a package, the scripts run as files, so its root goes on the path); the drum's
# triangles from the script that wrote cases/dem/drum_lifters/drum.stl.
sys.path.append(str(ROOT))
from bench.terrain_settling import run as ts  # noqa: E402

stl = _load("_make_drum_stl", ROOT / "scripts" / "make_drum_stl.py")
F, run_timed, lscpu_model, _tail, LOOP_RE = ts.F, ts.run_timed, ts.lscpu_model, ts._tail, ts.LOOP_RE

# ---------------------------------------------------------------------------------------------
# The case (identical for both codes)
# ---------------------------------------------------------------------------------------------
DRUM_R, DRUM_L, SEGMENTS = 0.1, 0.06, 96          # m, m, barrel panels
LIFTERS, LIFTER_H, LIFTER_T = 6, 0.015, 0.006     # count, m, m
RPM = 20.0                                        # counter-clockwise about +y
PERIOD = 60.0 / RPM                               # s (LIGGGHTS move/mesh rotate period)
DOMAIN_MIN = (-0.102, -0.002, -0.102)             # as cases/dem/drum_lifters
DOMAIN_MAX = (0.102, 0.062, 0.102)
R_MIN, R_MAX = 0.0027, 0.0033                     # bead radii, m (uniform)
DENSITY, YOUNGS, POISSON = 2500.0, 1.0e7, 0.3     # beads; the wall has the same E, nu
WALL_DENSITY = 7800.0                             # grainflow needs one; the wall is driven
RESTITUTION, FRICTION = 0.5, 0.5
GRAVITY = 9.81                                    # m/s^2 along -z
DT = 2.0e-5                                       # s
SKIN = 0.0015                                     # m
SPACING = 0.0068                                  # simple cubic lattice, m
FILL_R = 0.078                                    # lattice sites within this radius of the axis
FILL_Y = (0.004, 0.056)                           # lattice sites with y in this range
SERIES_EVERY = 0.01                               # s, grainflow series / LIGGGHTS thermo
SNAPSHOT_EVERY = 0.02                             # s, grainflow particles CSV (centre of mass)


def rayleigh_time(r: float) -> float:
    shear = YOUNGS / (2 * (1 + POISSON))
    return math.pi * r * math.sqrt(DENSITY / shear) / (0.1631 * POISSON + 0.8766)


def drum_triangles():
    return stl.drum_triangles(DRUM_R, DRUM_L, SEGMENTS, LIFTERS, LIFTER_H, LIFTER_T)


def write_ascii_stl(path: Path, tris, name="grainflow_drum_with_lifters") -> None:
    """ASCII STL (LIGGGHTS 3.8 reads only ASCII; grainflow reads both)."""
    out = [f"solid {name}"]
    for a, b, c in tris:
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        ln = math.sqrt(sum(x * x for x in n)) or 1.0
        out.append("  facet normal " + " ".join(f"{x / ln:.9e}" for x in n))
        out.append("    outer loop")
        for p in (a, b, c):
            out.append("      vertex " + " ".join(f"{float(x):.12e}" for x in p))
        out.append("    endloop")
        out.append("  endfacet")
    out.append(f"endsolid {name}")
    path.write_text("\n".join(out) + "\n")


def lattice_beads(n: int, seed: int) -> list[tuple[float, float, float, float]]:
    """The N lowest sites (z, then y, then x) of the simple cubic lattice in the fill cylinder,
    each with a radius uniform in [R_MIN, R_MAX] (seeded): [(x, y, z, r)]."""
    k_max = int(FILL_R / SPACING) + 1
    ys = []
    y = FILL_Y[0]
    while y <= FILL_Y[1] + 1e-12:
        ys.append(y)
        y += SPACING
    sites = []
    for i in range(-k_max, k_max + 1):
        for k in range(-k_max, k_max + 1):
            x, z = i * SPACING, k * SPACING
            if math.hypot(x, z) <= FILL_R + 1e-12:
                sites += [(x, yy, z) for yy in ys]
    if n > len(sites):
        sys.exit(f"--n {n}: the lattice has only {len(sites)} sites (spacing {SPACING} m, "
                 f"radius {FILL_R} m, y in {FILL_Y})")
    sites.sort(key=lambda p: (round(p[2], 9), round(p[1], 9), round(p[0], 9)))
    rng = random.Random(seed)
    return [(x, y, z, rng.uniform(R_MIN, R_MAX)) for x, y, z in sites[:n]]


def bed_weight(beads) -> tuple[float, float]:
    """(mass kg, weight N) of the beads."""
    m = sum(DENSITY * 4.0 / 3.0 * math.pi * r ** 3 for *_, r in beads)
    return m, m * GRAVITY


# ---------------------------------------------------------------------------------------------
# LIGGGHTS
# ---------------------------------------------------------------------------------------------
def liggghts_data(beads, lo=DOMAIN_MIN, hi=DOMAIN_MAX, script="drum_vs_liggghts.py",
                  density=DENSITY) -> str:
    """A LIGGGHTS data file of the beads [(x, y, z, r)] (atom type 1) in the box lo-hi, with two
    atom types (2: the walls)."""
    lines = [f"LIGGGHTS data file: grainflow bench/mesh/{script}", "",
             f"{len(beads)} atoms", "2 atom types", "",
             f"{F(lo[0])} {F(hi[0])} xlo xhi",
             f"{F(lo[1])} {F(hi[1])} ylo yhi",
             f"{F(lo[2])} {F(hi[2])} zlo zhi", "", "Atoms", ""]
    # atom_style granular: atom-ID atom-type diameter density x y z
    for i, (x, y, z, r) in enumerate(beads):
        lines.append(f"{i + 1} 1 {2 * r:.15g} {F(density)} {x:.15g} {y:.15g} {z:.15g}")
    return "\n".join(lines) + "\n"


def make_run_root(keep: bool, tag: str) -> Path:
    """The folder of a benchmark's runs: bench/runs/<tag>-<time>/ with --keep, else a temporary
    one (removed at the end by the caller)."""
    stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    root = (BENCH / "runs" / f"{tag}-{stamp}") if keep else Path(
        tempfile.mkdtemp(prefix=f"gf-{tag}-"))
    root.mkdir(parents=True, exist_ok=True)
    print(f"run folders: {root}" + ("" if keep else " (removed at the end; --keep keeps)"),
          flush=True)
    return root


def liggghts_input(n: int, fill_steps: int, run_steps: int, curvature: float | None) -> str:
    thermo = max(1, round(SERIES_EVERY / DT))
    curv = ""
    if curvature is not None:
        # The end plates' fan triangles have a 3.75 degree apex angle; a larger curvature needs
        # curvature_tolerant (LIGGGHTS otherwise refuses it).
        curv = f" curvature {F(curvature)}" + (" curvature_tolerant yes"
                                               if curvature >= 360.0 / SEGMENTS else "")
    return f"""\
# grainflow bench/mesh/drum_vs_liggghts.py: {n} beads in a drum with lifters (STL mesh), 20 rpm
{liggghts_head("data.drum", "the drum", SKIN, YOUNGS, POISSON, RESTITUTION, FRICTION, DT,
               GRAVITY)}
# mesh/surface/stress = mesh/surface + the total force and torque on the mesh (global vector:
# force 1-3, torque about reference_point 4-6, default reference point the origin)
fix cad all mesh/surface/stress file drum.stl type 2{curv}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes cad
fix move all move/mesh mesh cad rotate origin 0. 0. 0. axis 0. 1. 0. period {F(PERIOD)}

fix integr all nve/sphere
compute erot all erotate/sphere
compute cm all com
thermo_style custom step atoms ke c_erot f_cad[5] c_cm[1] f_cad[3]
thermo {thermo}
thermo_modify lost ignore norm no

run {fill_steps}
run {run_steps}
"""


def liggghts_head(data: str, walls: str, skin, youngs, poisson, restitution, friction, dt,
                  gravity) -> str:
    """The head of a LIGGGHTS deck of these benchmarks: the granular preamble, the data file,
    the neighbour skin, per-type properties (type 1 the beads, type 2 `walls`, the same E and
    nu), Hertz-Mindlin with tangential history, the step and gravity along -z."""
    e, mu = F(restitution), F(friction)
    return f"""{ts.LIGGGHTS_PREAMBLE}
read_data {data}

neighbor {F(skin)} bin
neigh_modify delay 0

# type 1 = beads, type 2 = {walls} (same E and nu)
fix m1 all property/global youngsModulus peratomtype {F(youngs)} {F(youngs)}
fix m2 all property/global poissonsRatio peratomtype {F(poisson)} {F(poisson)}
fix m3 all property/global coefficientRestitution peratomtypepair 2 {e} {e} {e} {e}
fix m4 all property/global coefficientFriction peratomtypepair 2 {mu} {mu} {mu} {mu}

pair_style gran model hertz tangential history
pair_coeff * *
timestep {F(dt)}
fix gravi all gravity {F(gravity)} vector 0.0 0.0 -1.0
"""


THERMO_RE = re.compile(r"^\s*(\d+)\s+(\d+)" + r"\s+(\S+)" * 5 + r"\s*$", re.M)


def run_liggghts_two_loops(exe, deck: str, workdir: Path, args, res: dict):
    """Runs LIGGGHTS on the input `deck` in `workdir` (log.liggghts); records its version,
    warnings and the two timed phases (fill, run: its first two `Loop time` records) in `res`.
    Returns (log text, loops), or None with res["why"] set when it failed."""
    # No `-screen none`: LIGGGHTS 3.8 segfaults in InputMeshTri::meshtrifile (it prints to the
    # null screen while reading the STL), so the screen output is captured instead.
    proc = run_timed([exe, "-in", deck, "-log", "log.liggghts"], workdir, "liggghts",
                     args.timeout)
    logp = workdir / "log.liggghts"
    log = logp.read_text(errors="replace") if logp.exists() else ""
    loops = [dict(seconds=float(m.group(1)), steps=int(m.group(3)), atoms=int(m.group(4)))
             for m in LOOP_RE.finditer(log)]
    v = re.search(r"LIGGGHTS \(Version ([^,)]+)", log)
    res["version"] = v.group(1) if v else "unknown"
    res["warnings"] = sorted({l.strip() for l in log.splitlines() if "WARNING" in l})
    if proc.rc != 0 or len(loops) < 2:
        err = [l for l in (log + proc.stdout + proc.stderr).splitlines() if "ERROR" in l]
        res["why"] = (f"exit {proc.rc}, {len(loops)} loop(s) in log; "
                      + (" | ".join(err[:2]) if err else _tail(proc.stdout + proc.stderr + log)))
        return None
    res["phases"] = ts.peer_phases(proc, loops, ("fill", "run"))
    res["maxrss"] = proc.maxrss_bytes
    return log, loops


def run_liggghts(exe, beads, tris, fill_steps, run_steps, workdir: Path, args) -> dict:
    res = {"code": "LIGGGHTS", "ok": False, "version": "n/a"}
    if exe is None:
        res["why"] = f"binary not found ({args.liggghts})"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    write_ascii_stl(workdir / "drum.stl", tris)
    (workdir / "data.drum").write_text(liggghts_data(beads))
    (workdir / "in.drum").write_text(liggghts_input(len(beads), fill_steps, run_steps,
                                                    args.curvature))
    got = run_liggghts_two_loops(exe, "in.drum", workdir, args, res)
    if got is None:
        return res
    log, loops = got
    res["mesh_info"] = [l.strip() for l in log.splitlines()
                        if re.search(r"(?i)mesh|element|neighbor|curvature", l)
                        and not l.lstrip().startswith(("fix ", "#"))][:20]
    res["n_end"] = loops[1]["atoms"]
    rows = {}
    for m in THERMO_RE.finditer(log):
        try:
            step = int(m.group(1))
            rows[step] = dict(t=step * DT, atoms=int(m.group(2)), ke=float(m.group(3)),
                              erot=float(m.group(4)), torque_y=float(m.group(5)),
                              com_x=float(m.group(6)), force_z=float(m.group(7)))
        except ValueError:
            pass
    res["series"] = [rows[k] for k in sorted(rows)]
    res["ok"] = True
    return res


# ---------------------------------------------------------------------------------------------
# grainflow
# ---------------------------------------------------------------------------------------------
def _vec(v) -> str:
    return "[" + ", ".join(F(x) for x in v) + "]"


def grainflow_case(n: int, end: float, checkpoint_every: float, snapshot_every: float,
                   outdir: str) -> str:
    return f"""\
# grainflow bench/mesh/drum_vs_liggghts.py: {n} beads in a drum with lifters (STL mesh), 20 rpm
name: drum_vs_liggghts_{n}
dimension: 3
time: {{step: {F(DT)}, end: {F(end)}}}
domain: {{min: {_vec(DOMAIN_MIN)}, max: {_vec(DOMAIN_MAX)}}}
gravity: [0.0, 0.0, {F(-GRAVITY)}]
materials:
  beads: {{density: {F(DENSITY)}, youngs_modulus: {F(YOUNGS)}, poisson_ratio: {F(POISSON)}}}
  steel: {{density: {F(WALL_DENSITY)}, youngs_modulus: {F(YOUNGS)}, poisson_ratio: {F(POISSON)}}}
contacts:
  - {{between: [beads, beads], model: hertz_mindlin, restitution: {F(RESTITUTION)}, friction: {F(FRICTION)}, rolling_friction: 0.0}}
  - {{between: [beads, steel], model: hertz_mindlin, restitution: {F(RESTITUTION)}, friction: {F(FRICTION)}, rolling_friction: 0.0}}
particles:
  - {{shape: sphere, material: beads, file: particles.csv}}
walls:
  - name: drum
    mesh: {{file: drum.stl}}
    material: steel
    motion: {{rotate: {{axis: [0.0, 1.0, 0.0], center: [0.0, 0.0, 0.0], rpm: {F(RPM)}}}}}
neighbor: {{skin: {F(SKIN)}}}
output:
  directory: {outdir}
  particles_csv: {{every: {F(snapshot_every)}}}
  series: {{every: {F(SERIES_EVERY)}, quantities: [translational_kinetic_energy, rotational_kinetic_energy, wall_torque.drum.y, wall_force.drum.z, contact_count, wall_contact_count]}}
  checkpoint: {{every: {F(checkpoint_every)}}}
"""


def _read_series(path: Path) -> list[dict]:
    try:
        with path.open() as f:
            rows = []
            for r in csv.DictReader(l for l in f if l.strip() and not l.startswith("#")):
                rows.append({k.strip(): float(v) for k, v in r.items() if k and v not in (None, "")})
            return rows
    except (OSError, ValueError):
        return []


def _com_x(path: Path) -> float | None:
    """Mass-weighted mean x of a particles CSV (one density: weights r^3)."""
    try:
        with path.open() as f:
            rd = csv.DictReader(l for l in f if l.strip() and not l.startswith("#"))
            sw = swx = 0.0
            for r in rd:
                w = float(r["radius"]) ** 3
                sw += w
                swx += w * float(r["x"])
            return swx / sw if sw else None
    except (OSError, KeyError, ValueError):
        return None


def run_grainflow_two_phases(exe, workdir: Path, args, res: dict) -> dict | None:
    """Runs grainflow on workdir/fill.yaml, then on workdir/run.yaml from the fill's last
    checkpoint, one thread each; records the two timed phases and their warnings in `res`.
    Returns the two summary.json contents by phase, or None with res["why"] set."""
    summ, procs = {}, {}
    for tag in ("fill", "run"):
        restart = None
        if tag == "run":
            restart = ts.last_checkpoint(workdir / "fill")
            if restart is None:
                res["why"] = "fill run wrote no checkpoint"
                return None
        proc, s, why = ts._grainflow_one(exe, workdir / f"{tag}.yaml", workdir / tag, 1,
                                         restart, tag, args)
        if why:
            res["why"] = f"{tag} run: {why}"
            return None
        summ[tag], procs[tag] = s, proc
    res["phases"] = {tag: {"steps": int(s["steps"]), "seconds": float(s["loop_seconds"]),
                           "load": procs[tag].load, "cpu_share": procs[tag].cpu_share,
                           "loop_fraction": float(s["loop_seconds"]) / max(procs[tag].wall, 1e-9)}
                     for tag, s in summ.items()}
    return summ


def grainflow_result(exe) -> dict:
    """The result record of a grainflow run with its version (and the binary's date)."""
    res = {"code": "grainflow", "ok": False, "version": "n/a"}
    if exe is not None:
        built = _dt.datetime.fromtimestamp(Path(exe).stat().st_mtime).strftime("%Y-%m-%d %H:%M")
        res["version"] = ts.grainflow_version(exe) + f" (binary of {built})"
    return res


def run_grainflow(exe, beads, tris, fill_steps, run_steps, workdir: Path, args) -> dict:
    res = grainflow_result(exe)
    if exe is None:
        res["why"] = f"binary not found ({args.grainflow})"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    write_ascii_stl(workdir / "drum.stl", tris)
    (workdir / "particles.csv").write_text(
        "x,y,z,radius\n" + "".join(f"{x:.15g},{y:.15g},{z:.15g},{r:.15g}\n"
                                   for x, y, z, r in beads))
    t1, t2 = fill_steps * DT, (fill_steps + run_steps) * DT
    n = len(beads)
    (workdir / "fill.yaml").write_text(grainflow_case(n, t1, t1, 0.0, "fill"))
    # Run phase: no periodic checkpoints inside the timed loop; particle snapshots for the
    # bed's centre of mass.
    (workdir / "run.yaml").write_text(grainflow_case(n, t2, 0.0, SNAPSHOT_EVERY, "run"))
    summ = run_grainflow_two_phases(exe, workdir, args, res)
    if summ is None:
        return res
    res["n"] = int(summ["fill"].get("n_particles", n))
    res["n_end"] = int(summ["run"].get("n_particles", 0))
    res["stages"] = {tag: s.get("stages") for tag, s in summ.items()}
    res["summary"] = summ
    res["stderr"] = {tag: (workdir / f"{tag}.stderr").read_text(errors="replace")
                     for tag in summ if (workdir / f"{tag}.stderr").exists()}
    res["warnings"] = sorted({l.strip() for t in res["stderr"].values() for l in t.splitlines()
                              if re.search(r"(?i)warn", l)})
    series = _read_series(workdir / "fill" / "series.csv") + _read_series(workdir / "run" / "series.csv")
    by_t = {}
    for r in series:
        t = r.get("time")
        if t is None:
            continue
        by_t[round(t / DT)] = dict(
            t=t, ke=r.get("translational_kinetic_energy"), erot=r.get("rotational_kinetic_energy"),
            torque_y=r.get("wall_torque.drum.y"), force_z=r.get("wall_force.drum.z"),
            contacts=r.get("contact_count"), wall_contacts=r.get("wall_contact_count"))
    res["series"] = [by_t[k] for k in sorted(by_t)]
    snaps = []
    for p in sorted((workdir / "run").glob("particles_*.csv")):
        m = re.search(r"particles_(\d+)\.csv$", p.name)
        if m:
            snaps.append({"step": int(m.group(1)), "com_x": _com_x(p)})
    res["snapshots"] = snaps
    res["ok"] = True
    return res


# ---------------------------------------------------------------------------------------------
# Cross-check and report
# ---------------------------------------------------------------------------------------------
def _mean(xs):
    xs = [x for x in xs if x is not None and x == x]
    return (statistics.fmean(xs), statistics.pstdev(xs), len(xs)) if xs else (None, None, 0)


def cross_check(r: dict, t_end: float, window: float, weight: float) -> dict:
    t0 = t_end - window - 0.5 * DT
    rows = [s for s in r.get("series", []) if s["t"] >= t0]
    out = {k: _mean([s.get(k) for s in rows]) for k in ("torque_y", "ke", "erot", "force_z")}
    if r["code"] == "LIGGGHTS":
        out["com_x"] = _mean([s.get("com_x") for s in rows])
    else:
        # Snapshot names carry the step counted from t = 0, or an output index: take the
        # snapshots in the window by step if the numbers look like steps, else the last ones.
        snaps = r.get("snapshots", [])
        steps = [s["step"] for s in snaps]
        if steps and max(steps) >= round(0.9 * t_end / DT):
            sel = [s for s in snaps if s["step"] * DT >= t0]
        else:
            sel = snaps[-(int(round(window / SNAPSHOT_EVERY)) + 1):]
        out["com_x"] = _mean([s["com_x"] for s in sel])
    cx = out["com_x"][0]
    out["gravity_torque"] = weight * cx if cx is not None else None
    return out


def rate(n, ph):
    return n * ph["steps"] / ph["seconds"] if ph["seconds"] > 0 else float("nan")


def _f(x, fmt):
    return "n/a" if x is None or x != x else format(x, fmt)


def format_table(n, per) -> str:
    head = ("| N | code | phase | steps | loop s | particle-steps/s | gf/LIGGGHTS | "
            "load (start/mean/max) | CPU share |")
    out = [head, "|" + "---|" * head.count(" | ") + "---|"]
    for phase in ("fill", "run"):
        ref = per.get("LIGGGHTS")
        ref_rate = rate(n, ref["phases"][phase]) if ref and ref["ok"] else None
        for code in ("LIGGGHTS", "grainflow"):
            r = per.get(code)
            if r is None:
                continue
            if not r["ok"]:
                out.append(f"| {n} | {code} | {phase} | n/a | n/a | n/a | n/a | n/a | n/a |")
                continue
            ph = r["phases"][phase]
            rt = rate(n, ph)
            ratio = 1.0 if code == "LIGGGHTS" else (rt / ref_rate if ref_rate else None)
            ld = ph["load"]
            out.append("| " + " | ".join([
                str(n), code, phase, str(ph["steps"]), f"{ph['seconds']:.2f}", f"{rt:.3g}",
                _f(ratio, ".2f"), f"{ld['start']:.2f}/{ld['mean']:.2f}/{ld['max']:.2f}",
                _f(ph["cpu_share"], ".2f")]) + " |")
    return "\n".join(out)


def format_cross(per, checks, weight, window) -> str:
    head = (f"| code | torque_y on drum, N m (mean ± sd, last {window:g} s) | x_cm, m | "
            "M g x_cm, N m | force_z on drum, N | KE transl., J | KE rot., J | beads at end |")
    out = [head, "|" + "---|" * head.count(" | ") + "---|"]
    for code in ("LIGGGHTS", "grainflow"):
        r = per.get(code)
        if not r or not r["ok"]:
            continue
        c = checks[code]

        def ms(key, fmt):
            m, s, k = c[key]
            return "n/a" if m is None else f"{m:{fmt}} ± {s:{fmt}} ({k})"
        out.append("| " + " | ".join([
            code, ms("torque_y", ".4f"), ms("com_x", ".5f"), _f(c["gravity_torque"], ".4f"),
            ms("force_z", ".3f"), ms("ke", ".3e"), ms("erot", ".3e"),
            str(r.get("n_end"))]) + " |")
    return "\n".join(out)


def stage_shares(r: dict) -> dict:
    """{phase: [(stage, seconds, share)]} from grainflow's summary.json `stages`; the share is of
    the stages' sum (as grainflow's own timing summary prints it: the stages also hold the
    set-up neighbour build, so their sum is a little more than loop_seconds)."""
    out = {}
    for tag, st in (r.get("stages") or {}).items():
        if not isinstance(st, dict):
            continue
        items = [(k, float(v)) for k, v in st.items() if isinstance(v, (int, float))]
        total = sum(s for _, s in items)
        out[tag] = sorted(((k, s, s / total if total > 0 else float("nan")) for k, s in items),
                          key=lambda x: -x[1])
    return out


def fmt_stages(sh: dict) -> str:
    return "; ".join(f"{tag}: " + ", ".join(f"{k} {s:.2f} s ({100 * f:.0f} %)" for k, s, f in items)
                     for tag, items in sh.items())


# ---------------------------------------------------------------------------------------------
# Driver
# ---------------------------------------------------------------------------------------------
def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="See bench/mesh/README.md.")
    ap.add_argument("--n", type=int, default=2500, help="number of beads (default %(default)s)")
    ap.add_argument("--fill-time", type=float, default=0.3,
                    help="simulated time of the fill phase, s (default %(default)s)")
    ap.add_argument("--run-time", type=float, default=0.5,
                    help="simulated time of the run phase, s (default %(default)s)")
    ap.add_argument("--avg-window", type=float, default=0.2,
                    help="cross-check means over the last this many s (default %(default)s)")
    ap.add_argument("--seed", type=int, default=5, help="seed of the radii (default %(default)s)")
    ap.add_argument("--curvature", type=float, default=None, metavar="DEG",
                    help="LIGGGHTS fix mesh/surface curvature in degrees (default: LIGGGHTS' own, "
                         "0.256; >= 3.75 adds curvature_tolerant yes)")
    add_peer_args(ap)
    return ap.parse_args(argv)


def add_peer_args(ap) -> None:
    """The options of the grainflow-vs-LIGGGHTS scripts: which codes, their binaries, waiting
    for a quiet machine, and ts.add_run_args' (limit, --keep, where to record)."""
    ap.add_argument("--codes", default="liggghts,grainflow", help="default %(default)s")
    ap.add_argument("--grainflow", default=str(ROOT / "build" / "release" / "grainflow"))
    ap.add_argument("--liggghts", default="/usr/bin/liggghts")
    ap.add_argument("--wait-quiet", type=float, default=None, metavar="LOAD",
                    help="before each process, wait until the 1-minute load average is below LOAD "
                         "(at most --wait-max s)")
    ap.add_argument("--wait-max", type=float, default=600.0,
                    help="longest wait for --wait-quiet, s (default %(default)s)")
    ts.add_run_args(ap)


def peer_codes(a):
    """(the codes asked for, grainflow's binary or None, LIGGGHTS' binary or None) from the
    options of add_peer_args; exits without /usr/bin/time."""
    codes = {c.strip().lower() for c in a.codes.split(",")}
    ts.QUIET.update(load=a.wait_quiet, max_wait=a.wait_max)
    if not Path("/usr/bin/time").exists():
        sys.exit("/usr/bin/time missing: apt-get install -y time")
    gf = ts.resolve_exe(a.grainflow) if "grainflow" in codes else None
    lig = ts.resolve_exe(a.liggghts) if "liggghts" in codes else None
    return codes, gf, lig


def main(argv=None) -> int:
    a = parse_args(argv)
    codes, gf, lig = peer_codes(a)
    beads = lattice_beads(a.n, a.seed)
    tris = drum_triangles()
    mass, weight = bed_weight(beads)
    fill_steps, run_steps = round(a.fill_time / DT), round(a.run_time / DT)
    t_end = (fill_steps + run_steps) * DT
    t_r = rayleigh_time(R_MIN)
    print(f"N = {len(beads)} beads ({mass:.4f} kg, weight {weight:.3f} N), {len(tris)} triangles; "
          f"fill {fill_steps} + run {run_steps} steps; dt = {DT / t_r:.3f} t_R of the smallest "
          f"bead; load now {os.getloadavg()[0]:.2f}", flush=True)
    root = make_run_root(a.keep, "mesh-drum")

    per = {}
    if "liggghts" in codes:
        per["LIGGGHTS"] = run_liggghts(lig, beads, tris, fill_steps, run_steps,
                                       root / "liggghts", a)
    if "grainflow" in codes:
        per["grainflow"] = run_grainflow(gf, beads, tris, fill_steps, run_steps,
                                         root / "grainflow", a)
    checks, notes = {}, []
    for code, r in per.items():
        if not r["ok"]:
            print(f"  {code}: n/a ({r['why']})")
            notes.append(f"{code}: n/a — {r['why']}")
            continue
        checks[code] = cross_check(r, t_end, a.avg_window, weight)
        if r.get("n_end") is not None and r["n_end"] != len(beads):
            notes.append(f"{code}: LOST {len(beads) - r['n_end']} beads")
        for w in r.get("warnings", [])[:8]:
            notes.append(f"{code} warning: {w}")
    table = format_table(len(beads), per)
    cross = format_cross(per, checks, weight, a.avg_window)
    print("\n" + table + "\n\n" + cross)
    gfr = per.get("grainflow")
    stages = stage_shares(gfr) if gfr and gfr["ok"] else {}
    if stages:
        print("\ngrainflow stages: " + fmt_stages(stages))
    for code, r in per.items():
        for w in r.get("warnings", []):
            print(f"{code} warning: {w}")
    if a.keep:
        (root / "results.json").write_text(json.dumps(
            {"args": vars(a), "per": {k: {kk: vv for kk, vv in v.items() if kk != "summary"}
                                      for k, v in per.items()},
             "checks": checks}, indent=2, default=str))
    if not a.no_record:
        lr = per.get("LIGGGHTS", {})
        curv = (f"curvature {a.curvature:g} deg" + (" + curvature_tolerant yes"
                                                     if a.curvature >= 360.0 / SEGMENTS else "")
                if a.curvature is not None else "its default curvature, 0.256 deg")
        lines = [
            "", f"## mesh drum vs LIGGGHTS — {_dt.datetime.now().astimezone().isoformat(timespec='seconds')}",
            "",
            f"- Machine: {lscpu_model()}, {os.cpu_count()} cores (`lscpu`), load average at the "
            f"end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
            f"- Codes: {per.get('grainflow', {}).get('version', 'grainflow not run')}, "
            f"{lr.get('version', 'LIGGGHTS not run')} (Debian `liggghts`); serial, "
            "1 process / 1 thread each, run one after the other; double precision "
            "(bench/mesh/drum_vs_liggghts.py)",
            f"- Case (mirror of cases/dem/drum_lifters): drum R {DRUM_R:g} m, length {DRUM_L:g} m "
            f"along y, {SEGMENTS} barrel panels, end plates, {LIFTERS} lifters {LIFTER_H * 1e3:g} x "
            f"{LIFTER_T * 1e3:g} mm; one ASCII STL of {len(tris)} triangles read by both; "
            f"{RPM:g} rpm counter-clockwise about +y; {len(beads)} glass beads r uniform "
            f"[{R_MIN * 1e3:g}, {R_MAX * 1e3:g}] mm (seed {a.seed}, {mass:.4f} kg), "
            f"{DENSITY:g} kg/m^3, E {YOUNGS:g} Pa, nu {POISSON:g}, e {RESTITUTION:g}, "
            f"mu {FRICTION:g}, no rolling friction, Hertz-Mindlin with tangential history "
            f"(walls too); dt {DT:g} s, skin {SKIN:g} m; start: the N lowest sites of a simple "
            f"cubic lattice ({SPACING * 1e3:g} mm) at rest, the same file for both",
            f"- Phases: fill = the first {a.fill_time:g} s ({fill_steps} steps) from the lattice; "
            f"run = {a.run_time:g} s more ({run_steps} steps; LIGGGHTS second `run`, grainflow "
            f"`--restart`); rate = N x steps / loop time; gf/LIGGGHTS > 1: grainflow faster",
            f"- LIGGGHTS mesh: `fix mesh/surface/stress` ({curv}), `fix wall/gran model hertz "
            f"tangential history mesh`, `fix move/mesh rotate period {PERIOD:g}`",
        ]
        if stages:
            lines.append("- grainflow stages (summary.json; share of the stages' sum): "
                         + fmt_stages(stages))
        lines += [f"- {t}" for t in notes]
        ts.append_section(Path(a.results), lines, a.note, [
            "", table, "",
            f"Cross-check, means over t in [{t_end - a.avg_window:g}, {t_end:g}] s "
            f"(samples every {SERIES_EVERY:g} s; grainflow x_cm from particle snapshots "
            f"every {SNAPSHOT_EVERY:g} s); the bed's weight is {weight:.3f} N:", "", cross, ""])
    if not a.keep:
        shutil.rmtree(root, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
