#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Side-by-side speed of non-spherical grains: grainflow against the Debian peers.

Two comparisons, each the same physical case built for both codes by this script:

  polygons  2D convex polygons settling in a box: LAMMPS (Debian `lammps`, BODY package:
            atom_style body rounded/polygon, pair_style body/rounded/polygon, fix
            wall/body/polygon, fix nve/body) against grainflow `shape: polygon`, `dimension: 2`.
            Regular 5-, 6- and 7-gons (cycled), equal-area radius R uniform in [1.6, 2.4] mm,
            random angles, on a square lattice (spacing > 2 x the largest circumradius) with a
            small random velocity kick; both codes read the same positions, angles, radii and
            velocities (LAMMPS: a data file with a Bodies section; grainflow: one CSV per vertex
            count). Density 2600 kg/m^3, depth 0.01 m, dt 5e-6 s, gravity -y.
  rods      3D rods of aspect ratio 4 settling in a 12 x 12 cm box: LIGGGHTS-PUBLIC 3.8 (Debian
            `liggghts`), each rod a rigid chain of overlapping spheres (fix
            particletemplate/multisphere + fix multisphere; --rod-spheres spheres of radius r
            evenly spaced on the axis, the end ones centred on the cap centres), against
            grainflow `shape: spherocylinder` (cap radius r = 1.5 mm, aspect_ratio 4). Both insert
            N rods at random positions and orientations in the same region (each code its own
            random insertion: LIGGGHTS cannot place multisphere bodies from a list), POM-like
            material (1395 kg/m^3, E 1e7 Pa, nu 0.3, e 0.7, mu 0.3), Hertz-Mindlin with
            tangential history on both sides, dt 1e-5 s.

For each case and code: (1) settle: the first --*-settle-time seconds from the initial state,
(2) dense: --*-dense-steps further steps from the settled state (LAMMPS/LIGGGHTS: a second `run`
in the same input; grainflow: `--restart` from the checkpoint at the end of (1)). The rate is
grains x steps / loop time (rods and polygons counted, not the spheres of a chain), with the
load average during the run and the CPU share each process got (the machine is shared), as
bench/terrain_settling/run.py reports them (its helpers are reused). Unless --no-record is given
a dated section is appended to bench/RESULTS.md.

Contact models differ (see bench/shapes/README.md): grainflow's polygons push with the overlap
area (F = k A / l_c), LAMMPS's rounded polygons with vertex-edge springs on the rounded outline
(F = k_n delta per contact point); the script sets k_n so that a face-to-face contact of two
mean grains has the same stiffness in both, and the LAMMPS damping from the same restitution.

Examples (from the repository root):
  /usr/bin/python3 bench/shapes/peers.py
  /usr/bin/python3 bench/shapes/peers.py --cases polygons --polygon-sizes 500 --no-record
  /usr/bin/python3 bench/shapes/peers.py --cases rods --rod-spheres 5 --keep
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
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCH = HERE.parent
ROOT = BENCH.parent

# Measurement helpers (time -v, load sampling, CPU share) shared with the sphere benchmark:
# bench/ is a package, the scripts run as files, so its root goes on the path.
sys.path.append(str(ROOT))
from bench.terrain_settling import run as ts  # noqa: E402

F, run_timed, lscpu_model, _tail = ts.F, ts.run_timed, ts.lscpu_model, ts._tail

# ---------------------------------------------------------------------------------------------
# Case 1: 2D polygons
# ---------------------------------------------------------------------------------------------
P_DENSITY = 2600.0        # kg/m^3
P_DEPTH = 0.01            # m, depth of the grains (grainflow domain.thickness)
P_R_MIN, P_R_MAX = 0.0016, 0.0024   # equal-area radius range, m
P_VERTS = (5, 6, 7)       # vertex counts, cycled over the grains
P_STIFF = 2.0e5           # grainflow hooke stiffness = 2D modulus k, N/m (F = k A / l_c)
P_E = 0.3                 # restitution
P_MU = 0.5                # friction
P_DT = 5.0e-6             # s
P_SKIN = 0.001            # m, neighbour skin (both codes)
P_ROUND = 0.1             # LAMMPS rounding radius, fraction of each grain's equal-area radius
P_JITTER = 0.05           # m/s, uniform random initial velocity per component


def circumradius(n: int, r_eq: float) -> float:
    """Circumradius of the regular n-gon of area pi r_eq^2."""
    return r_eq * math.sqrt(2 * math.pi / (n * math.sin(2 * math.pi / n)))


