#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Side-by-side silo discharge: a flat-bottomed silo with an STL floor, grainflow vs LIGGGHTS.

The case mirrors cases/dem/silo without its recirculation and is built for both codes by this
script: a cylinder of radius 32 mm along z (grainflow `cylinder` wall, LIGGGHTS `wall/gran
primitive zcylinder`) standing on a flat floor at z = 0 with a central circular orifice of
diameter D = 24 mm = 6 d (the 128 triangles of scripts/make_silo_floor_stl.py, 64 sides,
written once as an ASCII STL that both codes read), and a gate plane at z = 0 that closes the
orifice while the bed settles. N glass beads (default 4000; radii uniform in [1.8, 2.2] mm,
seeded; 2500 kg/m^3, E 1e7 Pa, nu 0.3, e 0.5, mu 0.5, NO rolling friction: Hertz-Mindlin with
tangential history, walls too) start on the N lowest sites of a simple cubic lattice (spacing
4.6 mm, within 27.5 mm of the axis, from z = 4 mm up, each site shifted by a seeded random
horizontal offset of at most 0.09 mm so that the columns do not stay stacked) at rest; both
codes read these exact positions and radii. dt 2e-5 s, gravity -9.81 m/s^2 along z, skin 1 mm.

Two timed phases per code: (1) fill: --fill-time s with the gate closed (the beads fall and
settle); (2) run: the gate is taken away (LIGGGHTS: `unfix gate` before the second `run`;
grainflow: `--restart` from the fill's checkpoint, its gate moving down at 10 m/s from the start
of the run, out of reach of every bead within one step) and the silo discharges for --run-time
s. A bead that has fallen 20 mm below the floor leaves both simulations: grainflow's outlet
`below` (the box z < -0.02 m) takes it at the next neighbour-list build; LIGGGHTS loses it at
its box's bottom face, z = -0.02 m (`boundary f f f`, `thermo_modify lost ignore`).

Physics cross-check: the discharged mass against time (grainflow series outlet_mass.below;
LIGGGHTS thermo: initial mass minus `mass(all)`) and its least-squares slope, the mass flow rate
W, over the window from --transient s after the gate opens to the end; W of each code against
Beverloo's W = C rho_b sqrt(g) (D - k d)^(5/2) with k = 1.5 and the bulk density of the settled
bed (grainflow: solid fraction of the beads' centres 8-48 mm above the floor within 20 mm of the
axis, from the particles CSV at the end of the fill), which gives each code's C.

Speed: particle-steps per second (N x steps / loop time; LIGGGHTS `Loop time`, grainflow
summary.json) per phase, the ratio grainflow / LIGGGHTS, with the load average and CPU share
(helpers shared with bench/terrain_settling/run.py and bench/mesh/drum_vs_liggghts.py). In the
run phase N is the number at the start of the run (beads leave as it goes, the same in both).

Unless --no-record is given, a dated section is appended to bench/RESULTS.md.

Examples (from the repository root):
  /usr/bin/python3 bench/mesh/silo_vs_liggghts.py
  /usr/bin/python3 bench/mesh/silo_vs_liggghts.py --n 2000 --run-time 0.3 --no-record --keep
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import math
import os
import random
import re
import shutil
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCH = HERE.parent
ROOT = BENCH.parent


# The drum benchmark's helpers (ASCII STL writer, series reader, the two-phase runs of both
# codes, rates and tables) and through it the measurement helpers of
# bench/terrain_settling/run.py; the floor's triangles from the script that wrote
# cases/dem/silo/floor.stl. (bench/ is a package, the scripts run as files, so its root goes on
# the path.)
sys.path.append(str(ROOT))
from bench.mesh import drum_vs_liggghts as drum  # noqa: E402

floor_stl = drum._load("_make_silo_floor_stl", ROOT / "scripts" / "make_silo_floor_stl.py")
ts = drum.ts
F, lscpu_model = ts.F, ts.lscpu_model

