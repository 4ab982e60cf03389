#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Side-by-side benchmark of homogeneous simple shear between Lees-Edwards images: grainflow vs LAMMPS.

The case is cases/rheology/lees_edwards_spheres at other volume fractions: smooth (frictionless)
inelastic spheres, d = 5.3 mm, rho = 1395 kg/m^3, linear spring k_n = 6e5 N/m with a viscous
dashpot clamped so that the normal force never pulls (restitution 0.7), no gravity, in a
0.072 x 0.048 x 0.048 m box periodic in x, y and z, sheared at 100 1/s (flow x, gradient z) by
Lees-Edwards images: the images along z slide along x at rate x L_z. No walls: the whole box is
bulk.

Both codes start from the same state, written by this script for each volume fraction and
repeat (seed = --seed + repeat): the N = round(phi V / V_grain) grains on randomly chosen sites
of a simple cubic lattice commensurate with the box (spacing >= 1.005 d), with Gaussian velocity
fluctuations of --v-rms m/s per component (zero mean) on top of the mean flow
u_x = rate (z - z_mid).

  grainflow  particles.csv (x, y, z, vx, vy, vz) + a case with `model: hooke, stiffness: 6e5,
             restitution: 0.7, friction: 0`, `shear: {rate, boundary: lees_edwards,
             initial_profile: false}` (the CSV already holds the mean flow) and
             `analysis: {rheology: {every, bins: 16}}`; run with `--threads 1`.
  LAMMPS     data file (atom_style sphere: id type diameter density x y z, Velocities) in a
             triclinic box with xz tilt 0; pair_style gran/hooke k_n 0 gamma_n 0 0 0
             limit_damping (no tangential force, xmu 0; limit_damping clamps the normal force at
             0 as grainflow does); fix nve/sphere; fix deform 1 xz erate <rate> remap v flip yes;
             comm_modify vel yes; the neighbour skin that `grainflow check` prints, neigh_modify
             delay 0 every 1 check yes; plain serial `lmp -in`.

Damping: both codes use F_n = max(0, k_n delta + c v_approach), c = 2 zeta sqrt(m* k_n),
m* = m_i m_j / (m_i + m_j). With the clamp the grains separate when the force reaches zero, before
the overlap closes; the restitution of that collision is, in closed form (omega_0 = sqrt(k_n/m*),
omega = omega_0 sqrt(1 - zeta^2), b = zeta / sqrt(1 - zeta^2)),

    e(zeta) = -exp(-b omega t*) (cos(omega t*) - b sin(omega t*)),
    omega t* = pi - atan2(2 zeta sqrt(1 - zeta^2), 1 - 2 zeta^2),

which the script inverts for e = 0.7 (zeta = 0.1222; grainflow inverts the same collision
numerically). LAMMPS' damping force is m* gamma_n v_n, so gamma_n = 2 zeta sqrt(k_n / m*)
(2.57e4 1/s for equal grains). A head-on collision of two grains at the benchmark's time step
in both codes checks this: the realised restitutions are printed and recorded.

What is timed: the time loop only, N x steps / loop seconds = particle-steps/s: grainflow's
`loop_seconds` from summary.json (the loop without its output stage, which here is only the
rheology sampling), LAMMPS' "Loop time of X on 1 procs for N steps" (everything in the loop,
sampling included). Each phi runs --repeats times (one seed each), LAMMPS then grainflow, with the
load average during each run and the CPU share each process got (helpers of
bench/terrain_settling/run.py, imported from the package bench/).

Physics cross-check, so that the timing compares the same physics: both codes sample every
--sample-strain of strain (the same steps) and the script averages over the same strain window
(--window-start to the end):
  T      granular temperature <v'.v'>/3, v' = v - mean velocity of the grain's layer (16 layers
         along z), with the 1/(1 - 1/n) correction for a mean taken from the n grains themselves:
         grainflow rheology.csv `granular_temperature` (per layer); LAMMPS compute temp/chunk
         (com yes) over 16 layers given by an atom-style variable of the unwrapped z, its KE
         tensor sum_i m v'_a v'_b times N / (N - 16), / (3 N m) (no Boltzmann constant
         involved). Not compute temp/profile: LAMMPS wraps atoms into the box only when it
         rebuilds the neighbour list, and temp/profile (like chunk/atom bin/1d) wraps a grain that
         has left through the top into the bottom layer while its velocity still belongs to the
         top, which adds ~(rate L_z)^2 to its fluctuation (T 2-4 % high at phi 0.3)
  P_c, sigma_c_xz   collisional (virial) pressure and shear stress, (1/V) sum_pairs d_ij F_ij:
         grainflow `pressure_collisional`, `sigma_c_xz`; LAMMPS compute pressure NULL virial
         (scalar, [5] = xz). Both positive in compression (sigma_xz < 0 in this shear).
  P, sigma_xz       totals, + the kinetic (streaming) part (1/V) sum m v' v' (LAMMPS: the same
         KE tensor / V x N / (N - 16)): grainflow `pressure`, `sigma_xz`.
Each run's mean over the window has a blocking (Flyvbjerg-Petersen) standard error; the mean over
the repeats (independent seeds) takes the larger of the combined blocking error and, with three or
more repeats, the scatter of the run means / sqrt(repeats). The difference in combined standard
errors says whether the codes agree (|d| <= 2: yes, <= 3: marginal, else no).