def polar_moment(n: int, r_eq: float) -> float:
    """J = integral |x|^2 dA of the regular n-gon of area pi r_eq^2 about its centre, m^4."""
    rc = circumradius(n, r_eq)
    return math.pi * r_eq ** 2 * rc ** 2 * (1 + 2 * math.cos(math.pi / n) ** 2) / 6


def zeta(e: float) -> float:
    """Damping ratio of a linear spring-dashpot with restitution e."""
    le = math.log(e)
    return -le / math.sqrt(math.pi ** 2 + le * le)


def polygon_grains(n_target: int, seed: int):
    """Square lattice of grains (n, R, x, y, angle, vx, vy) and the box (width, lattice top)."""
    rng = random.Random(seed)
    spacing = 2 * circumradius(min(P_VERTS), P_R_MAX) * 1.05
    nx = max(8, round(math.sqrt(2 * n_target)))
    ny = math.ceil(n_target / nx)
    grains = []
    for k in range(n_target):
        i, j = k % nx, k // nx
        grains.append(dict(n=P_VERTS[k % len(P_VERTS)], R=rng.uniform(P_R_MIN, P_R_MAX),
                           x=(i + 0.5) * spacing, y=(j + 0.5) * spacing,
                           a=rng.uniform(0, 2 * math.pi),
                           vx=rng.uniform(-P_JITTER, P_JITTER), vy=rng.uniform(-P_JITTER, P_JITTER)))
    return grains, nx * spacing, ny * spacing


def polygon_matching():
    """LAMMPS k_n, wall k_n and c_n matched to grainflow's k for a face contact of mean grains.

    grainflow: F = k A / l_c, A = w delta for two parallel faces (w: the shorter face, here the
    edge of the mean hexagon), l_c = R_i + R_j (grain-grain) or R_i (wall): stiffness k w / l_c.
    LAMMPS: two vertex-edge contacts carry a flat face-face contact: stiffness 2 k_n.
    """
    r = 0.5 * (P_R_MIN + P_R_MAX)
    w = 2 * circumradius(6, r) * math.sin(math.pi / 6)
    k_pair = P_STIFF * w / (2 * r)
    k_wall = P_STIFF * w / r
    m = P_DENSITY * P_DEPTH * math.pi * r * r
    z = zeta(P_E)
    kn, kn_wall = k_pair / 2, k_wall / 2
    # Damping per contact point, two points per face: c = zeta sqrt(m_eff 2 k_n) per point.
    cn = z * math.sqrt(0.5 * m * 2 * kn)
    cn_wall = z * math.sqrt(m * 2 * kn_wall)
    return dict(r=r, w=w, k_pair=k_pair, k_wall=k_wall, kn=kn, kn_wall=kn_wall, cn=cn,
                cn_wall=cn_wall, m=m, t_c=math.pi * math.sqrt(0.5 * m / k_pair))