# ---------------------------------------------------------------------------------------------
# The case (identical for both codes)
# ---------------------------------------------------------------------------------------------
SILO_R = 0.032                                    # barrel radius, m
ORIFICE_D, FLOOR_R, SEGMENTS = 0.024, 0.036, 64   # m, m, sides of the orifice
OUTLET_Z = -0.02                                  # beads below this leave, m
DOMAIN_MIN = (-0.036, -0.036, OUTLET_Z)           # LIGGGHTS box = grainflow domain above OUTLET_Z
DOMAIN_MAX = (0.036, 0.036, 0.19)
R_MIN, R_MAX = 0.0018, 0.0022                     # bead radii, m (uniform)
D_MEAN = R_MIN + R_MAX                            # mean diameter, m
DENSITY, YOUNGS, POISSON = 2500.0, 1.0e7, 0.3     # beads; the walls have the same E, nu
RESTITUTION, FRICTION = 0.5, 0.5
GRAVITY = 9.81                                    # m/s^2 along -z
DT = 2.0e-5                                       # s
SKIN = 0.001                                      # m
SPACING = 0.0046                                  # simple cubic lattice, m
FILL_R = 0.0275                                   # lattice sites within this radius of the axis
FILL_Z0 = 0.004                                   # lowest lattice layer, m
JITTER = 0.00009                                  # max horizontal shift of a site, m
GATE_SPEED = 10.0                                 # grainflow gate, m/s down from the run's start
SERIES_EVERY = 0.01                               # s, grainflow series / LIGGGHTS thermo
BED_Z = (0.008, 0.048)                            # solid-fraction probe: heights above the floor
BED_R = 0.020                                     # ... and distance from the axis, m
BEVERLOO_K = 1.5


def lattice_beads(n: int, seed: int) -> list[tuple[float, float, float, float]]:
    """The N lowest sites (z, then y, then x) of the simple cubic lattice in the fill cylinder,
    each shifted horizontally by a seeded offset of at most JITTER and given a radius uniform in
    [R_MIN, R_MAX]: [(x, y, z, r)]. Neighbouring sites keep a gap of at least
    SPACING - 2 R_MAX - 2 JITTER = 0.02 mm."""
    k_max = int(FILL_R / SPACING) + 1
    layer = [(i * SPACING, k * SPACING) for i in range(-k_max, k_max + 1)
             for k in range(-k_max, k_max + 1) if math.hypot(i, k) * SPACING <= FILL_R + 1e-12]
    layers = math.ceil(n / len(layer))
    top = FILL_Z0 + (layers - 1) * SPACING
    if top + R_MAX > DOMAIN_MAX[2]:
        sys.exit(f"--n {n}: {layers} lattice layers reach z = {top:.3f} m, above the domain "
                 f"({DOMAIN_MAX[2]} m)")
    sites = [(x, y, FILL_Z0 + j * SPACING) for j in range(layers) for x, y in layer]
    sites.sort(key=lambda p: (round(p[2], 9), round(p[1], 9), round(p[0], 9)))
    rng = random.Random(seed)
    out = []
    for x, y, z in sites[:n]:
        out.append((x + rng.uniform(-JITTER, JITTER), y + rng.uniform(-JITTER, JITTER), z,
                    rng.uniform(R_MIN, R_MAX)))
    return out


def bead_mass(r: float) -> float:
    return DENSITY * 4.0 / 3.0 * math.pi * r ** 3


def floor_triangles():
    return floor_stl.floor_triangles(0.5 * ORIFICE_D, FLOOR_R, SEGMENTS)


# ---------------------------------------------------------------------------------------------
# LIGGGHTS
# ---------------------------------------------------------------------------------------------
def liggghts_input(n: int, fill_steps: int, run_steps: int) -> str:
    thermo = max(1, round(SERIES_EVERY / DT))
    hertz = "model hertz tangential history"
    return f"""\
# grainflow bench/mesh/silo_vs_liggghts.py: {n} beads discharging from a silo (STL floor)
{drum.liggghts_head("data.silo", "barrel, floor and gate", SKIN, YOUNGS, POISSON, RESTITUTION,
                    FRICTION, DT, GRAVITY)}
fix floorcad all mesh/surface file floor.stl type 2
fix floor all wall/gran {hertz} mesh n_meshes 1 meshes floorcad
fix barrel all wall/gran {hertz} primitive type 2 zcylinder {F(SILO_R)} 0.0 0.0
fix gate all wall/gran {hertz} primitive type 2 zplane 0.0

fix integr all nve/sphere
variable m equal mass(all)
thermo_style custom step atoms ke v_m
thermo {thermo}
thermo_modify lost ignore norm no

run {fill_steps}
unfix gate
run {run_steps}
"""


