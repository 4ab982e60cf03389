#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Side-by-side heated bed: heat conduction through contacts, grainflow vs LIGGGHTS.

The case mirrors cases/dem/heated_bed and is built for both codes by this script: a slab
--side x --side m periodic in x and y above a plane floor at z = 0 held at 373 K (grainflow
plane wall with `temperature`, LIGGGHTS `fix wall/gran ... primitive type 2 zplane 0.0
temperature 373`). N glass beads (default 4000; radii uniform in [1.4, 1.6] mm, seeded;
2500 kg/m^3, E 1e7 Pa, nu 0.3, e 0.5, mu 0.5, Hertz-Mindlin with tangential history, the floor
too) start at 293 K at rest on the N lowest sites of a simple cubic lattice (spacing 3.5 mm,
from z = 2 mm up, each site shifted by a seeded horizontal offset of at most 0.1 mm); both codes
read these exact positions and radii. Thermal properties: beads k = 1 W/(m K), c = 0.084
J/(kg K) (glass's 840 scaled down 10^4 times, as in the shipped case), floor k = 16 W/(m K).
Conduction: grainflow `heat: {model: intersection_area}`, which is LIGGGHTS' `fix
heat/gran/conduction` form (H = 4 k_i k_j / (k_i + k_j) sqrt(A), A the area of the spheres'
intersection circle; grainflow takes A = 2 pi R* delta, LIGGGHTS the exact circle, O(delta/R)
apart). dt 1.5e-5 s, gravity -9.81 m/s^2 along z, skin 0.75 mm.

Two timed phases per code: (1) fill: --fill-time s (the beads fall, land on the hot floor and
settle while heat flows); (2) run: --run-time s more (LIGGGHTS: a second `run`; grainflow:
`--restart` from the fill's checkpoint).

Physics cross-check: the beads' thermal energy sum m c T (grainflow series thermal_energy,
LIGGGHTS `f_heattransfer`, the fix's global scalar), as the heat taken up since the start,
and the mean temperature (energy / (M c)), at the ends of both phases and over the run.

Speed: particle-steps per second per phase (N x steps / loop time), the ratio grainflow /
LIGGGHTS, with load average and CPU share; grainflow's stages. Serial, one thread each.

Unless --no-record is given, a dated section is appended to bench/RESULTS.md.

Examples (from the repository root):
  /usr/bin/python3 bench/heat/heated_bed_vs_liggghts.py
  /usr/bin/python3 bench/heat/heated_bed_vs_liggghts.py --n 1000 --no-record --keep
"""

from __future__ import annotations

import argparse
import datetime as _dt
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
sys.path.append(str(ROOT))
from bench.mesh import drum_vs_liggghts as drum  # noqa: E402

ts = drum.ts
F, lscpu_model = ts.F, ts.lscpu_model

# ---------------------------------------------------------------------------------------------
# The case (identical for both codes)
# ---------------------------------------------------------------------------------------------
R_MIN, R_MAX = 0.0014, 0.0016                 # bead radii, m (uniform)
DENSITY, YOUNGS, POISSON = 2500.0, 1.0e7, 0.3  # beads; the floor has the same E, nu
RESTITUTION, FRICTION = 0.5, 0.5
K_BEAD, K_FLOOR, C_BEAD = 1.0, 16.0, 0.084     # W/(m K), W/(m K), J/(kg K)
T0, T_FLOOR = 293.0, 373.0                     # K
GRAVITY = 9.81
DT = 1.5e-5
SKIN = 0.00075
SPACING, Z0, JITTER = 0.0035, 0.002, 0.0001    # lattice, m (gap >= 0.1 mm)
SERIES_EVERY = 0.01                            # s


def lattice_beads(n: int, side: float, seed: int) -> list[tuple[float, float, float, float]]:
    """The N lowest sites of the simple cubic lattice filling the slab's footprint, each shifted
    horizontally by at most JITTER, radii uniform in [R_MIN, R_MAX]: [(x, y, z, r)]."""
    per_row = int(side / SPACING)
    rng = random.Random(seed)
    beads = []
    k = 0
    while len(beads) < n:
        for j in range(per_row):
            for i in range(per_row):
                if len(beads) == n:
                    break
                x = (i + 0.5) * side / per_row + rng.uniform(-JITTER, JITTER)
                y = (j + 0.5) * side / per_row + rng.uniform(-JITTER, JITTER)
                beads.append((x, y, Z0 + k * SPACING, rng.uniform(R_MIN, R_MAX)))
        k += 1
    return beads


def heat_capacity(beads) -> float:
    """Sum of m c over the beads, J/K."""
    return sum(DENSITY * 4.0 / 3.0 * math.pi * r ** 3 for *_, r in beads) * C_BEAD


def box(beads, side):
    top = max(z for _, _, z, _ in beads) + R_MAX + 0.005
    return (0.0, 0.0, -0.001), (side, side, top)


# ---------------------------------------------------------------------------------------------
# LIGGGHTS
# ---------------------------------------------------------------------------------------------
THERMO_RE = re.compile(r"^\s*(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s*$", re.M)


def liggghts_input(n: int, fill_steps: int, run_steps: int) -> str:
    head = drum.liggghts_head("data.bed", "the floor", SKIN, YOUNGS, POISSON, RESTITUTION,
                              FRICTION, DT, GRAVITY).replace("boundary f f f", "boundary p p f")
    return f"""\
# grainflow bench/heat/heated_bed_vs_liggghts.py: {n} beads on a floor at {F(T_FLOOR)} K
{head}
fix tc all property/global thermalConductivity peratomtype {F(K_BEAD)} {F(K_FLOOR)}
fix tca all property/global thermalCapacity peratomtype {F(C_BEAD)} {F(C_BEAD)}
fix heattransfer all heat/gran/conduction initial_temperature {F(T0)}
fix floor all wall/gran model hertz tangential history primitive type 2 zplane 0.0 temperature {F(T_FLOOR)}

fix integr all nve/sphere
thermo_style custom step atoms ke f_heattransfer
thermo {max(1, round(SERIES_EVERY / DT))}
thermo_modify lost ignore norm no

run {fill_steps}
run {run_steps}
"""


def run_liggghts(exe, beads, side, fill_steps, run_steps, workdir: Path, args) -> dict:
    res = {"code": "LIGGGHTS", "ok": False, "version": "n/a"}
    if exe is None:
        res["why"] = f"binary not found ({args.liggghts})"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    lo, hi = box(beads, side)
    (workdir / "data.bed").write_text(drum.liggghts_data(
        beads, lo, hi, script="../heat/heated_bed_vs_liggghts.py"))
    (workdir / "in.bed").write_text(liggghts_input(len(beads), fill_steps, run_steps))
    got = drum.run_liggghts_two_loops(exe, "in.bed", workdir, args, res)
    if got is None:
        return res
    log, loops = got
    res["n_end"] = loops[1]["atoms"]
    rows = {}
    for m in THERMO_RE.finditer(log):
        try:
            rows[int(m.group(1))] = dict(t=int(m.group(1)) * DT, energy=float(m.group(4)))
        except ValueError:
            pass
    res["series"] = [rows[k] for k in sorted(rows)]
    res["ok"] = True
    return res


# ---------------------------------------------------------------------------------------------
# grainflow
# ---------------------------------------------------------------------------------------------
def grainflow_case(n: int, lo, hi, end: float, checkpoint_every: float, outdir: str) -> str:
    v = drum._vec
    return f"""\
# grainflow bench/heat/heated_bed_vs_liggghts.py: {n} beads on a floor at {F(T_FLOOR)} K
name: heated_bed_vs_liggghts_{n}
dimension: 3
time: {{step: {F(DT)}, end: {F(end)}}}
domain: {{min: {v(lo)}, max: {v(hi)}, periodic: [true, true, false]}}
gravity: [0.0, 0.0, {F(-GRAVITY)}]
materials:
  beads: {{density: {F(DENSITY)}, youngs_modulus: {F(YOUNGS)}, poisson_ratio: {F(POISSON)}, thermal_conductivity: {F(K_BEAD)}, heat_capacity: {F(C_BEAD)}}}
  floor: {{density: {F(DENSITY)}, youngs_modulus: {F(YOUNGS)}, poisson_ratio: {F(POISSON)}, thermal_conductivity: {F(K_FLOOR)}}}
contacts:
  - {{between: [beads, beads], model: hertz_mindlin, restitution: {F(RESTITUTION)}, friction: {F(FRICTION)}, rolling_friction: 0.0}}
  - {{between: [beads, floor], model: hertz_mindlin, restitution: {F(RESTITUTION)}, friction: {F(FRICTION)}, rolling_friction: 0.0}}
heat: {{model: intersection_area, temperature: {F(T0)}}}
particles:
  - {{shape: sphere, material: beads, file: particles.csv}}
walls:
  - {{name: floor, plane: {{point: [0.0, 0.0, 0.0], normal: [0.0, 0.0, 1.0]}}, material: floor, temperature: {F(T_FLOOR)}}}
neighbor: {{skin: {F(SKIN)}}}
output:
  directory: {outdir}
  series: {{every: {F(SERIES_EVERY)}, quantities: [thermal_energy, temperature_mean, wall_heat_flow.floor, translational_kinetic_energy]}}
  checkpoint: {{every: {F(checkpoint_every)}}}
"""


def run_grainflow(exe, beads, side, fill_steps, run_steps, workdir: Path, args) -> dict:
    res = drum.grainflow_result(exe)
    if exe is None:
        res["why"] = f"binary not found ({args.grainflow})"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "particles.csv").write_text(
        "x,y,z,radius\n" + "".join(f"{x:.15g},{y:.15g},{z:.15g},{r:.15g}\n"
                                   for x, y, z, r in beads))
    lo, hi = box(beads, side)
    t1, t2 = fill_steps * DT, (fill_steps + run_steps) * DT
    (workdir / "fill.yaml").write_text(grainflow_case(len(beads), lo, hi, t1, t1, "fill"))
    (workdir / "run.yaml").write_text(grainflow_case(len(beads), lo, hi, t2, 0.0, "run"))
    summ = drum.run_grainflow_two_phases(exe, workdir, args, res)
    if summ is None:
        return res
    res["n_end"] = int(summ["run"].get("n_particles", 0))
    res["stages"] = {tag: s.get("stages") for tag, s in summ.items()}
    rows = {}
    for r in (drum._read_series(workdir / "fill" / "series.csv")
              + drum._read_series(workdir / "run" / "series.csv")):
        if "time" in r and "thermal_energy" in r:
            rows[round(r["time"] / DT)] = dict(t=r["time"], energy=r["thermal_energy"])
    res["series"] = [rows[k] for k in sorted(rows)]
    res["ok"] = True
    return res


# ---------------------------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------------------------
def energy_at(r: dict, t: float) -> float | None:
    rows = [s for s in r.get("series", []) if abs(s["t"] - t) < 0.5 * SERIES_EVERY]
    return rows[-1]["energy"] if rows else None


def format_cross(per, cap, times) -> str:
    head = ("| code | " + " | ".join(f"heat taken up by t = {t:.3g} s, J (mean T, K)" for t in times)
            + " |")
    out = [head, "|" + "---|" * (len(times) + 1)]
    for code in ("LIGGGHTS", "grainflow"):
        r = per.get(code)
        if not r or not r["ok"]:
            continue
        e0 = energy_at(r, 0.0)
        cells = []
        for t in times:
            e = energy_at(r, t)
            cells.append("n/a" if e is None or e0 is None
                         else f"{e - e0:.5f} ({e / cap:.2f})")
        out.append(f"| {code} | " + " | ".join(cells) + " |")
    lg, gf = per.get("LIGGGHTS"), per.get("grainflow")
    if lg and gf and lg["ok"] and gf["ok"]:
        cells = []
        for t in times:
            a, b = energy_at(lg, t), energy_at(gf, t)
            a0, b0 = energy_at(lg, 0.0), energy_at(gf, 0.0)
            cells.append("n/a" if None in (a, b, a0, b0) or a == a0
                         else f"{(b - b0) / (a - a0) - 1:+.1%}")
        out.append("| grainflow / LIGGGHTS − 1 | " + " | ".join(cells) + " |")
    return "\n".join(out)


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="See bench/heat/README.md.")
    ap.add_argument("--n", type=int, default=4000, help="number of beads (default %(default)s)")
    ap.add_argument("--side", type=float, default=0.06,
                    help="side of the periodic slab, m (default %(default)s)")
    ap.add_argument("--fill-time", type=float, default=0.3,
                    help="simulated time of the fill phase, s (default %(default)s)")
    ap.add_argument("--run-time", type=float, default=0.5,
                    help="simulated time of the run phase, s (default %(default)s)")
    ap.add_argument("--seed", type=int, default=7, help="seed of the beads (default %(default)s)")
    drum.add_peer_args(ap)
    return ap.parse_args(argv)


def main(argv=None) -> int:
    a = parse_args(argv)
    codes, gf, lig = drum.peer_codes(a)
    beads = lattice_beads(a.n, a.side, a.seed)
    cap = heat_capacity(beads)
    fill_steps, run_steps = round(a.fill_time / DT), round(a.run_time / DT)
    t1, t2 = fill_steps * DT, (fill_steps + run_steps) * DT
    print(f"N = {len(beads)} beads (sum m c = {cap:.5f} J/K), slab {a.side:g} m; fill "
          f"{fill_steps} + run {run_steps} steps; load now {os.getloadavg()[0]:.2f}", flush=True)
    root = drum.make_run_root(a.keep, "heat-bed")
    per = {}
    if "liggghts" in codes:
        per["LIGGGHTS"] = run_liggghts(lig, beads, a.side, fill_steps, run_steps,
                                       root / "liggghts", a)
    if "grainflow" in codes:
        per["grainflow"] = run_grainflow(gf, beads, a.side, fill_steps, run_steps,
                                         root / "grainflow", a)
    notes = []
    for code, r in per.items():
        if not r["ok"]:
            print(f"  {code}: n/a ({r['why']})")
            notes.append(f"{code}: n/a — {r['why']}")
            continue
        if r.get("n_end") is not None and r["n_end"] != len(beads):
            notes.append(f"{code}: LOST {len(beads) - r['n_end']} beads")
        for w in r.get("warnings", [])[:8]:
            notes.append(f"{code} warning: {w}")
    table = drum.format_table(len(beads), per)
    times = [round(t1 / 2, 6), t1, round((t1 + t2) / 2, 6), t2]
    cross = format_cross(per, cap, times)
    print("\n" + table + "\n\n" + cross)
    gfr = per.get("grainflow")
    stages = drum.stage_shares(gfr) if gfr and gfr["ok"] else {}
    if stages:
        print("\ngrainflow stages: " + drum.fmt_stages(stages))
    if not a.no_record:
        lr = per.get("LIGGGHTS", {})
        lines = [
            "", f"## heated bed (heat conduction) vs LIGGGHTS — "
            f"{_dt.datetime.now().astimezone().isoformat(timespec='seconds')}", "",
            f"- Machine: {lscpu_model()}, {os.cpu_count()} cores (`lscpu`), load average at the "
            f"end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
            f"- Codes: {per.get('grainflow', {}).get('version', 'grainflow not run')}, "
            f"{lr.get('version', 'LIGGGHTS not run')} (Debian `liggghts`); serial, 1 process / "
            "1 thread each, run one after the other (bench/heat/heated_bed_vs_liggghts.py)",
            f"- Case (mirror of cases/dem/heated_bed): slab {a.side:g} x {a.side:g} m periodic in "
            f"x, y; {len(beads)} glass beads r uniform [{R_MIN * 1e3:g}, {R_MAX * 1e3:g}] mm "
            f"(seed {a.seed}) at {T0:g} K, k {K_BEAD:g} W/(m K), c {C_BEAD:g} J/(kg K) (scaled "
            f"10^4), floor at {T_FLOOR:g} K, k {K_FLOOR:g}; Hertz-Mindlin e {RESTITUTION:g}, "
            f"mu {FRICTION:g}; conduction: LIGGGHTS `fix heat/gran/conduction` (contact_area "
            "overlap), grainflow `heat: {model: intersection_area}`; dt "
            f"{DT:g} s, skin {SKIN:g} m",
            f"- Phases: fill = the first {a.fill_time:g} s ({fill_steps} steps; beads land on "
            f"the hot floor and settle); run = {a.run_time:g} s more ({run_steps} steps); "
            "rate = N x steps / loop time; gf/LIGGGHTS > 1: grainflow faster",
        ]
        if stages:
            lines.append("- grainflow stages (summary.json; share of the stages' sum): "
                         + drum.fmt_stages(stages))
        lines += [f"- {t}" for t in notes]
        ts.append_section(Path(a.results), lines, a.note, [
            "", table, "", f"Heat taken up by the beads (sum m c T minus its start; sum m c = "
            f"{cap:.5f} J/K):", "", cross, ""])
    if not a.keep:
        shutil.rmtree(root, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