def lammps_polygon_inputs(grains, width, top, settle_steps, dense_steps, match) -> tuple[str, str]:
    height = 1.5 * top + 0.02
    lines = ["grainflow bench/shapes/peers.py: regular polygons, rounded corners", "",
             f"{len(grains)} atoms", f"{len(grains)} bodies", "1 atom types",
             f"0.0 {F(width)} xlo xhi", f"0.0 {F(height)} ylo yhi",
             f"{F(-P_DEPTH / 2)} {F(P_DEPTH / 2)} zlo zhi", "", "Atoms", ""]
    for k, g in enumerate(grains):
        m = P_DENSITY * P_DEPTH * math.pi * g["R"] ** 2
        lines.append(f"{k + 1} 1 1 {m:.12g} {g['x']:.12g} {g['y']:.12g} 0.0")
    lines += ["", "Velocities", ""]
    for k, g in enumerate(grains):
        lines.append(f"{k + 1} {g['vx']:.12g} {g['vy']:.12g} 0.0 0.0 0.0 0.0")
    lines += ["", "Bodies", ""]
    for k, g in enumerate(grains):
        n, r = g["n"], g["R"]
        rc = circumradius(n, r)
        rr = P_ROUND * r
        # Core polygon inset by the rounding radius: its rounded outline has the same edges as
        # the grainflow polygon (only the corners are rounded).
        s = (rc * math.cos(math.pi / n) - rr) / (rc * math.cos(math.pi / n))
        izz = P_DENSITY * P_DEPTH * polar_moment(n, r)
        lines.append(f"{k + 1} 1 {6 + 3 * n + 1}")
        lines.append(str(n))
        lines.append(f"{izz / 2:.12g} {izz / 2:.12g} {izz:.12g} 0 0 0")
        for v in range(n):
            a = g["a"] + 2 * math.pi * v / n
            lines.append(f"{s * rc * math.cos(a):.12g} {s * rc * math.sin(a):.12g} 0")
        lines.append(f"{2 * rr:.12g}")
    data = "\n".join(lines) + "\n"
    inp = f"""\
# grainflow bench/shapes/peers.py: {len(grains)} rounded polygons settling in a box
units si
dimension 2
boundary f f p
atom_style body rounded/polygon 1 8
atom_modify map array
read_data data.polygons
pair_style body/rounded/polygon {F(match['cn'])} {F(match['cn'])} {F(P_MU)} 1.0 0.0
pair_coeff * * {F(match['kn'])} 0.0
comm_modify vel yes
neighbor {F(P_SKIN)} bin
neigh_modify every 1 delay 0 check yes
timestep {F(P_DT)}
fix 1 all nve/body
fix 2 all enforce2d
fix g all gravity 9.81 vector 0.0 -1.0 0.0
fix wx all wall/body/polygon {F(match['kn_wall'])} {F(match['cn_wall'])} {F(match['cn_wall'])} xplane 0.0 {F(width)}
fix wy all wall/body/polygon {F(match['kn_wall'])} {F(match['cn_wall'])} {F(match['cn_wall'])} yplane 0.0 NULL
compute ymax all reduce max y
compute ymean all reduce ave y
thermo_style custom step atoms ke c_ymax c_ymean
thermo {max(1, settle_steps // 10)}
thermo_modify lost ignore norm no
run {settle_steps}
run {dense_steps}
"""
    return data, inp


def grainflow_polygon_case(grains, width, top, end_time, ckpt_every, outdir) -> tuple[str, dict]:
    height = 1.5 * top + 0.02
    csvs, groups = {}, []
    for n in P_VERTS:
        rows = ["x,y,vx,vy,angle,radius"]
        for g in grains:
            if g["n"] == n:
                rows.append(f"{g['x']:.12g},{g['y']:.12g},{g['vx']:.12g},{g['vy']:.12g},"
                            f"{g['a']:.12g},{g['R']:.12g}")
        if len(rows) > 1:
            csvs[f"polygons_{n}.csv"] = "\n".join(rows) + "\n"
            groups.append(f"  - {{shape: polygon, polygon: {{regular: {n}}}, material: stone, "
                          f"file: polygons_{n}.csv}}")
    case = f"""\
# grainflow bench/shapes/peers.py: {len(grains)} regular polygons settling in a box
name: peers_polygons_{len(grains)}
dimension: 2
time: {{step: {F(P_DT)}, end: {F(end_time)}}}
domain: {{min: [0.0, 0.0], max: [{F(width)}, {F(height)}], thickness: {F(P_DEPTH)}}}
gravity: [0.0, -9.81]
materials:
  stone: {{density: {F(P_DENSITY)}, youngs_modulus: 1.0e8, poisson_ratio: 0.3}}
contacts:
  - {{between: [stone, stone], model: hooke, stiffness: {F(P_STIFF)}, restitution: {F(P_E)}, friction: {F(P_MU)}}}
particles:
{chr(10).join(groups)}
walls:
  - {{name: box, box: {{min: [0.0, 0.0], max: [{F(width)}, {F(height)}], open: [ymax]}}, material: stone}}
neighbor: {{skin: {F(P_SKIN)}}}
output:
  directory: {outdir}
  series: {{every: {F(end_time)}, quantities: [kinetic_energy, max_z, mean_z, contact_count]}}
  checkpoint: {{every: {F(ckpt_every)}}}
"""
    return case, csvs


# ---------------------------------------------------------------------------------------------
# Case 2: rods
# ---------------------------------------------------------------------------------------------
R_RADIUS = 0.0015         # cap radius / chain sphere radius, m
R_ASPECT = 4.0            # (L + 2r) / 2r
R_DENSITY = 1395.0
R_YOUNGS, R_POISSON, R_E, R_MU = 1.0e7, 0.3, 0.7, 0.3
R_DT = 1.0e-5
R_BOX = 0.12              # m, square box side
R_FILL = (0.01, 0.40)     # m, insertion region height range
R_HEIGHT = 0.6            # m, domain height
R_SKIN = 0.00075          # m, neighbour skin (both codes)