THERMO_RE = re.compile(r"^\s*(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s*$", re.M)


def run_liggghts(exe, beads, tris, fill_steps, run_steps, workdir: Path, args) -> dict:
    res = {"code": "LIGGGHTS", "ok": False, "version": "n/a"}
    if exe is None:
        res["why"] = f"binary not found ({args.liggghts})"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    drum.write_ascii_stl(workdir / "floor.stl", tris, "grainflow_silo_floor")
    (workdir / "data.silo").write_text(
        drum.liggghts_data(beads, DOMAIN_MIN, DOMAIN_MAX, "silo_vs_liggghts.py", DENSITY))
    (workdir / "in.silo").write_text(liggghts_input(len(beads), fill_steps, run_steps))
    got = drum.run_liggghts_two_loops(exe, "in.silo", workdir, args, res)
    if got is None:
        return res
    log, loops = got
    res["n_fill_end"] = loops[0]["atoms"]
    res["n_end"] = loops[1]["atoms"]
    m0 = sum(bead_mass(r) for *_, r in beads)
    rows = {}
    for m in THERMO_RE.finditer(log):
        try:
            step = int(m.group(1))
            rows[step] = dict(t=step * DT, atoms=int(m.group(2)), out=m0 - float(m.group(4)))
        except ValueError:
            pass
    res["series"] = [rows[k] for k in sorted(rows)]
    res["ok"] = True
    return res


# ---------------------------------------------------------------------------------------------
# grainflow
# ---------------------------------------------------------------------------------------------
_vec = drum._vec


def grainflow_case(n: int, t_open: float, end: float, checkpoint_every: float,
                   snapshot_every: float, outdir: str) -> str:
    snap = f"\n  particles_csv: {{every: {F(snapshot_every)}}}" if snapshot_every > 0 else ""
    return f"""\
# grainflow bench/mesh/silo_vs_liggghts.py: {n} beads discharging from a silo (STL floor)
name: silo_vs_liggghts_{n}
dimension: 3
time: {{step: {F(DT)}, end: {F(end)}}}
domain: {{min: {_vec(DOMAIN_MIN[:2] + (OUTLET_Z - 0.03,))}, max: {_vec(DOMAIN_MAX)}}}
gravity: [0.0, 0.0, {F(-GRAVITY)}]
materials:
  beads: {{density: {F(DENSITY)}, youngs_modulus: {F(YOUNGS)}, poisson_ratio: {F(POISSON)}}}
contacts:
  - {{between: [beads, beads], model: hertz_mindlin, restitution: {F(RESTITUTION)}, friction: {F(FRICTION)}, rolling_friction: 0.0}}
particles:
  - {{shape: sphere, material: beads, file: particles.csv}}
walls:
  - name: barrel
    cylinder: {{center: [0.0, 0.0, 0.0], axis: [0.0, 0.0, 1.0], radius: {F(SILO_R)}, inside: true}}
    material: beads
  - name: floor
    mesh: {{file: floor.stl}}
    material: beads
  - name: gate
    plane: {{point: [0.0, 0.0, 0.0], normal: [0.0, 0.0, 1.0]}}
    material: beads
    motion: {{translate: {{velocity: [0.0, 0.0, {F(-GATE_SPEED)}], start: {F(t_open)}}}}}
outlets:
  - name: below
    box: {{min: {_vec(DOMAIN_MIN[:2] + (OUTLET_Z - 0.03,))}, max: {_vec(DOMAIN_MAX[:2] + (OUTLET_Z,))}}}
neighbor: {{skin: {F(SKIN)}}}
output:
  directory: {outdir}{snap}
  series: {{every: {F(SERIES_EVERY)}, quantities: [particle_count, outlet_mass.below, kinetic_energy]}}
  checkpoint: {{every: {F(checkpoint_every)}}}
"""