Known differences (bench/shear/README.md): LAMMPS 2021 updates the tilted box in fix deform's
end_of_step, so the images lag one step behind during the force computation (rate L_z dt =
4.8 um at dt 1e-6, a constant offset through a contact: a <= 0.1 % change of the contact
distance of the pairs across z), wraps grains only at neighbour-list builds, and rebuilds at every
box flip; grainflow sets the images' offset for the end of the step, wraps every step and rebuilds
when a grain moved (skin - |slide since the build|) / 2.

Unless --no-record is given a dated section is appended to bench/RESULTS.md.

Examples (from the repository root):
  /usr/bin/python3 bench/shear/run.py
  /usr/bin/python3 bench/shear/run.py --phis 0.1 --steps 100000 --repeats 1 --no-record
  /usr/bin/python3 bench/shear/run.py --phis 0.2,0.4 --dt 5e-7 --steps 600000 --keep
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
BENCH = HERE.parent
ROOT = BENCH.parent

# Measurement helpers (time -v, load sampling, CPU share, results section) shared with the sphere benchmark:
# bench/ is a package, the scripts run as files, so its root goes on the path.
sys.path.append(str(ROOT))
from bench.terrain_settling import run as ts  # noqa: E402

F, run_timed, lscpu_model, _tail = ts.F, ts.run_timed, ts.lscpu_model, ts._tail

# ---------------------------------------------------------------------------------------------
# The case (cases/rheology/lees_edwards_spheres)
# ---------------------------------------------------------------------------------------------
RADIUS = 0.00265                 # m
DIAMETER = 2 * RADIUS
DENSITY = 1395.0                 # kg/m^3
STIFFNESS = 6.0e5                # N/m, linear normal spring
RESTITUTION = 0.7
BOX = (0.072, 0.048, 0.048)      # m; flow x, vorticity y, gradient z
RATE = 100.0                     # 1/s
BINS = 16                        # layers along z for the mean velocity (both codes)
MASS = DENSITY * 4.0 / 3.0 * math.pi * RADIUS ** 3
M_EFF = MASS / 2                 # equal grains
VOLUME = BOX[0] * BOX[1] * BOX[2]
QUANTITIES = [  # key, label, unit
    ("T", "granular temperature T", "m²/s²"),
    ("P", "pressure P", "Pa"),
    ("P_c", "collisional pressure P_c", "Pa"),
    ("sxz", "shear stress σ_xz", "Pa"),
    ("sxz_c", "collisional σ_xz", "Pa"),
]


def clamped_restitution(zeta: float) -> float:
    """Restitution of a linear spring-dashpot collision whose force is clamped at 0 (the grains
    separate when k delta + c delta' reaches 0), zeta = c / (2 sqrt(m* k)) < 1."""
    w = math.sqrt(1.0 - zeta * zeta)
    b = zeta / w
    wt = math.pi - math.atan2(2.0 * zeta * w, 1.0 - 2.0 * zeta * zeta)
    return -math.exp(-b * wt) * (math.cos(wt) - b * math.sin(wt))


def damping_ratio(e: float) -> float:
    """zeta with clamped_restitution(zeta) = e (bisection; e decreases with zeta)."""
    lo, hi = 0.0, 0.999
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if clamped_restitution(mid) > e else (lo, mid)
    return 0.5 * (lo + hi)


ZETA = damping_ratio(RESTITUTION)
GAMMA_N = 2.0 * ZETA * math.sqrt(STIFFNESS / M_EFF)   # LAMMPS gran/hooke gamma_n, 1/s
CONTACT_TIME = math.pi / (math.sqrt(STIFFNESS / M_EFF) * math.sqrt(1 - ZETA ** 2))


def n_grains(phi: float) -> int:
    return round(phi * VOLUME / (4.0 / 3.0 * math.pi * RADIUS ** 3))