def rod_half_length() -> float:
    return R_RADIUS * (R_ASPECT - 1)  # L/2 = r (alpha - 1)


def liggghts_rod_input(n, n_spheres, settle_steps, dense_steps, seed) -> str:
    h = rod_half_length()
    zs = [(-h + 2 * h * k / (n_spheres - 1)) for k in range(n_spheres)]
    spheres = "  ".join(f"0.0 0.0 {F(z)} {F(R_RADIUS)}" for z in zs)
    primes = ts._primes_above(10000 + 7919 * (seed % 1000), 4)
    walls = "\n".join(
        f"fix {name} all wall/gran model hertz tangential history primitive type 1 {plane} {F(pos)}"
        for name, plane, pos in [("wx0", "xplane", 0.0), ("wx1", "xplane", R_BOX),
                                 ("wy0", "yplane", 0.0), ("wy1", "yplane", R_BOX),
                                 ("wz0", "zplane", 0.0)])
    return f"""\
# grainflow bench/shapes/peers.py: {n} rods (aspect ratio {R_ASPECT:g}) as chains of {n_spheres} spheres
{ts.LIGGGHTS_PREAMBLE}region domain block 0.0 {F(R_BOX)} 0.0 {F(R_BOX)} 0.0 {F(R_HEIGHT)} units box
create_box 1 domain
neighbor {F(R_SKIN)} bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype {F(R_YOUNGS)}
fix m2 all property/global poissonsRatio peratomtype {F(R_POISSON)}
fix m3 all property/global coefficientRestitution peratomtypepair 1 {F(R_E)}
fix m4 all property/global coefficientFriction peratomtypepair 1 {F(R_MU)}
pair_style gran model hertz tangential history
pair_coeff * *
timestep {F(R_DT)}
fix gravi all gravity 9.81 vector 0.0 0.0 -1.0
{walls}
fix pts1 all particletemplate/multisphere {primes[0]} atom_type 1 density constant {F(R_DENSITY)} nspheres {n_spheres} ntry 1000000 spheres {spheres} type 1
fix pdd1 all particledistribution/discrete {primes[1]} 1 pts1 1.0
region ins block 0.0 {F(R_BOX)} 0.0 {F(R_BOX)} {F(R_FILL[0])} {F(R_FILL[1])} units box
fix ins all insert/pack seed {primes[2]} distributiontemplate pdd1 vel constant 0.0 0.0 0.0 orientation random insert_every once overlapcheck yes all_in yes particles_in_region {n} region ins ntry_mc 10000
fix ms all multisphere
compute zmax all reduce max z
compute zmean all reduce ave z
thermo_style custom step atoms ke c_zmax c_zmean
thermo {max(1, settle_steps // 10)}
thermo_modify lost ignore norm no
run {settle_steps}
run {dense_steps}
"""


def grainflow_rod_case(n, end_time, ckpt_every, outdir, seed) -> str:
    return f"""\
# grainflow bench/shapes/peers.py: {n} spherocylinders (aspect ratio {R_ASPECT:g}) settling in a box
name: peers_rods_{n}
dimension: 3
time: {{step: {F(R_DT)}, end: {F(end_time)}}}
domain: {{min: [0.0, 0.0, 0.0], max: [{F(R_BOX)}, {F(R_BOX)}, {F(R_HEIGHT)}]}}
gravity: [0.0, 0.0, -9.81]
materials:
  pom: {{density: {F(R_DENSITY)}, youngs_modulus: {F(R_YOUNGS)}, poisson_ratio: {F(R_POISSON)}}}
contacts:
  - {{between: [pom, pom], model: hertz_mindlin, restitution: {F(R_E)}, friction: {F(R_MU)}, rolling_friction: 0.0}}
particles:
  - shape: spherocylinder
    radius: {F(R_RADIUS)}
    aspect_ratio: {F(R_ASPECT)}
    material: pom
    fill: {{box: {{min: [0.0, 0.0, {F(R_FILL[0])}], max: [{F(R_BOX)}, {F(R_BOX)}, {F(R_FILL[1])}]}}, lattice: random, count: {n}, seed: {seed}, orientation: random}}
walls:
  - {{name: box, box: {{min: [0.0, 0.0, 0.0], max: [{F(R_BOX)}, {F(R_BOX)}, {F(R_HEIGHT)}], open: [zmax]}}, material: pom}}
neighbor: {{skin: {F(R_SKIN)}}}
output:
  directory: {outdir}
  series: {{every: {F(end_time)}, quantities: [kinetic_energy, max_z, mean_z, contact_count]}}
  checkpoint: {{every: {F(ckpt_every)}}}
"""