def bed_solid_fraction(path: Path) -> tuple[float, float] | None:
    """Solid fraction of the settled bed from a particles CSV: the volume of the beads whose
    centres lie in the probe (BED_R about the axis, from BED_Z[0] above the floor up to BED_Z[1]
    or three diameters under the bed's surface, the 90th percentile of the centres' heights,
    whichever is lower) over the probe's volume; with the probe's top, m. None when the bed is
    too shallow for a probe two diameters high."""
    rows = [r for r in drum._read_series(path) if {"x", "y", "z", "radius"} <= r.keys()]
    if not rows:
        return None
    zs = sorted(r["z"] for r in rows)
    top = min(BED_Z[1], zs[int(0.9 * (len(zs) - 1))] - 3 * D_MEAN)
    if top - BED_Z[0] < 2 * D_MEAN:
        return None
    v = sum(4.0 / 3.0 * math.pi * r["radius"] ** 3 for r in rows
            if BED_Z[0] <= r["z"] <= top and math.hypot(r["x"], r["y"]) <= BED_R)
    return v / (math.pi * BED_R ** 2 * (top - BED_Z[0])), top


def run_grainflow(exe, beads, tris, fill_steps, run_steps, workdir: Path, args) -> dict:
    res = drum.grainflow_result(exe)
    if exe is None:
        res["why"] = f"binary not found ({args.grainflow})"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    drum.write_ascii_stl(workdir / "floor.stl", tris, "grainflow_silo_floor")
    (workdir / "particles.csv").write_text(
        "x,y,z,radius\n" + "".join(f"{x:.15g},{y:.15g},{z:.15g},{r:.15g}\n"
                                   for x, y, z, r in beads))
    t1, t2 = fill_steps * DT, (fill_steps + run_steps) * DT
    n = len(beads)
    # Fill: one particle snapshot at its end (the bed's solid fraction); run: no periodic
    # checkpoints or snapshots inside the timed loop.
    (workdir / "fill.yaml").write_text(grainflow_case(n, t1, t1, t1, t1, "fill"))
    (workdir / "run.yaml").write_text(grainflow_case(n, t1, t2, 0.0, 0.0, "run"))
    summ = drum.run_grainflow_two_phases(exe, workdir, args, res)
    if summ is None:
        return res
    res["stages"] = {tag: s.get("stages") for tag, s in summ.items()}
    res["warnings"] = sorted({l.strip() for tag in summ
                              for l in (workdir / f"{tag}.stderr").read_text(errors="replace")
                              .splitlines() if re.search(r"(?i)warn", l)})
    series = drum._read_series(workdir / "run" / "series.csv")
    res["series"] = [dict(t=r["time"], atoms=int(r.get("particle_count", 0)),
                          out=r.get("outlet_mass.below", 0.0)) for r in series if "time" in r]
    fill_series = drum._read_series(workdir / "fill" / "series.csv")
    res["n_fill_end"] = int(fill_series[-1].get("particle_count", 0)) if fill_series else None
    res["n_end"] = res["series"][-1]["atoms"] if res["series"] else None
    snaps = sorted((workdir / "fill").glob("particles_*.csv"))
    probe = bed_solid_fraction(snaps[-1]) if snaps else None
    res["solid_fraction"], res["probe_top"] = probe if probe else (None, None)
    res["ok"] = True
    return res


# ---------------------------------------------------------------------------------------------
# Cross-check and report
# ---------------------------------------------------------------------------------------------
def flow_rate(series: list[dict], t0: float, t1: float) -> tuple[float | None, float | None]:
    """Least-squares slope of the discharged mass over [t0, t1] (kg/s) and the largest deviation
    of the samples from the fitted line (kg)."""
    pts = [(s["t"], s["out"]) for s in series if t0 - 1e-9 <= s["t"] <= t1 + 1e-9]
    if len(pts) < 3:
        return None, None
    n = len(pts)
    mt = sum(t for t, _ in pts) / n
    mm = sum(m for _, m in pts) / n
    stt = sum((t - mt) ** 2 for t, _ in pts)
    w = sum((t - mt) * (m - mm) for t, m in pts) / stt
    dev = max(abs(m - (mm + w * (t - mt))) for t, m in pts)
    return w, dev