def initial_state(phi: float, v_rms: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Positions on random sites of a box-commensurate simple cubic lattice, and velocities:
    Gaussian fluctuations (zero mean) + the mean flow rate (z - z_mid) along x."""
    cells = [int(L // (1.005 * DIAMETER)) for L in BOX]
    spacing = np.array([L / c for L, c in zip(BOX, cells)])
    n_sites = cells[0] * cells[1] * cells[2]
    n = n_grains(phi)
    if n > n_sites:
        sys.exit(f"phi {phi:g}: {n} grains > {n_sites} lattice sites (phi <= "
                 f"{n_sites * MASS / DENSITY / VOLUME:.3f})")
    rng = np.random.default_rng(seed)
    pick = np.sort(rng.choice(n_sites, n, replace=False))
    ijk = np.stack(np.unravel_index(pick, cells), axis=1)
    x = (ijk + 0.5) * spacing
    v = rng.normal(0.0, v_rms, (n, 3))
    v -= v.mean(axis=0)
    v[:, 0] += RATE * (x[:, 2] - 0.5 * BOX[2])
    return x, v


# ---------------------------------------------------------------------------------------------
# Inputs
# ---------------------------------------------------------------------------------------------
def grainflow_header(name: str, dt: float, end: float, box, particles: str) -> str:
    """The grainflow case up to its particles: a periodic box of the benchmark's material and
    contact law, no gravity; `particles` is the group's source (`file: ...` or positions)."""
    return f"""\
name: {name}
time: {{step: {F(dt)}, end: {F(end)}}}
domain: {{min: [0.0, 0.0, 0.0], max: [{F(box[0])}, {F(box[1])}, {F(box[2])}], periodic: [true, true, true]}}
gravity: [0.0, 0.0, 0.0]
materials:
  grain: {{density: {F(DENSITY)}, youngs_modulus: 1.0e7, poisson_ratio: 0.3}}
contacts:
  - {{between: [grain, grain], model: hooke, stiffness: {F(STIFFNESS)}, restitution: {F(RESTITUTION)}, friction: 0.0}}
particles:
  - {{shape: sphere, radius: {F(RADIUS)}, material: grain, {particles}}}
"""


def grainflow_case(name: str, steps: int, dt: float, sample_steps: int, window_start: float,
                   particles: str) -> str:
    return ("# grainflow bench/shear/run.py: frictionless spheres sheared between Lees-Edwards "
            "images\n" + grainflow_header(name, dt, steps * dt, BOX, f"file: {particles}") + f"""\
shear: {{rate: {F(RATE)}, boundary: lees_edwards, initial_profile: false}}
analysis:
  rheology: {{every: {F(sample_steps * dt)}, bins: {BINS}, start: {F(window_start / RATE)}}}
output:
  directory: out
""")


def particles_csv(x: np.ndarray, v: np.ndarray) -> str:
    rows = ["x,y,z,vx,vy,vz"]
    rows += [",".join(f"{c:.17g}" for c in (*p, *q)) for p, q in zip(x, v)]
    return "\n".join(rows) + "\n"


def lammps_data(x: np.ndarray, v: np.ndarray) -> str:
    lines = ["grainflow bench/shear/run.py: spheres for Lees-Edwards shear", "",
             f"{len(x)} atoms", "1 atom types",
             f"0.0 {F(BOX[0])} xlo xhi", f"0.0 {F(BOX[1])} ylo yhi", f"0.0 {F(BOX[2])} zlo zhi",
             "0.0 0.0 0.0 xy xz yz", "", "Atoms # sphere", ""]
    lines += [f"{i + 1} 1 {F(DIAMETER)} {F(DENSITY)} {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}"
              for i, p in enumerate(x)]
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {q[0]:.17g} {q[1]:.17g} {q[2]:.17g} 0.0 0.0 0.0" for i, q in enumerate(v)]
    return "\n".join(lines) + "\n"


def lammps_head(skin: float, dt: float) -> str:
    """Contact law, integration and neighbour settings shared by the shear and collision inputs."""
    return f"""\
pair_style gran/hooke {F(STIFFNESS)} 0.0 {GAMMA_N:.12g} 0.0 0.0 0 limit_damping
pair_coeff * *
neighbor {F(skin)} bin
neigh_modify delay 0 every 1 check yes
timestep {F(dt)}
fix integrate all nve/sphere
"""


def lammps_input(n: int, steps: int, dt: float, sample_steps: int, skin: float) -> str:
    return f"""\
# grainflow bench/shear/run.py: {n} frictionless spheres sheared between Lees-Edwards images
units si
atom_style sphere
boundary p p p
comm_modify vel yes
read_data data.shear
{lammps_head(skin, dt)}fix shear all deform 1 xz erate {F(RATE)} remap v flip yes
compute pcol all pressure NULL virial
# Layers along z from the unwrapped z (atoms leave the box between neighbour-list builds with
# their velocities not yet remapped; temp/profile and bin/1d chunks would wrap them to the other
# side): layer 1..{BINS}, clamped.
variable layer atom floor({BINS}*(z-{F(0.0)})/{F(BOX[2])})+1
variable layerc atom v_layer+(v_layer<1)*(1-v_layer)-(v_layer>{BINS})*(v_layer-{BINS})
compute layers all chunk/atom v_layerc
compute tkin all temp/chunk layers temp com yes
fix samples all ave/time {sample_steps} 1 {sample_steps} c_pcol c_pcol[5] c_tkin[1] c_tkin[2] c_tkin[3] c_tkin[5] file samples.txt
thermo_style custom step atoms ke
thermo {max(1, steps // 10)}
thermo_modify norm no
run {steps}
"""


# ---------------------------------------------------------------------------------------------
# Running
# ---------------------------------------------------------------------------------------------
LOOP_RE = re.compile(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def grainflow_check(gf: str, workdir: Path) -> tuple[float | None, str]:
    """`grainflow check` of a case in workdir: (neighbour skin in m, or None; the output)."""
    p = subprocess.run([gf, "check", "case.yaml"], cwd=workdir, capture_output=True, text=True,
                       timeout=120)
    out = p.stdout + p.stderr
    m = re.search(r"neighbor skin\s+(\S+) m", out)
    return (float(m.group(1)) if p.returncode == 0 and m else None), out


def run_lammps(lmp: str, workdir: Path, files: dict, tag: str, timeout: float) -> dict:
    workdir.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (workdir / name).write_text(text)
    proc = run_timed([lmp, "-in", "in.lammps", "-log", "log.lammps", "-screen", "none"], workdir,
                     tag, timeout)
    log = (workdir / "log.lammps").read_text(errors="replace") \
        if (workdir / "log.lammps").exists() else ""
    loops = LOOP_RE.findall(log)
    res = {"code": "LAMMPS", "ok": proc.rc == 0 and bool(loops), "proc": proc, "log": log}
    if not res["ok"]:
        err = [l for l in (log + proc.stdout + proc.stderr).splitlines() if "ERROR" in l]
        res["why"] = f"exit {proc.rc}; " + (" | ".join(err[:2]) if err else
                                            _tail(proc.stdout + proc.stderr))
        return res
    sec, _, steps, atoms = loops[-1]
    res.update(seconds=float(sec), steps=int(steps), n=int(atoms), load=proc.load,
               share=proc.cpu_share, loop_fraction=float(sec) / max(proc.wall, 1e-9))
    m = re.search(r"Neighbor list builds = (\d+)", log)
    res["builds"] = int(m.group(1)) if m else None
    m = re.search(r"Dangerous builds = (\d+)", log)
    res["dangerous"] = int(m.group(1)) if m else None
    m = re.search(r"LAMMPS \(([^)]+)\)", log)
    res["version"] = m.group(1) if m else "unknown"
    res["warnings"] = sorted({l.strip() for l in log.splitlines() if l.startswith("WARNING")})
    # "MPI task timing breakdown": section | min | avg | max | %varavg | %total
    res["stages"] = {}
    for line in log.splitlines():
        cols = [c.strip() for c in line.split("|")]
        if len(cols) == 6 and cols[0] in ("Pair", "Neigh", "Comm", "Output", "Modify", "Other"):
            try:
                res["stages"][cols[0]] = float(cols[2])
            except ValueError:
                pass
    return res


def lammps_samples(workdir: Path, dt: float, n: int) -> dict[str, np.ndarray]:
    """fix ave/time rows (step, P_c, sigma_c_xz, KE tensor xx yy zz xz) -> the compared series."""
    d = np.loadtxt(workdir / "samples.txt", comments="#", ndmin=2)
    bessel = n / (n - BINS)  # layer means taken from the grains themselves
    kin = d[:, 3:7] * bessel / VOLUME            # streaming stress xx, yy, zz, xz, Pa
    p_kin = kin[:, :3].sum(axis=1) / 3.0
    return {"strain": d[:, 0] * dt * RATE,
            "T": p_kin * VOLUME / (n * MASS),
            "P_c": d[:, 1], "sxz_c": d[:, 2],
            "P": d[:, 1] + p_kin, "sxz": d[:, 2] + kin[:, 3]}


def run_grainflow(gf: str | None, workdir: Path, files: dict, tag: str, timeout: float) -> dict:
    res = {"code": "grainflow", "ok": False}
    if gf is None:
        res["why"] = "binary not found"
        return res
    workdir.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (workdir / name).write_text(text)
    proc = run_timed([gf, "run", "case.yaml", "--output", "out", "--overwrite", "--threads", "1"],
                     workdir, tag, timeout)
    sj = workdir / "out" / "summary.json"
    if proc.rc != 0 or not sj.exists():
        res["why"] = f"exit {proc.rc}: " + _tail(proc.stderr or proc.stdout)
        return res
    s = json.loads(sj.read_text())
    res.update(ok=True, seconds=float(s["loop_seconds"]), steps=int(s["steps"]),
               n=int(s["n_particles"]), load=proc.load, share=proc.cpu_share,
               loop_fraction=float(s["loop_seconds"]) / max(proc.wall, 1e-9),
               builds=s.get("neighbor_builds"), stages=s.get("stages") or {},
               version=s.get("program", "grainflow"), threads=s.get("threads"),
               warnings=sorted({l.strip() for l in (proc.stdout + proc.stderr).splitlines()
                                if "[warning]" in l}))
    return res


def grainflow_samples(workdir: Path) -> dict[str, np.ndarray]:
    d = np.genfromtxt(workdir / "out" / "rheology.csv", delimiter=",", names=True)
    return {"strain": d["strain"], "T": d["granular_temperature"], "P": d["pressure"],
            "P_c": d["pressure_collisional"], "sxz": d["sigma_xz"], "sxz_c": d["sigma_c_xz"]}


def restitution_check(gf, lmp, dt: float, skin: float, root: Path) -> dict:
    """Head-on collision of two grains (1 m/s closing speed) in both codes at the benchmark's
    dt: realised restitution sqrt(KE_after / KE_before)."""
    out = {}
    gap, v0, steps = 0.1e-3, 0.5, int(round(4 * (0.2e-3 + CONTACT_TIME) / dt))
    x1, x2 = 0.02, 0.02 + DIAMETER + gap
    end = steps * dt
    if lmp:
        wd = root / "collision" / "lammps"
        wd.mkdir(parents=True, exist_ok=True)
        (wd / "in.lammps").write_text(f"""\
units si
atom_style sphere
boundary p p p
comm_modify vel yes
region box block 0.0 0.05 0.0 0.05 0.0 0.05
create_box 1 box
create_atoms 1 single {F(x1)} 0.025 0.025
create_atoms 1 single {F(x2)} 0.025 0.025
set group all diameter {F(DIAMETER)} density {F(DENSITY)}
group second id 2
velocity all set {F(v0)} 0.0 0.0
velocity second set {F(-v0)} 0.0 0.0
{lammps_head(skin, dt)}thermo_style custom step ke
thermo {steps}
thermo_modify norm no format float %.15g
run {steps}
""")
        p = subprocess.run([lmp, "-in", "in.lammps", "-log", "none"], cwd=wd,
                           capture_output=True, text=True, timeout=120)
        rows = re.findall(r"^\s*(\d+)\s+(\S+)\s*$", p.stdout, re.M)
        try:
            ke = {int(s): float(k) for s, k in rows}
            out["LAMMPS"] = math.sqrt(ke[steps] / ke[0])
        except (KeyError, ValueError, ZeroDivisionError):
            out["LAMMPS"] = None
    if gf:
        wd = root / "collision" / "grainflow"
        wd.mkdir(parents=True, exist_ok=True)
        pair = (f"positions: [[{F(x1)}, 0.025, 0.025], [{F(x2)}, 0.025, 0.025]], "
                f"velocities: [[{F(v0)}, 0.0, 0.0], [{F(-v0)}, 0.0, 0.0]]")
        (wd / "case.yaml").write_text(grainflow_header("collision", dt, end, (0.05, 0.05, 0.05),
                                                       pair) + f"""\
neighbor: {{skin: {F(skin)}}}
output:
  directory: out
  series: {{every: {F(end)}, quantities: [kinetic_energy]}}
""")
        p = subprocess.run([gf, "run", "case.yaml", "--output", "out", "--overwrite", "--threads",
                            "1"], cwd=wd, capture_output=True, text=True, timeout=120)
        try:
            rows = [l.split(",") for l in (wd / "out" / "series.csv").read_text().split()[1:]]
            out["grainflow"] = math.sqrt(float(rows[-1][1]) / float(rows[0][1]))
        except (OSError, IndexError, ValueError, ZeroDivisionError):
            out["grainflow"] = None
    return out


# ---------------------------------------------------------------------------------------------
# Statistics
# ---------------------------------------------------------------------------------------------
def blocking_se(x: np.ndarray, min_blocks: int = 16) -> float:
    """Standard error of the mean of a correlated series (Flyvbjerg & Petersen 1989): the
    largest naive standard error over the pairwise blocking levels with >= min_blocks blocks."""
    x = np.asarray(x, dtype=float)
    best = x.std(ddof=1) / math.sqrt(len(x)) if len(x) > 1 else float("nan")
    while len(x) >= 2 * min_blocks:
        x = 0.5 * (x[: len(x) // 2 * 2 : 2] + x[1: len(x) // 2 * 2: 2])
        best = max(best, x.std(ddof=1) / math.sqrt(len(x)))
    return best


def window_stats(series: list[dict], lo: float, hi: float) -> dict:
    """Per quantity: mean over the repeats of each run's mean over strain in [lo, hi], its
    standard error (blocking per run, combined), the sample count."""
    out = {}
    for key, _, _ in QUANTITIES:
        means, ses, count = [], [], 0
        for s in series:
            m = (s["strain"] >= lo - 1e-9) & (s["strain"] <= hi + 1e-9)
            vals = s[key][m]
            if len(vals) < 2:
                continue
            means.append(vals.mean())
            ses.append(blocking_se(vals))
            count += len(vals)
        if means:
            se_block = math.sqrt(sum(e * e for e in ses)) / len(ses)
            # Independent repeats: their scatter is a second estimate, which does not depend on
            # the blocking having reached the correlation time; the larger one is used.
            se_scatter = (float(np.std(means, ddof=1)) / math.sqrt(len(means))
                          if len(means) >= 3 else 0.0)
            out[key] = {"mean": float(np.mean(means)), "se": max(se_block, se_scatter),
                        "se_block": se_block, "se_scatter": se_scatter,
                        "n": count, "runs": [float(x) for x in means]}
    return out


# ---------------------------------------------------------------------------------------------
# Tables
# ---------------------------------------------------------------------------------------------
def fmt_load(ld) -> str:
    return f"{ld['start']:.2f}/{ld['mean']:.2f}/{ld['max']:.2f}" if ld else "n/a"


def speed_table(runs: list[dict]) -> str:
    head = ("| phi | N | repeat (seed) | code | steps | loop s | particle-steps/s | gf/LAMMPS | "
            "neighbour builds | load (start/mean/max) | CPU share |")
    out = [head, "|" + "---|" * head.count(" | ") + "---|"]
    for r in runs:
        for code in ("LAMMPS", "grainflow"):
            x = r[code]
            ratio = ""
            if x["ok"]:
                if code == "LAMMPS":
                    ratio = "1.00"
                elif r["LAMMPS"]["ok"]:
                    ratio = f"{x['rate'] / r['LAMMPS']['rate']:.2f}"
                cells = [str(x["steps"]), f"{x['seconds']:.2f}", f"{x['rate']:.3g}",
                         ratio or "n/a", str(x.get("builds", "n/a")), fmt_load(x["load"]),
                         f"{x['share']:.2f}" if x.get("share") else "n/a"]
            else:
                cells = ["n/a"] * 7
            out.append("| " + " | ".join([f"{r['phi']:g}", str(r["n"]), f"{r['repeat']} ({r['seed']})",
                                          code, *cells]) + " |")
    return "\n".join(out)


def summary_table(phis, runs) -> tuple[str, dict]:
    head = ("| phi | N | LAMMPS particle-steps/s (runs) | grainflow particle-steps/s (runs) | "
            "gf/LAMMPS (runs) |")
    out, ratios = [head, "|" + "---|" * head.count(" | ") + "---|"], {}
    for phi in phis:
        rs = [r for r in runs if r["phi"] == phi]
        lam = [r["LAMMPS"]["rate"] for r in rs if r["LAMMPS"]["ok"]]
        gfr = [r["grainflow"]["rate"] for r in rs if r["grainflow"]["ok"]]
        rat = [r["grainflow"]["rate"] / r["LAMMPS"]["rate"] for r in rs
               if r["LAMMPS"]["ok"] and r["grainflow"]["ok"]]
        ratios[phi] = rat

        def cell(v):
            return (f"{np.mean(v):.3g} ({', '.join(f'{x:.3g}' for x in v)})" if v else "n/a")

        rc = f"{np.mean(rat):.2f} ({', '.join(f'{x:.2f}' for x in rat)})" if rat else "n/a"
        out.append(f"| {phi:g} | {rs[0]['n'] if rs else 'n/a'} | {cell(lam)} | {cell(gfr)} | {rc} |")
    return "\n".join(out), ratios


def physics_table(phis, stats, window) -> tuple[str, list[str]]:
    head = ("| phi | quantity | grainflow mean ± se | LAMMPS mean ± se | gf − LAMMPS | "
            "difference / combined se | agree? |")
    out, flags, compared = [head, "|" + "---|" * head.count(" | ") + "---|"], [], 0
    for phi in phis:
        g, l = stats[phi].get("grainflow", {}), stats[phi].get("LAMMPS", {})
        for key, label, unit in QUANTITIES:
            if key not in g or key not in l:
                cells = [f"{x[key]['mean']:.4g} ± {x[key]['se']:.2g}" if key in x else "n/a"
                         for x in (g, l)]
                out.append(f"| {phi:g} | {label} ({unit}) | {cells[0]} | {cells[1]} | | | |")
                continue
            compared += 1
            a, b = g[key], l[key]
            diff = a["mean"] - b["mean"]
            se = math.hypot(a["se"], b["se"])
            z = diff / se if se > 0 else float("inf")
            verdict = "yes" if abs(z) <= 2 else ("marginal" if abs(z) <= 3 else "**no**")
            if abs(z) > 2:
                flags.append(f"phi {phi:g} {label}: {a['mean']:.4g} vs {b['mean']:.4g} {unit} "
                             f"({z:+.1f} combined standard errors)")
            rel = f" ({100 * diff / b['mean']:+.1f} %)" if b["mean"] else ""
            out.append(f"| {phi:g} | {label} ({unit}) | {a['mean']:.4g} ± {a['se']:.2g} | "
                       f"{b['mean']:.4g} ± {b['se']:.2g} | {diff:+.3g}{rel} | {z:+.1f} | {verdict} |")
    return "\n".join(out), flags, compared


# ---------------------------------------------------------------------------------------------
# Driver
# ---------------------------------------------------------------------------------------------
def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="See bench/shear/README.md.")
    ap.add_argument("--phis", default="0.1,0.3", help="volume fractions (default %(default)s)")
    ap.add_argument("--steps", type=int, default=400000,
                    help="time steps per run (default %(default)s: strain 40 at the default dt)")
    ap.add_argument("--dt", type=float, default=1.0e-6,
                    help="time step, s, both codes (default %(default)s; the shipped case: 5e-7)")
    ap.add_argument("--repeats", type=int, default=4,
                    help="runs per phi and code, seed --seed + repeat (default %(default)s)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--v-rms", type=float, default=0.5,
                    help="initial velocity fluctuation per component, m/s (default %(default)s)")
    ap.add_argument("--window-start", type=float, default=10.0,
                    help="strain where the averaging window starts; it ends with the run "
                         "(default %(default)s)")
    ap.add_argument("--sample-strain", type=float, default=0.01,
                    help="strain between samples, both codes (default %(default)s)")
    ap.add_argument("--box-scale", type=float, default=1.0,
                    help="multiplies each edge of the box (2: 8 times the grains; default "
                         "%(default)s)")
    ap.add_argument("--grainflow", default=str(ROOT / "build" / "release" / "grainflow"))
    ap.add_argument("--lammps", default="/usr/bin/lmp")
    ts.add_run_args(ap)
    return ap.parse_args(argv)


def machine() -> str:
    text = lscpu_model()
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        m = re.search(r"Hypervisor vendor:\s*(.+)", out)
        if m:
            text += f", {m.group(1).strip()} guest"
        elif re.search(r"^Flags:.*\bhypervisor\b", out, re.M):
            text += ", virtual machine (`hypervisor` CPU flag)"
    except OSError:
        pass
    return f"{text}, {os.cpu_count()} cores (`lscpu`)"


def main(argv=None) -> int:
    global BOX, VOLUME
    a = parse_args(argv)
    if a.box_scale <= 0:
        sys.exit(f"--box-scale {a.box_scale:g}: must be positive")
    BOX = tuple(a.box_scale * L for L in BOX)
    VOLUME = BOX[0] * BOX[1] * BOX[2]
    phis = [float(s) for s in a.phis.split(",") if s.strip()]
    gf, lmp = ts.resolve_exe(a.grainflow), ts.resolve_exe(a.lammps)
    if not Path("/usr/bin/time").exists():
        sys.exit("/usr/bin/time missing: apt-get install -y time")
    end_strain = a.steps * a.dt * RATE
    window = (a.window_start, end_strain)
    if a.window_start >= end_strain:
        window = (0.5 * end_strain, end_strain)
        print(f"warning: --window-start {a.window_start:g} >= the run's strain {end_strain:g}: "
              f"averaging over the second half", file=sys.stderr)
    sample_steps = max(1, round(a.sample_strain / (RATE * a.dt)))
    stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    root = (BENCH / "runs" / f"shear-{stamp}") if a.keep else Path(tempfile.mkdtemp(prefix="gf-shear-"))
    root.mkdir(parents=True, exist_ok=True)
    t_start = _dt.datetime.now()
    gf_mtime = Path(gf).stat().st_mtime if gf else None
    notes: list[str] = []
    print(f"run folders: {root}; grainflow {gf}; LAMMPS {lmp}", flush=True)
    print(f"contact: k_n {STIFFNESS:g} N/m, e {RESTITUTION:g} (clamped) -> zeta {ZETA:.6f}, "
          f"LAMMPS gamma_n {GAMMA_N:.6g} 1/s; contact time {CONTACT_TIME:.4g} s = "
          f"{CONTACT_TIME / a.dt:.0f} dt; {a.steps} steps = strain {end_strain:g}, window "
          f"[{window[0]:g}, {window[1]:g}], a sample every {sample_steps} steps", flush=True)

    # Neighbour skin: grainflow's default, read from `grainflow check` of the first case.
    skin, check_out = None, ""
    x0, v0 = initial_state(phis[0], a.v_rms, a.seed)
    if gf:
        wd = root / "check"
        wd.mkdir(parents=True, exist_ok=True)
        (wd / "particles.csv").write_text(particles_csv(x0, v0))
        (wd / "case.yaml").write_text(grainflow_case("check", a.steps, a.dt, sample_steps,
                                                     window[0], "particles.csv"))
        skin, check_out = grainflow_check(gf, wd)
        if skin is None:
            print("grainflow check failed:\n" + check_out, file=sys.stderr)
    if skin is None:
        skin = 0.25 * DIAMETER  # grainflow's documented default
    print(f"neighbour skin {skin:g} m (both codes)", flush=True)

    coll = restitution_check(gf, lmp, a.dt, skin, root)
    print("realised restitution at dt " + f"{a.dt:g} s: " +
          ", ".join(f"{k} {v:.8f}" if v else f"{k} n/a" for k, v in coll.items()), flush=True)

    runs, series = [], {phi: {"grainflow": [], "LAMMPS": []} for phi in phis}
    for phi in phis:
        for rep in range(a.repeats):
            seed = a.seed + rep
            x, v = initial_state(phi, a.v_rms, seed)
            n = len(x)
            print(f"\nphi {phi:g}, N {n}, repeat {rep} (seed {seed}), load "
                  f"{os.getloadavg()[0]:.2f}", flush=True)
            wd = root / f"phi{phi:g}" / f"rep{rep}"
            r = {"phi": phi, "n": n, "repeat": rep, "seed": seed}
            if lmp:
                r["LAMMPS"] = run_lammps(lmp, wd / "lammps",
                                         {"data.shear": lammps_data(x, v),
                                          "in.lammps": lammps_input(n, a.steps, a.dt, sample_steps, skin)},
                                         "lammps", a.timeout)
            else:
                r["LAMMPS"] = {"code": "LAMMPS", "ok": False, "why": f"{a.lammps} not found"}
            r["grainflow"] = run_grainflow(
                gf, wd / "grainflow",
                {"particles.csv": particles_csv(x, v),
                 "case.yaml": grainflow_case(f"shear_phi{phi:g}_seed{seed}", a.steps, a.dt,
                                             sample_steps, window[0], "particles.csv")},
                "grainflow", a.timeout)
            for code in ("LAMMPS", "grainflow"):
                x_ = r[code]
                if not x_["ok"]:
                    print(f"  {code}: n/a ({x_['why']})", flush=True)
                    continue
                x_["rate"] = x_["n"] * x_["steps"] / x_["seconds"]
                try:
                    s = (lammps_samples(wd / "lammps", a.dt, n) if code == "LAMMPS"
                         else grainflow_samples(wd / "grainflow"))
                    series[phi][code].append(s)
                    m = s["strain"] >= window[0]
                    brief = (f", window means T {s['T'][m].mean():.4g} m²/s², "
                             f"P {s['P'][m].mean():.4g} Pa, σ_xz {s['sxz'][m].mean():.4g} Pa")
                except (OSError, ValueError, KeyError, IndexError) as e:
                    brief = f", samples unreadable: {e}"
                print(f"  {code}: {x_['seconds']:.2f} s, {x_['rate']:.3g} particle-steps/s, "
                      f"{x_.get('builds')} neighbour builds, CPU share "
                      f"{x_['share'] if x_.get('share') is None else round(x_['share'], 2)}"
                      + brief, flush=True)
            runs.append(r)

    if gf and Path(gf).stat().st_mtime != gf_mtime:
        notes.append(f"the grainflow binary was replaced during this run (modified "
                     f"{_dt.datetime.fromtimestamp(Path(gf).stat().st_mtime):%H:%M:%S}): its "
                     f"runs may come from two builds")
        print("warning: " + notes[-1], file=sys.stderr)
    stats = {phi: {code: window_stats(series[phi][code], *window) for code in series[phi]}
             for phi in phis}
    t1 = speed_table(runs)
    t2, ratios = summary_table(phis, runs)
    t3, flags, compared = physics_table(phis, stats, window)
    print("\n" + t1 + "\n\n" + t2 + "\n\n" + t3)
    if flags:
        print("\nDISAGREEMENT beyond 2 combined standard errors:\n  " + "\n  ".join(flags))

    if not a.no_record:
        lam_ok = [r["LAMMPS"] for r in runs if r["LAMMPS"]["ok"]]
        gf_ok = [r["grainflow"] for r in runs if r["grainflow"]["ok"]]
        built = (_dt.datetime.fromtimestamp(gf_mtime).strftime("%Y-%m-%d %H:%M") if gf else "n/a")
        loads = [x["load"] for x in lam_ok + gf_ok if x.get("load")]
        shares = [x["share"] for x in lam_ok + gf_ok if x.get("share")]
        out_share = [x["stages"].get("output", 0.0) / x["seconds"] for x in gf_ok if x["seconds"]]
        lw = sorted({w for x in lam_ok for w in x["warnings"]})
        gw = sorted({w.split("]", 1)[-1].strip() for x in gf_ok for w in x["warnings"]})
        lines = [
            "", f"## Lees-Edwards shear of spheres: grainflow vs LAMMPS — {t_start.date().isoformat()}",
            "",
            f"- Machine: {machine()}, shared; started {t_start.isoformat(timespec='seconds')}; "
            f"load average over the runs (1-min, mean of each run's mean) "
            f"{np.mean([l['mean'] for l in loads]):.2f}, max {max(l['max'] for l in loads):.2f}; "
            f"CPU share of the processes {min(shares):.2f}-{max(shares):.2f}"
            if loads and shares else f"- Machine: {machine()}, shared",
            f"- Codes: grainflow ({gf_ok[0]['version'] if gf_ok else 'n/a'}, {gf}, binary of "
            f"{built}), LAMMPS {lam_ok[0]['version'] if lam_ok else 'n/a'} (Debian `lammps`, "
            f"{lmp}); serial, 1 process / 1 thread each (`--threads 1`, `OMP_NUM_THREADS=1`), run "
            f"one after the other (LAMMPS first); double precision (bench/shear/run.py)",
            f"- Case (cases/rheology/lees_edwards_spheres at other phi): frictionless spheres d "
            f"{DIAMETER * 1e3:g} mm, {DENSITY:g} kg/m^3, linear spring k_n {STIFFNESS:g} N/m with "
            f"a clamped dashpot, e {RESTITUTION:g} (zeta {ZETA:.4f}; LAMMPS `gran/hooke` gamma_n "
            f"{GAMMA_N:.5g} 1/s `limit_damping`, Kt 0, xmu 0), no gravity, box "
            f"{' x '.join(f'{L:g}' for L in BOX)} m periodic, shear rate {RATE:g} 1/s between "
            f"Lees-Edwards images (LAMMPS: triclinic box, `fix deform xz erate remap v flip yes`); "
            f"dt {a.dt:g} s (contact time / {CONTACT_TIME / a.dt:.0f}), {a.steps} steps = strain "
            f"{end_strain:g}; neighbour skin {skin:g} m both; start: random sites of a simple "
            f"cubic lattice, Gaussian velocities rms {a.v_rms:g} m/s per component + the mean "
            f"flow, the same file contents for both codes, seeds {a.seed}..{a.seed + a.repeats - 1}",
            "- Two-grain head-on collision at this dt (1 m/s closing): realised restitution "
            + ", ".join(f"{k} {v:.8f}" if v else f"{k} n/a" for k, v in coll.items())
            + f" (the continuous-time model: {RESTITUTION:g})",
            "- Rate = N x steps / loop time (grainflow `loop_seconds` of summary.json, without its "
            "output stage = the rheology sampling, "
            + (f"{100 * min(out_share):.1f}-{100 * max(out_share):.1f} % of the loop" if out_share
               else "n/a")
            + "; LAMMPS `Loop time`, sampling included); gf/LAMMPS > 1: grainflow faster",
        ]
        for phi in phis:
            first = next((r for r in runs if r["phi"] == phi), None)
            parts = []
            for code in ("grainflow", "LAMMPS") if first else ():
                x = first[code]
                if x["ok"] and x.get("stages"):
                    tot = sum(x["stages"].values())
                    parts.append(f"{code} " + ", ".join(
                        f"{k} {v:.2f} s ({100 * v / tot:.0f} %)" for k, v in x["stages"].items()
                        if v > 0))
            if parts:
                lines.append(f"- Time per stage, phi {phi:g}, repeat 0: " + "; ".join(parts))
        lines += [f"- Note: {t}" for t in notes]
        if lw:
            lines.append("- LAMMPS warnings: " + "; ".join(lw))
        if gw:
            lines.append("- grainflow warnings: " + "; ".join(gw))
        for r in runs:
            for code in ("LAMMPS", "grainflow"):
                if not r[code]["ok"]:
                    lines.append(f"- phi {r['phi']:g} repeat {r['repeat']} {code}: n/a — {r[code]['why']}")
        body = ["", t1, "", "Mean over the repeats:", "", t2, "",
                f"Cross-check over strain [{window[0]:g}, {window[1]:g}] (samples every "
                f"{sample_steps} steps = strain {sample_steps * a.dt * RATE:g}, the same steps in "
                f"both codes; mean over the repeats of each run's mean, standard error: the larger of "
                f"the runs' blocking errors combined and the scatter of the run means / "
                f"sqrt(repeats); T with the 1/(1 - 1/n) correction for layer means, LAMMPS: compute "
                f"temp/chunk com yes over {BINS} layers of the unwrapped z, KE tensor x "
                f"N/(N - {BINS}); collisional parts: "
                f"grainflow d_ij F_ij sum, LAMMPS compute pressure NULL virial; compressive "
                f"positive; agree: |difference| <= 2 combined standard errors):", "", t3, ""]
        if flags:
            body += ["Disagreements beyond 2 combined standard errors: " + "; ".join(flags) + ".", ""]
        elif compared:
            body += ["All compared quantities agree within 2 combined standard errors.", ""]
        else:
            body += ["No cross-check: one of the codes gave no samples.", ""]
        ts.append_section(Path(a.results), lines, a.note or None, body)
    if a.keep:
        (root / "results.json").write_text(json.dumps(
            {"args": vars(a), "restitution": coll, "stats": {str(k): v for k, v in stats.items()},
             "runs": [{**{k: r[k] for k in ("phi", "n", "repeat", "seed")},
                       **{c: {k: v for k, v in r[c].items() if k not in ("proc", "log")}
                          for c in ("LAMMPS", "grainflow")}} for r in runs]},
            indent=2, default=str))
    else:
        shutil.rmtree(root, ignore_errors=True)
    print(f"\ntotal wall time {(_dt.datetime.now() - t_start).total_seconds():.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