# ---------------------------------------------------------------------------------------------
# Running
# ---------------------------------------------------------------------------------------------
LOOP_RE = re.compile(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")
NEIGH_RE = re.compile(r"Ave neighs/atom = (\S+)")


def thermo_rows(text: str) -> list[list[float]]:
    """Numeric thermo rows `step atoms ke max mean` of a LAMMPS/LIGGGHTS log."""
    rows = []
    for m in re.finditer(r"^\s*(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", text, re.M):
        try:
            rows.append([float(x) for x in m.groups()])
        except ValueError:
            pass
    return rows


def run_peer(exe, cmd_args, workdir: Path, files: dict, settle_steps, timeout, peer) -> dict:
    """One LAMMPS/LIGGGHTS process with two `run`s; per-phase loop times from its log."""
    workdir.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (workdir / name).write_text(text)
    # No `-screen none`: LIGGGHTS 3.8 crashes in Region::reset_random (fprintf to a null screen).
    proc = run_timed([exe, *cmd_args, "-log", "log.txt"], workdir, peer, timeout)
    log = (workdir / "log.txt").read_text(errors="replace") if (workdir / "log.txt").exists() else ""
    loops = [dict(seconds=float(m.group(1)), steps=int(m.group(3)), atoms=int(m.group(4)))
             for m in LOOP_RE.finditer(log)]
    res = {"code": peer, "ok": proc.rc == 0 and len(loops) >= 2, "proc": proc}
    if not res["ok"]:
        err = [l for l in (log + proc.stdout + proc.stderr).splitlines() if "ERROR" in l]
        res["why"] = (f"exit {proc.rc}, {len(loops)} loop(s) in log; "
                      + (" | ".join(err[:2]) if err else _tail(proc.stdout + proc.stderr)))
        return res
    res["phases"] = ts.peer_phases(proc, loops, ("settle", "dense"))
    res["atoms"] = loops[1]["atoms"]
    res["neighs"] = [float(x) for x in NEIGH_RE.findall(log)]
    rows = thermo_rows(log)
    at = [r for r in rows if int(r[0]) == settle_steps]
    if at:
        res["state"] = {"ke": at[0][2], "max": at[0][3], "mean": at[0][4]}
    m = re.search(r"inserted (\d+) particle templates", log)
    res["inserted"] = int(m.group(1)) if m else None
    m = re.search(r"mass = (\S+), radius of bounding sphere", log)
    res["template_mass"] = float(m.group(1).rstrip(",")) if m else None
    return res


def run_gf(exe, workdir: Path, n_settle: int, n_dense: int, dt: float, make_case, timeout) -> dict:
    """grainflow settle run (checkpoint at its end), then the dense run restarted from it.

    make_case(end_time, checkpoint_every, outdir) -> (case text, {extra file: text})."""
    res = {"code": "grainflow", "ok": False}
    if exe is None:
        res["why"] = "binary not found"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    t1, t2 = n_settle * dt, (n_settle + n_dense) * dt
    for tag, end, ck in (("settle", t1, t1), ("dense", t2, 0.0)):
        text, extra = make_case(end, ck, tag)
        (workdir / f"{tag}.yaml").write_text(text)
        for name, body in extra.items():
            (workdir / name).write_text(body)
    phases, summ = {}, {}
    for tag in ("settle", "dense"):
        cmd = [exe, "run", f"{tag}.yaml", "--output", tag, "--overwrite", "--threads", "1"]
        if tag == "dense":
            ck = ts.last_checkpoint(workdir / "settle")
            if ck is None:
                res["why"] = "settle run wrote no checkpoint"
                return res
            cmd += ["--restart", str(ck)]
        proc = run_timed(cmd, workdir, f"grainflow_{tag}", timeout)
        sj = workdir / tag / "summary.json"
        if proc.rc != 0 or not sj.exists():
            res["why"] = f"{tag} run: exit {proc.rc}: " + _tail(proc.stderr or proc.stdout)
            return res
        s = json.loads(sj.read_text())
        summ[tag] = s
        phases[tag] = {"steps": int(s["steps"]), "seconds": float(s["loop_seconds"]),
                       "load": proc.load, "cpu_share": proc.cpu_share,
                       "loop_fraction": float(s["loop_seconds"]) / max(proc.wall, 1e-9)}
    res.update(ok=True, phases=phases, n=int(summ["settle"]["n_particles"]),
               stages={k: v.get("stages") for k, v in summ.items()},
               threads=summ["dense"].get("threads"), program=summ["settle"].get("program"))
    last = ts._last_series_row(workdir / "settle" / "series.csv")
    if last:
        res["state"] = {"ke": last.get("kinetic_energy"), "max": last.get("max_z"),
                        "mean": last.get("mean_z"), "contacts": last.get("contact_count")}
    return res


def rate(n, ph):
    return n * ph["steps"] / ph["seconds"] if ph["seconds"] > 0 else float("nan")


def table_rows(case_name, n, per: dict, peer: str) -> list[dict]:
    out = []
    for phase in ("settle", "dense"):
        ref = per.get(peer)
        ref_rate = rate(n, ref["phases"][phase]) if ref and ref["ok"] else None
        for code in (peer, "grainflow"):
            r = per.get(code)
            row = {"case": case_name, "N": n, "code": code, "phase": phase, "steps": None,
                   "seconds": None, "rate": None, "ratio": None, "load": None, "share": None}
            if r and r["ok"]:
                ph = r["phases"][phase]
                row.update(steps=ph["steps"], seconds=ph["seconds"], rate=rate(n, ph),
                           load=ph["load"], share=ph["cpu_share"])
                if code == peer:
                    row["ratio"] = 1.0
                elif ref_rate:
                    row["ratio"] = row["rate"] / ref_rate
            out.append(row)
    return out


def format_table(rows) -> str:
    head = ("| case | N (grains) | code | phase | steps | loop s | grain-steps/s | gf/peer | "
            "load (start/mean/max) | CPU share |")
    out = [head, "|" + "---|" * head.count(" | ") + "---|"]
    for r in rows:
        ld = r["load"]
        out.append("| " + " | ".join([
            r["case"], str(r["N"]), r["code"], r["phase"],
            str(r["steps"]) if r["steps"] else "n/a",
            f"{r['seconds']:.2f}" if r["seconds"] else "n/a",
            f"{r['rate']:.3g}" if r["rate"] else "n/a",
            f"{r['ratio']:.2f}" if r["ratio"] else "n/a",
            f"{ld['start']:.2f}/{ld['mean']:.2f}/{ld['max']:.2f}" if ld else "n/a",
            f"{r['share']:.2f}" if r["share"] else "n/a"]) + " |")
    return "\n".join(out)


def fmt_state(r: dict, unit_h: str) -> str:
    s = r.get("state")
    if not s:
        return "state n/a"
    text = (f"KE {s['ke']:.2e} J, max {unit_h} {s['max']:.4f} m, mean {unit_h} {s['mean']:.4f} m")
    if s.get("contacts") is not None:
        text += f", {s['contacts']:.0f} contacts"
    return text


# ---------------------------------------------------------------------------------------------
# Driver
# ---------------------------------------------------------------------------------------------
def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="See bench/shapes/README.md.")
    ap.add_argument("--cases", default="polygons,rods", help="polygons, rods or both (default %(default)s)")
    ap.add_argument("--polygon-sizes", default="500,2000", help="polygon counts (default %(default)s)")
    ap.add_argument("--polygon-settle-time", type=float, default=0.15,
                    help="simulated settling time of the polygons, s (default %(default)s)")
    ap.add_argument("--polygon-dense-steps", type=int, default=5000)
    ap.add_argument("--rod-sizes", default="2000", help="rod counts (default %(default)s)")
    ap.add_argument("--rod-spheres", type=int, default=7,
                    help="spheres per LIGGGHTS rod (default %(default)s: spacing r)")
    ap.add_argument("--rod-settle-time", type=float, default=0.3,
                    help="simulated settling time of the rods, s (default %(default)s)")
    ap.add_argument("--rod-dense-steps", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--grainflow", default=str(ROOT / "build" / "release" / "grainflow"))
    ap.add_argument("--lammps", default="/usr/bin/lmp")
    ap.add_argument("--liggghts", default="/usr/bin/liggghts")
    ts.add_run_args(ap)
    return ap.parse_args(argv)


def main(argv=None) -> int:
    a = parse_args(argv)
    cases = {c.strip() for c in a.cases.split(",")}
    gf = ts.resolve_exe(a.grainflow)
    lmp, lig = ts.resolve_exe(a.lammps), ts.resolve_exe(a.liggghts)
    stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    root = (BENCH / "runs" / f"shapes-peers-{stamp}") if a.keep else Path(
        tempfile.mkdtemp(prefix="gf-shapes-"))
    root.mkdir(parents=True, exist_ok=True)
    print(f"run folders: {root}; grainflow {gf}", flush=True)
    rows, notes = [], []

    if "polygons" in cases:
        match = polygon_matching()
        print(f"polygons: k {P_STIFF:g} N/m -> face stiffness {match['k_pair']:.3g} N/m "
              f"(wall {match['k_wall']:.3g}); LAMMPS k_n {match['kn']:.3g}, wall {match['kn_wall']:.3g}, "
              f"c_n {match['cn']:.3g}, wall {match['cn_wall']:.3g} N s/m; "
              f"contact time {match['t_c']:.3g} s = {match['t_c'] / P_DT:.0f} dt", flush=True)
        notes.append(
            f"polygons: regular 5/6/7-gons, R uniform [{P_R_MIN * 1e3:g}, {P_R_MAX * 1e3:g}] mm, "
            f"{P_DENSITY:g} kg/m^3, depth {P_DEPTH:g} m, dt {P_DT:g} s, skin {P_SKIN:g} m, kick "
            f"+-{P_JITTER:g} m/s; grainflow hooke k {P_STIFF:g} N/m (face stiffness of mean grains "
            f"{match['k_pair']:.3g} N/m, wall {match['k_wall']:.3g}), e {P_E:g}, mu {P_MU:g}; LAMMPS "
            f"k_n {match['kn']:.3g} N/m per contact point (wall {match['kn_wall']:.3g}), c_n = c_t "
            f"{match['cn']:.3g} N s/m (wall {match['cn_wall']:.3g}), mu {P_MU:g}, delta_ua 1, "
            f"no cohesion, rounding radius {P_ROUND:g} R (core inset so the edges coincide); "
            f"face contact time {match['t_c']:.3g} s = {match['t_c'] / P_DT:.0f} dt; settle "
            f"{a.polygon_settle_time:g} s from the lattice, dense {a.polygon_dense_steps} steps")
        for n in [int(float(s)) for s in a.polygon_sizes.split(",") if s.strip()]:
            grains, width, top = polygon_grains(n, a.seed)
            n_settle = round(a.polygon_settle_time / P_DT)
            print(f"\npolygons N = {n}: box {width:.3f} m wide, lattice top {top:.3f} m, "
                  f"settle {n_settle} + dense {a.polygon_dense_steps} steps, load "
                  f"{os.getloadavg()[0]:.2f}", flush=True)
            per = {}
            if lmp:
                data, inp = lammps_polygon_inputs(grains, width, top, n_settle,
                                                  a.polygon_dense_steps, match)
                per["LAMMPS"] = run_peer(lmp, ["-in", "in.polygons"], root / f"poly{n}" / "lammps",
                                         {"data.polygons": data, "in.polygons": inp}, n_settle,
                                         a.timeout, "LAMMPS")
            else:
                per["LAMMPS"] = {"ok": False, "why": f"{a.lammps} not found"}
            per["grainflow"] = run_gf(
                gf, root / f"poly{n}" / "grainflow", n_settle, a.polygon_dense_steps, P_DT,
                lambda end, ck, out: grainflow_polygon_case(grains, width, top, end, ck, out),
                a.timeout)
            for code, r in per.items():
                print(f"  {code}: " + (fmt_state(r, "y") if r["ok"] else f"n/a ({r['why']})"),
                      flush=True)
                if r["ok"]:
                    extra = ""
                    if r.get("neighs"):
                        extra = f"; {r['neighs'][-1]:.2f} neighbours/atom at the end"
                    notes.append(f"polygons N {n} {code}: after settling {fmt_state(r, 'y')}{extra}")
                else:
                    notes.append(f"polygons N {n} {code}: n/a — {r['why']}")
            rows += table_rows("polygons", n, per, "LAMMPS")

    if "rods" in cases:
        notes.append(
            f"rods: cap radius {R_RADIUS * 1e3:g} mm, aspect ratio {R_ASPECT:g} (length "
            f"{2 * R_RADIUS * R_ASPECT * 1e3:g} mm), {R_DENSITY:g} kg/m^3, E {R_YOUNGS:g} Pa, nu "
            f"{R_POISSON:g}, e {R_E:g}, mu {R_MU:g}, Hertz-Mindlin with tangential history; box "
            f"{R_BOX:g} x {R_BOX:g} m (5 walls), random insertion in z [{R_FILL[0]:g}, {R_FILL[1]:g}] m "
            f"at rest; dt {R_DT:g} s, skin {R_SKIN:g} m; LIGGGHTS rods = {a.rod_spheres} spheres "
            f"of radius r spaced {2 * rod_half_length() / (a.rod_spheres - 1) * 1e3:.3g} mm "
            f"(fix multisphere); settle {a.rod_settle_time:g} s, dense {a.rod_dense_steps} steps")
        for n in [int(float(s)) for s in a.rod_sizes.split(",") if s.strip()]:
            n_settle = round(a.rod_settle_time / R_DT)
            print(f"\nrods N = {n}: settle {n_settle} + dense {a.rod_dense_steps} steps, "
                  f"LIGGGHTS chains of {a.rod_spheres} spheres, load {os.getloadavg()[0]:.2f}",
                  flush=True)
            per = {}
            if lig:
                inp = liggghts_rod_input(n, a.rod_spheres, n_settle, a.rod_dense_steps, a.seed)
                per["LIGGGHTS"] = run_peer(lig, ["-in", "in.rods"], root / f"rods{n}" / "liggghts",
                                           {"in.rods": inp}, n_settle, a.timeout, "LIGGGHTS")
                r = per["LIGGGHTS"]
                if r["ok"] and r.get("inserted") not in (None, n):
                    r["ok"], r["why"] = False, f"inserted only {r['inserted']} of {n} rods"
            else:
                per["LIGGGHTS"] = {"ok": False, "why": f"{a.liggghts} not found"}
            per["grainflow"] = run_gf(
                gf, root / f"rods{n}" / "grainflow", n_settle, a.rod_dense_steps, R_DT,
                lambda end, ck, out: (grainflow_rod_case(n, end, ck, out, a.seed), {}), a.timeout)
            for code, r in per.items():
                print(f"  {code}: " + (fmt_state(r, "z") if r["ok"] else f"n/a ({r['why']})"),
                      flush=True)
                if r["ok"]:
                    extra = ""
                    if code == "LIGGGHTS":
                        extra = (f"; {r['atoms']} spheres, rod mass {r.get('template_mass') or 0:.4g} kg "
                                 f"(spherocylinder {R_DENSITY * math.pi * R_RADIUS ** 2 * (2 * rod_half_length() + 4 / 3 * R_RADIUS):.4g} kg)")
                        if r.get("neighs"):
                            extra += f", {r['neighs'][-1]:.2f} neighbours/sphere at the end"
                    notes.append(f"rods N {n} {code}: after settling {fmt_state(r, 'z')}{extra}")
                else:
                    notes.append(f"rods N {n} {code}: n/a — {r['why']}")
            rows += table_rows(f"rods ({a.rod_spheres}-sphere chains)", n, per, "LIGGGHTS")

    table = format_table(rows)
    print("\n" + table)
    if not a.no_record:
        built = (_dt.datetime.fromtimestamp(Path(gf).stat().st_mtime).strftime("%Y-%m-%d %H:%M")
                 if gf else "n/a")
        lines = ["", f"## shapes vs peers — {_dt.datetime.now().astimezone().isoformat(timespec='seconds')}",
                 "",
                 f"- Machine: {lscpu_model()}, {os.cpu_count()} cores (`lscpu`), load average at "
                 f"the end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
                 f"- Codes: grainflow ({gf}, binary of {built}), LAMMPS 29 Sep 2021 update 2 "
                 f"(Debian `lammps`, BODY package), LIGGGHTS-PUBLIC 3.8.0 (Debian `liggghts`); "
                 f"serial, 1 process / 1 thread each, run one after the other; double precision "
                 f"(bench/shapes/peers.py)",
                 "- Rate: grains x steps / loop time, counting polygons and rods (not the spheres "
                 "of a chain); gf/peer > 1: grainflow faster"]
        lines += [f"- {t}" for t in notes]
        ts.append_section(Path(a.results), lines, a.note, ["", table, ""])
    if not a.keep:
        shutil.rmtree(root, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