def beverloo_c(w: float, solid_fraction: float) -> float:
    rho_b = solid_fraction * DENSITY
    return w / (rho_b * math.sqrt(GRAVITY) * (ORIFICE_D - BEVERLOO_K * D_MEAN) ** 2.5)


def format_cross(per, checks, window) -> str:
    head = (f"| code | W, g/s (slope, t in [{window[0]:g}, {window[1]:g}] s) | largest deviation "
            "from the line, g | W first half / second half, g/s | beads out | beads at end | "
            "Beverloo C (k 1.5, grainflow's rho_b) |")
    out = [head, "|" + "---|" * head.count(" | ") + "---|"]
    for code in ("LIGGGHTS", "grainflow"):
        r = per.get(code)
        if not r or not r["ok"]:
            continue
        c = checks[code]
        g = (lambda x, fmt: drum._f(None if x is None else 1e3 * x, fmt))
        out.append("| " + " | ".join([
            code, g(c["w"], ".2f"), g(c["dev"], ".2f"),
            f"{g(c['w1'], '.2f')} / {g(c['w2'], '.2f')}", str(c["beads_out"]),
            str(r.get("n_end")), drum._f(c.get("C"), ".3f")]) + " |")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# Driver
# ---------------------------------------------------------------------------------------------
def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="See bench/mesh/README.md.")
    ap.add_argument("--n", type=int, default=4000, help="number of beads (default %(default)s)")
    ap.add_argument("--fill-time", type=float, default=0.5,
                    help="simulated time with the gate closed, s (default %(default)s)")
    ap.add_argument("--run-time", type=float, default=0.6,
                    help="simulated time of the discharge, s (default %(default)s)")
    ap.add_argument("--transient", type=float, default=0.15,
                    help="the flow rate is fitted from this long after the gate opens to the "
                         "end, s (default %(default)s)")
    ap.add_argument("--seed", type=int, default=7, help="seed of the start (default %(default)s)")
    drum.add_peer_args(ap)
    return ap.parse_args(argv)


def main(argv=None) -> int:
    a = parse_args(argv)
    codes, gf, lig = drum.peer_codes(a)
    beads = lattice_beads(a.n, a.seed)
    tris = floor_triangles()
    mass = sum(bead_mass(r) for *_, r in beads)
    fill_steps, run_steps = round(a.fill_time / DT), round(a.run_time / DT)
    t_open, t_end = fill_steps * DT, (fill_steps + run_steps) * DT
    window = (t_open + a.transient, t_end)
    if window[1] - window[0] < 0.1:
        sys.exit("--run-time minus --transient must be at least 0.1 s")
    print(f"N = {len(beads)} beads ({mass:.4f} kg), floor of {len(tris)} triangles, orifice "
          f"{ORIFICE_D * 1e3:g} mm = {ORIFICE_D / D_MEAN:g} d; fill {fill_steps} + run "
          f"{run_steps} steps; load now {os.getloadavg()[0]:.2f}", flush=True)
    root = drum.make_run_root(a.keep, "mesh-silo")

    per = {}
    if "liggghts" in codes:
        per["LIGGGHTS"] = run_liggghts(lig, beads, tris, fill_steps, run_steps,
                                       root / "liggghts", a)
    if "grainflow" in codes:
        per["grainflow"] = run_grainflow(gf, beads, tris, fill_steps, run_steps,
                                         root / "grainflow", a)
    gfr = per.get("grainflow")
    phi = gfr.get("solid_fraction") if gfr and gfr["ok"] else None
    checks, notes = {}, []
    mid = 0.5 * (window[0] + window[1])
    for code, r in per.items():
        if not r["ok"]:
            print(f"  {code}: n/a ({r['why']})")
            notes.append(f"{code}: n/a — {r['why']}")
            continue
        w, dev = flow_rate(r["series"], *window)
        w1, _ = flow_rate(r["series"], window[0], mid)
        w2, _ = flow_rate(r["series"], mid, window[1])
        checks[code] = dict(w=w, dev=dev, w1=w1, w2=w2,
                            beads_out=(r["n_fill_end"] or 0) - (r["n_end"] or 0),
                            C=beverloo_c(w, phi) if (w is not None and phi) else None)
        if r.get("n_fill_end") is not None and r["n_fill_end"] != len(beads):
            notes.append(f"{code}: {len(beads) - r['n_fill_end']} beads LOST while the gate was "
                         "closed")
        for wn in r.get("warnings", [])[:8]:
            notes.append(f"{code} warning: {wn}")
    lg, gc = checks.get("LIGGGHTS"), checks.get("grainflow")
    if lg and gc and lg["w"] and gc["w"] is not None:
        notes.append(f"W grainflow / LIGGGHTS = {gc['w'] / lg['w']:.3f}")
    if phi:
        notes.append(f"solid fraction of the settled bed (grainflow, centres {BED_Z[0] * 1e3:g}-"
                     f"{gfr['probe_top'] * 1e3:.0f} mm up within {BED_R * 1e3:g} mm of the axis): "
                     f"{phi:.3f}")
    elif gfr and gfr["ok"]:
        notes.append("solid fraction of the bed: n/a (bed too shallow for the probe), no "
                     "Beverloo C")
    table = drum.format_table(len(beads), per)
    cross = format_cross(per, checks, window)
    print("\n" + table + "\n\n" + cross + "\n\n" + "\n".join(notes))
    stages = drum.stage_shares(gfr) if gfr and gfr["ok"] else {}
    if stages:
        print("\ngrainflow stages: " + drum.fmt_stages(stages))
    if a.keep:
        (root / "results.json").write_text(json.dumps(
            {"args": vars(a), "per": per, "checks": checks}, indent=2, default=str))
    if not a.no_record:
        lr = per.get("LIGGGHTS", {})
        lines = [
            "", f"## silo discharge vs LIGGGHTS — "
            f"{_dt.datetime.now().astimezone().isoformat(timespec='seconds')}", "",
            f"- Machine: {lscpu_model()}, {os.cpu_count()} cores (`lscpu`), load average at the "
            f"end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
            f"- Codes: {per.get('grainflow', {}).get('version', 'grainflow not run')}, "
            f"{lr.get('version', 'LIGGGHTS not run')} (Debian `liggghts`); serial, "
            "1 process / 1 thread each, run one after the other; double precision "
            "(bench/mesh/silo_vs_liggghts.py)",
            f"- Case (mirror of cases/dem/silo, no recirculation): barrel R {SILO_R * 1e3:g} mm "
            f"(grainflow cylinder wall, LIGGGHTS primitive zcylinder); flat floor at z = 0 with a "
            f"central orifice D {ORIFICE_D * 1e3:g} mm ({SEGMENTS} sides, one ASCII STL of "
            f"{len(tris)} triangles read by both); gate plane z = 0 during the fill; "
            f"{len(beads)} glass beads r uniform [{R_MIN * 1e3:g}, {R_MAX * 1e3:g}] mm (seed "
            f"{a.seed}, {mass:.4f} kg), {DENSITY:g} kg/m^3, E {YOUNGS:g} Pa, nu {POISSON:g}, "
            f"e {RESTITUTION:g}, mu {FRICTION:g}, no rolling friction, Hertz-Mindlin with "
            f"tangential history (walls too); dt {DT:g} s, skin {SKIN:g} m; start: the N lowest "
            f"sites of a jittered simple cubic lattice ({SPACING * 1e3:g} mm) at rest, the same "
            "file for both; beads leave 20 mm below the floor",
            f"- Phases: fill = {a.fill_time:g} s ({fill_steps} steps) with the gate closed; "
            f"run = {a.run_time:g} s of discharge ({run_steps} steps; LIGGGHTS `unfix gate` and "
            f"a second `run`, grainflow `--restart` with the gate moving away); rate = N x "
            f"steps / loop time with N = {len(beads)} in both phases; gf/LIGGGHTS > 1: grainflow "
            "faster",
        ]
        if stages:
            lines.append("- grainflow stages (summary.json; share of the stages' sum): "
                         + drum.fmt_stages(stages))
        lines += [f"- {t}" for t in notes]
        ts.append_section(Path(a.results), lines, a.note, [
            "", table, "",
            f"Discharge (samples every {SERIES_EVERY:g} s; W the least-squares slope of the "
            f"discharged mass, the halves split the window at {mid:g} s):", "", cross, ""])
    if not a.keep:
        shutil.rmtree(root, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
