#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Side-by-side DEM benchmark of the "terrain settling" case: grainflow vs LIGGGHTS.

Both codes run the same case: monodisperse glass spheres (r = 5 mm, 2500 kg/m^3, E = 1e7 Pa,
nu = 0.3, e = 0.5, mu = 0.5, Hertz-Mindlin with tangential history, no rolling friction)
start on a simple cubic lattice (spacing 1.05 d) just above the floor of a box with five plane
walls (open top), get a small random velocity kick (to break the lattice symmetry, otherwise
the columns just compress and never collapse) and settle under gravity with dt = 2e-5 s.

Per code and per size N it measures
  (1) settle: the whole run from the lattice for a fixed simulated time,
  (2) dense:  a fixed number of further steps from the settled state
              (LIGGGHTS: a second `run` in the same input; grainflow: `--restart` from the
              checkpoint written at the end of the settling run),
  (3) peak memory: "Maximum resident set size" from /usr/bin/time -v, raw and minus a baseline
      run of the same code with a tiny N, per particle,
and prints particle-steps/s (N x steps / loop wall time), the grainflow/LIGGGHTS ratio and
bytes/particle, with the machine load and the CPU share each process got (the machine is
shared). Unless --no-record is given it appends a dated section to bench/RESULTS.md.

If the grainflow binary is missing or fails, its rows are reported as n/a and the LIGGGHTS
figures are still produced.

Examples (from the repository root):
  /usr/bin/python3 bench/terrain_settling/run.py --sizes 10000
  /usr/bin/python3 bench/terrain_settling/run.py --sizes 10000,50000 --codes liggghts --keep
  /usr/bin/python3 bench/terrain_settling/run.py --sizes 10000 --threads 2   # mpirun -np 2
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCH = HERE.parent
ROOT = BENCH.parent

# ---------------------------------------------------------------------------------------------
# The case (identical for both codes)
# ---------------------------------------------------------------------------------------------
RADIUS = 0.005            # m
DENSITY = 2500.0          # kg/m^3
YOUNGS = 1.0e7            # Pa
POISSON = 0.3
RESTITUTION = 0.5
FRICTION = 0.5
GRAVITY = 9.81            # m/s^2, along -z
DT = 2.0e-5               # s
SPACING = 1.05 * 2 * RADIUS  # simple cubic lattice spacing, m
SKIN = 0.5 * RADIUS       # neighbour skin, m
SERIES_EVERY = 0.01       # s, energy / height output in both codes (LIGGGHTS: thermo)
BASELINE_N = 64           # tiny run for the memory baseline (4 x 4 x 4)
BASELINE_STEPS = 200


# The head of every LIGGGHTS input in bench/ (granular atoms, fixed boundaries, SI units).
LIGGGHTS_PREAMBLE = """\
atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
"""


def append_section(path: Path, head: list[str], note: str | None = None,
                   body: list[str] = ()) -> None:
    """Appends a dated section to bench/RESULTS.md: its head lines, a `- Note:` line if a note
    is given, then its body (tables)."""
    lines = list(head) + ([f"- Note: {note}"] if note else []) + list(body)
    new = not path.exists()
    with path.open("a") as f:
        if new:
            f.write("# Benchmark results\n\nAppended by the scripts under bench/; newest last.\n")
        f.write("\n".join(lines))
    print(f"\nappended to {path}")


def last_checkpoint(folder: Path) -> Path | None:
    """The checkpoint a later phase restarts from: checkpoint_final.h5, else the last periodic
    one, else None (the run wrote none)."""
    final = folder / "checkpoint_final.h5"
    if final.exists():
        return final
    c = sorted(folder.glob("checkpoint_*.h5"))
    return c[-1] if c else None


def peer_phases(proc, loops: list[dict], names: tuple[str, str]) -> dict:
    """The two timed phases of a peer run (its first two `Loop time` records), with the process's
    load and CPU share and the share of its wall time spent in the two loops."""
    frac = (loops[0]["seconds"] + loops[1]["seconds"]) / max(proc.wall, 1e-9)
    return {ph: {"steps": lp["steps"], "seconds": lp["seconds"], "load": proc.load,
                 "cpu_share": proc.cpu_share, "loop_fraction": frac}
            for ph, lp in zip(names, loops)}


def F(x: float) -> str:
    """A float for input files, always with a decimal point: 0.0105, 10000000.0, 2.0e-05, 0.0."""
    text = f"{float(x):.10g}"
    mant, _, exp = text.partition("e")
    if "." not in mant:
        mant += ".0"
    return mant + ("e" + exp if exp else "")


def rayleigh_time() -> float:
    """Rayleigh time of the spheres, s."""
    shear = YOUNGS / (2 * (1 + POISSON))
    return math.pi * RADIUS * math.sqrt(DENSITY / shear) / (0.1631 * POISSON + 0.8766)


@dataclass
class Geometry:
    """Lattice n_xy x n_xy x n_z in a box L x L x H (open top); the lattice fills the bottom."""

    n_xy: int
    n_z: int

    @property
    def n(self) -> int:
        return self.n_xy * self.n_xy * self.n_z

    @property
    def side(self) -> float:        # box side L, m
        return self.n_xy * SPACING

    @property
    def lattice_top(self) -> float:  # top of the lattice block, m
        return self.n_z * SPACING

    @property
    def height(self) -> float:      # domain height, m (head room above the lattice)
        return 1.5 * self.lattice_top + 4 * RADIUS


def choose_geometry(target: int) -> Geometry:
    """Square footprint, about 20 layers, N = n_xy^2 n_z as close to `target` as possible."""
    if target <= BASELINE_N:
        k = max(1, round(target ** (1 / 3)))
        return Geometry(k, k)
    best = None
    for n_z in range(4, 61):
        n_xy = max(1, round(math.sqrt(target / n_z)))
        key = (abs(n_xy * n_xy * n_z - target), abs(n_z - 20), n_z)
        if best is None or key < best[0]:
            best = (key, Geometry(n_xy, n_z))
    return best[1]


# ---------------------------------------------------------------------------------------------
# Measurement helpers
# ---------------------------------------------------------------------------------------------
QUIET = {"load": None, "max_wait": 0.0}


def wait_quiet() -> None:
    """With --wait-quiet L: wait (at most --wait-max s) until the 1-minute load is below L."""
    if QUIET["load"] is None:
        return
    t0 = time.monotonic()
    while os.getloadavg()[0] >= QUIET["load"] and time.monotonic() - t0 < QUIET["max_wait"]:
        time.sleep(10)
    waited = time.monotonic() - t0
    if waited > 1:
        print(f"    (waited {waited:.0f} s for load < {QUIET['load']:g}; now "
              f"{os.getloadavg()[0]:.2f})", flush=True)


class LoadSampler:
    """Samples the 1-minute load average while a run is going (mean / max over the run)."""

    def __init__(self, period: float = 2.0):
        self.period = period
        self.samples: list[float] = []
        self.start = os.getloadavg()[0]
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True)

    def _loop(self):
        while not self._stop.wait(self.period):
            self.samples.append(os.getloadavg()[0])

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()
        self.samples.append(os.getloadavg()[0])

    def summary(self) -> dict:
        return {"start": self.start, "mean": statistics.fmean(self.samples),
                "max": max(self.samples)}


@dataclass
class Proc:
    """One process run under /usr/bin/time -v."""

    rc: int
    wall: float
    maxrss_bytes: int | None
    cpu_percent: str
    cpu_share: float | None  # CPU seconds / (wall seconds x ranks), from time -v
    load: dict
    stdout: str
    stderr: str


def parse_time_v(path: Path) -> tuple[int | None, str, float | None, float | None]:
    """From a /usr/bin/time -v report: (max RSS in bytes, 'Percent of CPU this job got',
    user + system CPU seconds, elapsed wall seconds)."""
    if not path.exists():
        return None, "?", None, None
    text = path.read_text(errors="replace")
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    c = re.search(r"Percent of CPU this job got: (\S+)", text)
    u = re.search(r"User time \(seconds\): (\S+)", text)
    k = re.search(r"System time \(seconds\): (\S+)", text)
    e = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text)
    cpu_s = float(u.group(1)) + float(k.group(1)) if u and k else None
    wall_s = None
    if e:
        wall_s = 0.0
        for part in e.group(1).split(":"):
            wall_s = wall_s * 60 + float(part)
    return (int(m.group(1)) * 1024 if m else None), (c.group(1) if c else "?"), cpu_s, wall_s


def _share(cpu_s, wall_s, ranks=1):
    if cpu_s is None or not wall_s:
        return None
    return min(1.0, cpu_s / (wall_s * ranks))


def run_timed(cmd: list[str], cwd: Path, tag: str, timeout: float,
              per_rank_time: int = 0, threads: int = 1) -> Proc:
    """Run `cmd` in `cwd` under /usr/bin/time -v (written to <tag>.time).

    per_rank_time > 0: `cmd` is an mpirun command whose ranks are each wrapped in time -v
    (files <tag>.time.<rank>); the max RSS is then the sum over the ranks.
    threads: threads of a single process (for the CPU share).
    """
    wait_quiet()
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("BENCH_OMP_NUM_THREADS", "1"))
    tfile = cwd / f"{tag}.time"
    full = cmd if per_rank_time else ["/usr/bin/time", "-v", "-o", str(tfile), *cmd]
    t0 = time.perf_counter()
    with LoadSampler() as load:
        try:
            p = subprocess.run(full, cwd=cwd, env=env, capture_output=True, text=True,
                               timeout=timeout)
            rc, out, err = p.returncode, p.stdout, p.stderr
        except subprocess.TimeoutExpired:
            rc, out, err = 124, "", f"timed out after {timeout:g} s"
        except OSError as e:
            rc, out, err = 127, "", str(e)
    wall = time.perf_counter() - t0
    (cwd / f"{tag}.stdout").write_text(out or "")
    (cwd / f"{tag}.stderr").write_text(err or "")
    if per_rank_time:
        rss, cpus, cpu_s, wall_s = 0, [], 0.0, 0.0
        for r in range(per_rank_time):
            b, c, cs, ws = parse_time_v(cwd / f"{tag}.time.{r}")
            rss = None if (b is None or rss is None) else rss + b
            cpu_s = None if (cs is None or cpu_s is None) else cpu_s + cs
            wall_s = None if (ws is None or wall_s is None) else max(wall_s, ws)
            cpus.append(c)
        cpu, share = "+".join(cpus), _share(cpu_s, wall_s, per_rank_time)
    else:
        rss, cpu, cpu_s, wall_s = parse_time_v(tfile)
        share = _share(cpu_s, wall_s, threads)
    return Proc(rc, wall, rss, cpu, share, load.summary(), out or "", err or "")


# ---------------------------------------------------------------------------------------------
# LIGGGHTS
# ---------------------------------------------------------------------------------------------
def liggghts_input(geo: Geometry, settle_steps: int, dense_steps: int, jitter: float,
                   seed: int) -> str:
    """The LIGGGHTS 3.8 input deck: settle run, then the dense run (its own Loop time)."""
    L, H, top = geo.side, geo.height, geo.lattice_top
    thermo = max(1, round(SERIES_EVERY / DT))
    # grainflow's lattice fill puts the first site at (r, r, r) from the fill box minimum (the
    # spheres just touch the walls and the floor); the same here with origin = r / spacing.
    org = RADIUS / SPACING
    # LIGGGHTS' random() needs seeds that are primes > 10000.
    seeds = [p for p in _primes_above(10000 + 7919 * (seed % 1000), 3)]
    walls = "\n".join(
        f"fix {name} all wall/gran model hertz tangential history primitive type 1 {plane} {F(pos)}"
        for name, plane, pos in [("wx0", "xplane", 0.0), ("wx1", "xplane", L),
                                 ("wy0", "yplane", 0.0), ("wy1", "yplane", L),
                                 ("wz0", "zplane", 0.0)])
    kick = ""
    if jitter > 0:
        kick = (f"variable vx atom random({F(-jitter)},{F(jitter)},{seeds[0]})\n"
                f"variable vy atom random({F(-jitter)},{F(jitter)},{seeds[1]})\n"
                f"variable vz atom random({F(-jitter)},{F(jitter)},{seeds[2]})\n"
                "velocity all set v_vx v_vy v_vz\n")
    return f"""\
# terrain settling benchmark, N = {geo.n} ({geo.n_xy} x {geo.n_xy} x {geo.n_z} simple cubic)
{LIGGGHTS_PREAMBLE}
region domain block 0 {F(L)} 0 {F(L)} 0 {F(H)} units box
create_box 1 domain

neighbor {F(SKIN)} bin
neigh_modify delay 0

fix m1 all property/global youngsModulus peratomtype {F(YOUNGS)}
fix m2 all property/global poissonsRatio peratomtype {F(POISSON)}
fix m3 all property/global coefficientRestitution peratomtypepair 1 {F(RESTITUTION)}
fix m4 all property/global coefficientFriction peratomtypepair 1 {F(FRICTION)}

pair_style gran model hertz tangential history
pair_coeff * *
timestep {F(DT)}
fix gravi all gravity {F(GRAVITY)} vector 0.0 0.0 -1.0

{walls}

lattice sc {F(SPACING)} origin {F(org)} {F(org)} {F(org)}
region lat block 0 {F(L)} 0 {F(L)} 0 {F(top)} units box
create_atoms 1 region lat
set group all diameter {F(2 * RADIUS)} density {F(DENSITY)}
{kick}
fix integr all nve/sphere
compute zmax all reduce max z
compute cpa all contact/atom
compute ncon all reduce sum c_cpa
variable coord equal c_ncon/atoms
thermo_style custom step atoms ke c_zmax v_coord
thermo {thermo}
thermo_modify lost ignore norm no

run {settle_steps}
run {dense_steps}
"""


def _primes_above(start: int, count: int) -> list[int]:
    out, k = [], start + 1
    while len(out) < count:
        if all(k % d for d in range(2, int(k ** 0.5) + 1)):
            out.append(k)
        k += 1
    return out


LOOP_RE = re.compile(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def parse_liggghts_log(text: str) -> dict:
    loops = [dict(seconds=float(m.group(1)), procs=int(m.group(2)), steps=int(m.group(3)),
                  atoms=int(m.group(4))) for m in LOOP_RE.finditer(text)]
    neighs = [float(x) for x in re.findall(r"Ave neighs/atom = (\S+)", text)]
    created = re.search(r"Created (\d+) atoms", text)
    thermo = re.findall(r"^\s+(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", text, re.M)
    version = re.search(r"LIGGGHTS \(Version ([^,)]+)", text)
    return {"loops": loops, "neighs_per_atom": neighs,
            "created": int(created.group(1)) if created else None,
            "thermo": thermo,
            "version": version.group(1) if version else "unknown"}


def run_liggghts(exe: str, geo: Geometry, settle_steps: int, dense_steps: int, threads: int,
                 workdir: Path, args) -> dict:
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.settling").write_text(
        liggghts_input(geo, settle_steps, dense_steps, args.jitter, args.seed))
    base = [exe, "-in", "in.settling", "-log", "log.liggghts", "-screen", "none"]
    if threads > 1:
        # One /usr/bin/time per rank, so the memory is the sum over the ranks.
        wrapped = ["sh", "-c", '/usr/bin/time -v -o "liggghts.time.$OMPI_COMM_WORLD_RANK" "$@"',
                   "sh", *base]
        cmd = ["mpirun", "-np", str(threads), *args.mpirun_args.split(), *wrapped]
        proc = run_timed(cmd, workdir, "liggghts", args.timeout, per_rank_time=threads)
    else:
        proc = run_timed(base, workdir, "liggghts", args.timeout)
    log = workdir / "log.liggghts"
    info = parse_liggghts_log(log.read_text(errors="replace") if log.exists() else "")
    res = {"code": "LIGGGHTS", "ok": proc.rc == 0 and len(info["loops"]) >= 2, "rc": proc.rc,
           "proc": proc, "info": info, "version": info["version"]}
    if not res["ok"]:
        res["why"] = (f"exit {proc.rc}, {len(info['loops'])} loop(s) in log; "
                      + _tail(proc.stdout + proc.stderr))
        return res
    settle, dense = info["loops"][0], info["loops"][1]
    res["phases"] = {
        "settle": {"steps": settle["steps"], "seconds": settle["seconds"], "load": proc.load,
                   "cpu_share": proc.cpu_share},
        "dense": {"steps": dense["steps"], "seconds": dense["seconds"], "load": proc.load,
                  "cpu_share": proc.cpu_share},
    }
    frac = (settle["seconds"] + dense["seconds"]) / proc.wall if proc.wall > 0 else 0.0
    for ph in res["phases"].values():
        ph["loop_fraction"] = frac
    res["n"] = info["created"]
    res["n_end"] = dense["atoms"]
    res["maxrss"] = proc.maxrss_bytes
    res["cpu"] = proc.cpu_percent
    res["neighs"] = info["neighs_per_atom"][-1] if info["neighs_per_atom"] else None
    at_settle = [t for t in info["thermo"] if int(t[0]) == settle_steps]
    if at_settle:  # state at the end of the settling run, as grainflow's series reports it
        res["ke_end"], res["zmax_end"] = float(at_settle[0][2]), float(at_settle[0][3])
        res["coord_end"] = float(at_settle[0][4])
    return res


# ---------------------------------------------------------------------------------------------
# grainflow
# ---------------------------------------------------------------------------------------------
def _yaml_vec(v) -> str:
    return "[" + ", ".join(F(x) for x in v) + "]"


def grainflow_case(geo: Geometry, end_time: float, checkpoint_every: float, outdir: str,
                   jitter: float, seed: int) -> str:
    """The grainflow case file (keys per docs of record, DESIGN.md "The case file")."""
    L, H, top = geo.side, geo.height, geo.lattice_top
    jit = f", velocity_jitter: {F(jitter)}, seed: {seed}" if jitter > 0 else ""
    return f"""\
# terrain settling benchmark, N = {geo.n} ({geo.n_xy} x {geo.n_xy} x {geo.n_z} simple cubic)
name: terrain_settling_{geo.n}
dimension: 3
time: {{step: {F(DT)}, end: {F(end_time)}}}
domain: {{min: [0.0, 0.0, 0.0], max: {_yaml_vec([L, L, H])}, periodic: [false, false, false]}}
gravity: [0.0, 0.0, {F(-GRAVITY)}]
materials:
  glass: {{density: {F(DENSITY)}, youngs_modulus: {F(YOUNGS)}, poisson_ratio: {F(POISSON)}}}
contacts:
  - between: [glass, glass]
    model: hertz_mindlin
    restitution: {F(RESTITUTION)}
    friction: {F(FRICTION)}
    rolling_friction: 0.0
particles:
  - shape: sphere
    radius: {F(RADIUS)}
    material: glass
    fill: {{box: {{min: [0.0, 0.0, 0.0], max: {_yaml_vec([L, L, top])}}}, lattice: cubic, spacing: {F(SPACING)}, count: {geo.n}{jit}}}
walls:
  - {{name: box, box: {{min: [0.0, 0.0, 0.0], max: {_yaml_vec([L, L, H])}, open: [zmax]}}, material: glass}}
neighbor: {{skin: {F(SKIN)}}}
output:
  directory: {outdir}
  series: {{every: {F(SERIES_EVERY)}, quantities: [kinetic_energy, max_z, coordination_number]}}
  checkpoint: {{every: {F(checkpoint_every)}}}
"""


def grainflow_version(exe: str) -> str:
    try:
        p = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30)
        line = (p.stdout or p.stderr).strip().splitlines()
        return line[0] if p.returncode == 0 and line else "unknown"
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"


def _grainflow_one(exe: str, case: Path, out: Path, threads: int, restart: Path | None,
                   tag: str, args) -> tuple[Proc, dict | None, str | None]:
    cmd = [exe, "run", case.name, "--output", out.name, "--overwrite", "--threads", str(threads)]
    if restart is not None:
        cmd += ["--restart", str(restart)]
    proc = run_timed(cmd, case.parent, tag, args.timeout, threads=threads)
    summ = out / "summary.json"
    if proc.rc != 0:
        return proc, None, f"exit {proc.rc}: " + _tail(proc.stderr or proc.stdout)
    if not summ.exists():
        return proc, None, "no summary.json written"
    try:
        return proc, json.loads(summ.read_text()), None
    except json.JSONDecodeError as e:
        return proc, None, f"summary.json unreadable: {e}"


def run_grainflow(exe: str | None, geo: Geometry, settle_steps: int, dense_steps: int,
                  threads: int, workdir: Path, args) -> dict:
    res = {"code": "grainflow", "ok": False, "version": "n/a"}
    if exe is None:
        res["why"] = f"binary not found ({args.grainflow})"
        return res
    built = _dt.datetime.fromtimestamp(Path(exe).stat().st_mtime).strftime("%Y-%m-%d %H:%M")
    res["version"] = grainflow_version(exe)
    res["built"] = built
    workdir.mkdir(parents=True, exist_ok=True)
    settle_end = settle_steps * DT
    dense_end = (settle_steps + dense_steps) * DT
    (workdir / "settle.yaml").write_text(
        grainflow_case(geo, settle_end, settle_end, "settle", args.jitter, args.seed))
    # Dense run: same case, longer end time; no periodic checkpoints inside the timed loop.
    (workdir / "dense.yaml").write_text(
        grainflow_case(geo, dense_end, 0.0, "dense", args.jitter, args.seed))

    p1, s1, why = _grainflow_one(exe, workdir / "settle.yaml", workdir / "settle", threads,
                                 None, "settle", args)
    if why:
        res["why"] = "settle run: " + why
        return res
    ckpt = last_checkpoint(workdir / "settle")
    if ckpt is None:
        res["why"] = "settle run wrote no checkpoint"
        return res
    p2, s2, why = _grainflow_one(exe, workdir / "dense.yaml", workdir / "dense", threads,
                                 ckpt, "dense", args)
    if why:
        res["why"] = "dense run: " + why
        return res
    res.update(ok=True, n=int(s1.get("n_particles", geo.n)), n_end=int(s2.get("n_particles", 0)))
    res["phases"] = {
        "settle": {"steps": int(s1["steps"]), "seconds": float(s1["loop_seconds"]),
                   "load": p1.load, "cpu_share": p1.cpu_share,
                   "reported_rate": s1.get("particle_steps_per_second")},
        "dense": {"steps": int(s2["steps"]), "seconds": float(s2["loop_seconds"]),
                  "load": p2.load, "cpu_share": p2.cpu_share,
                  "reported_rate": s2.get("particle_steps_per_second")},
    }
    res["phases"]["settle"]["loop_fraction"] = float(s1["loop_seconds"]) / max(p1.wall, 1e-9)
    res["phases"]["dense"]["loop_fraction"] = float(s2["loop_seconds"]) / max(p2.wall, 1e-9)
    # Peak memory: the larger of the two processes (the restart one holds the dense state).
    rss = [x for x in (p1.maxrss_bytes, p2.maxrss_bytes) if x]
    res["maxrss"] = max(rss) if rss else None
    res["cpu"] = f"{p1.cpu_percent}/{p2.cpu_percent}"
    res["summary_peak_rss"] = [s1.get("peak_rss_bytes"), s2.get("peak_rss_bytes")]
    res["stages"] = {"settle": s1.get("stages"), "dense": s2.get("stages")}
    res["threads_reported"] = s2.get("threads")
    res["neighbor_builds"] = [s1.get("neighbor_builds"), s2.get("neighbor_builds")]
    if res["version"] == "unknown" and s1.get("program"):
        res["version"] = s1["program"]
    res["version"] += f" (binary of {built})"
    last = _last_series_row(workdir / "settle" / "series.csv")
    if last:
        res["series_end"] = last
    if res["phases"]["dense"]["steps"] != dense_steps:
        res["note"] = (f"dense run did {res['phases']['dense']['steps']} steps "
                       f"(asked {dense_steps}; restart step counting?)")
    return res


def _last_series_row(path: Path) -> dict | None:
    """The last row of grainflow's series.csv as {column: value} (None if unreadable)."""
    try:
        lines = [l for l in path.read_text().splitlines() if l.strip()]
        head, last = lines[0].split(","), lines[-1].split(",")
        return {k: float(v) for k, v in zip(head, last)} if len(lines) > 1 else None
    except (OSError, ValueError, IndexError):
        return None


def _tail(text: str, n: int = 3) -> str:
    lines = [l for l in text.strip().splitlines() if l.strip()]
    return " | ".join(lines[-n:])[:400] if lines else "(no output)"


# ---------------------------------------------------------------------------------------------
# Driver
# ---------------------------------------------------------------------------------------------
def rate(n: int, phase: dict) -> float:
    return n * phase["steps"] / phase["seconds"] if phase["seconds"] > 0 else float("nan")


def fmt_rate(x) -> str:
    return "n/a" if x is None or x != x else f"{x:.3g}"


def resolve_exe(path: str) -> str | None:
    """An executable file given by path, or else a program name looked up on the PATH."""
    p = Path(path)
    return str(p) if p.is_file() and os.access(p, os.X_OK) else shutil.which(path)


def lscpu_model() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        m = re.search(r"Model name:\s*(.+)", out)
        return m.group(1).strip() if m else platform.processor()
    except OSError:
        return platform.processor() or "unknown"


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="See bench/terrain_settling/README.md.")
    ap.add_argument("--sizes", default="10000,50000,200000",
                    help="comma-separated target particle counts (default %(default)s)")
    ap.add_argument("--settle-time", default="0.6",
                    help="simulated settling time in s; one value, or one per size "
                         "(comma-separated), the same for both codes (default %(default)s)")
    ap.add_argument("--dense-steps", type=int, default=5000,
                    help="steps of the dense phase (default %(default)s)")
    ap.add_argument("--threads", type=int, default=1,
                    help="grainflow --threads N vs mpirun -np N liggghts (default 1)")
    ap.add_argument("--codes", default="liggghts,grainflow",
                    help="which codes to run (default %(default)s)")
    ap.add_argument("--grainflow", default=str(ROOT / "build" / "release" / "grainflow"),
                    help="grainflow binary (default build/release/grainflow)")
    ap.add_argument("--liggghts", default="liggghts", help="LIGGGHTS binary (default liggghts)")
    ap.add_argument("--mpirun-args", default="--allow-run-as-root --oversubscribe --bind-to none",
                    help="extra mpirun arguments when --threads > 1 (default '%(default)s')")
    ap.add_argument("--jitter", type=float, default=0.05,
                    help="uniform random initial velocity amplitude per component, m/s, to break "
                         "the lattice symmetry (default %(default)s)")
    ap.add_argument("--seed", type=int, default=1, help="random seed for the kick")
    ap.add_argument("--no-baseline", action="store_true",
                    help="skip the tiny-N memory baseline runs")
    ap.add_argument("--wait-quiet", type=float, default=None, metavar="LOAD",
                    help="before each process, wait until the 1-minute load average is below LOAD "
                         "(at most --wait-max s)")
    ap.add_argument("--wait-max", type=float, default=900.0,
                    help="longest wait for --wait-quiet, s (default %(default)s)")
    add_run_args(ap, timeout=3600.0)
    return ap.parse_args(argv)


def add_run_args(ap, timeout: float = 600.0) -> None:
    """The options every peer script shares: a per-process limit, keeping the run folders, and
    where (and whether) the dated results section is recorded."""
    ap.add_argument("--timeout", type=float, default=timeout,
                    help="per-process time limit in s (default %(default)s)")
    ap.add_argument("--keep", action="store_true",
                    help="keep the run folders under bench/runs/<timestamp>/")
    ap.add_argument("--results", default=str(BENCH / "RESULTS.md"),
                    help="file to append the dated section to (default bench/RESULTS.md)")
    ap.add_argument("--no-record", action="store_true", help="do not append to RESULTS.md")
    ap.add_argument("--note", default="", help="free text added to the RESULTS.md section")


def main(argv=None) -> int:
    args = parse_args(argv)
    QUIET.update(load=args.wait_quiet, max_wait=args.wait_max)
    sizes = [int(float(s)) for s in args.sizes.split(",") if s.strip()]
    st = [float(s) for s in args.settle_time.split(",") if s.strip()]
    if len(st) not in (1, len(sizes)):
        sys.exit("--settle-time: give one value or one per size")
    settle_times = st * len(sizes) if len(st) == 1 else st
    codes = {c.strip().lower() for c in args.codes.split(",")}
    if not Path("/usr/bin/time").exists():
        sys.exit("/usr/bin/time missing: apt-get install -y time")

    lig = shutil.which(args.liggghts) if "liggghts" in codes else None
    if "liggghts" in codes and lig is None:
        print(f"warning: LIGGGHTS binary '{args.liggghts}' not found", file=sys.stderr)
    gf = None
    if "grainflow" in codes:
        p = Path(args.grainflow)
        gf = str(p) if p.is_file() and os.access(p, os.X_OK) else shutil.which(args.grainflow)

    t_r = rayleigh_time()
    print(f"dt = {DT:g} s = {DT / t_r:.3f} x Rayleigh time ({t_r:.3e} s); must be < 0.15")
    assert DT < 0.15 * t_r

    stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    if args.keep:
        root = BENCH / "runs" / f"terrain_settling-{stamp}"
        root.mkdir(parents=True, exist_ok=True)
    else:
        root = Path(tempfile.mkdtemp(prefix="gf-bench-"))
    print(f"run folders: {root}" + ("" if args.keep else " (removed at the end; --keep keeps)"))

    # Memory baseline: the same code with a tiny N.
    baseline = {}
    if not args.no_baseline:
        g0 = choose_geometry(BASELINE_N)
        for name, exe in (("LIGGGHTS", lig), ("grainflow", gf)):
            if exe is None:
                continue
            fn = run_liggghts if name == "LIGGGHTS" else run_grainflow
            r = fn(exe, g0, BASELINE_STEPS, BASELINE_STEPS, args.threads,
                   root / "baseline" / name, args)
            baseline[name] = r.get("maxrss") if r["ok"] else None
            print(f"baseline {name} (N = {g0.n}): "
                  + (f"{baseline[name] / 2**20:.1f} MiB" if baseline[name] else
                     f"failed: {r.get('why')}"))

    rows, results = [], []
    for target, t_settle in zip(sizes, settle_times):
        geo = choose_geometry(target)
        settle_steps = round(t_settle / DT)
        print(f"\nN = {geo.n} ({geo.n_xy} x {geo.n_xy} x {geo.n_z}), box {geo.side:.4f} m square, "
              f"settle {t_settle:g} s = {settle_steps} steps, dense {args.dense_steps} steps, "
              f"load now {os.getloadavg()[0]:.2f}", flush=True)
        per = {}
        if "liggghts" in codes:
            if lig:
                per["LIGGGHTS"] = run_liggghts(lig, geo, settle_steps, args.dense_steps,
                                               args.threads, root / f"N{geo.n}" / "liggghts", args)
            else:
                per["LIGGGHTS"] = {"code": "LIGGGHTS", "ok": False, "why": "binary not found"}
        if "grainflow" in codes:
            per["grainflow"] = run_grainflow(gf, geo, settle_steps, args.dense_steps, args.threads,
                                             root / f"N{geo.n}" / "grainflow", args)
        for name, r in per.items():
            if r["ok"]:
                extra = ""
                if "coord_end" in r:
                    extra = (f", after settling: coordination {r['coord_end']:.3f}, "
                             f"KE {r['ke_end']:.2e} J, max z {r['zmax_end']:.4f} m")
                elif r.get("series_end"):
                    e = r["series_end"]
                    extra = (f", after settling: coordination "
                             f"{e.get('coordination_number', float('nan')):.3f}, "
                             f"KE {e.get('kinetic_energy', float('nan')):.2e} J, "
                             f"max z {e.get('max_z', float('nan')):.4f} m")
                if r.get("n_end") and r["n_end"] != r["n"]:
                    extra += f", LOST {r['n'] - r['n_end']} particles"
                print(f"  {name}: ok{extra}" + (f" ({r['note']})" if r.get("note") else ""))
            else:
                print(f"  {name}: n/a ({r.get('why')})")
        results.append({"geo": geo, "settle_time": t_settle, "per": per})
        for phase in ("settle", "dense"):
            ref = per.get("LIGGGHTS")
            ref_rate = rate(ref["n"], ref["phases"][phase]) if ref and ref["ok"] else None
            for name in ("LIGGGHTS", "grainflow"):
                r = per.get(name)
                if r is None:
                    continue
                row = {"N": geo.n, "code": name, "phase": phase, "steps": None, "seconds": None,
                       "rate": None, "ratio": None, "bpp_raw": None, "bpp_net": None,
                       "load": None, "cpu": r.get("cpu"), "share": None, "rate_cpu": None}
                if r["ok"]:
                    ph = r["phases"][phase]
                    row.update(steps=ph["steps"], seconds=ph["seconds"], rate=rate(r["n"], ph),
                               load=ph["load"], share=ph.get("cpu_share"))
                    # Only meaningful when the time loop is most of the process's life.
                    if row["share"] and ph.get("loop_fraction", 0) >= 0.8:
                        row["rate_cpu"] = row["rate"] / row["share"]
                    if name == "grainflow" and ref_rate:
                        row["ratio"] = row["rate"] / ref_rate
                    elif name == "LIGGGHTS":
                        row["ratio"] = 1.0
                    if r.get("maxrss"):
                        row["bpp_raw"] = r["maxrss"] / r["n"]
                        if baseline.get(name):
                            row["bpp_net"] = (r["maxrss"] - baseline[name]) / r["n"]
                rows.append(row)

    table = format_table(rows)
    print("\n" + table)
    meta = {
        "date": _dt.datetime.now().astimezone().isoformat(timespec="seconds"),
        "cpu": lscpu_model(), "cores": os.cpu_count(),
        "liggghts": next((r["per"]["LIGGGHTS"].get("version") for r in results
                          if "LIGGGHTS" in r["per"]), "not run"),
        "grainflow": next((r["per"]["grainflow"].get("version") for r in results
                           if "grainflow" in r["per"] and r["per"]["grainflow"]["ok"]),
                          "n/a" if "grainflow" in codes else "not run"),
        "baseline": baseline,
    }
    if args.keep:
        (root / "results.json").write_text(json.dumps(
            {"meta": meta, "rows": rows, "args": vars(args)}, indent=2, default=str))
    if not args.no_record:
        append_results(Path(args.results), meta, args, results, table, gf)
    if not args.keep:
        shutil.rmtree(root, ignore_errors=True)
    return 0


def format_table(rows: list[dict]) -> str:
    head = ("| N | code | phase | steps | loop s | particle-steps/s | gf/LIGGGHTS | "
            "bytes/particle raw | bytes/particle net | load (start/mean/max) | CPU share | "
            "particle-steps/CPU-s (approx.) |")
    out = [head, "|" + "---|" * head.count(" | ") + "---|"]
    for r in rows:
        ld = r["load"]
        load = f"{ld['start']:.2f}/{ld['mean']:.2f}/{ld['max']:.2f}" if ld else "n/a"
        out.append("| " + " | ".join([
            str(r["N"]), r["code"], r["phase"],
            str(r["steps"]) if r["steps"] else "n/a",
            f"{r['seconds']:.2f}" if r["seconds"] else "n/a",
            fmt_rate(r["rate"]),
            f"{r['ratio']:.2f}" if r["ratio"] else "n/a",
            f"{r['bpp_raw']:.0f}" if r["bpp_raw"] else "n/a",
            f"{r['bpp_net']:.0f}" if r["bpp_net"] else "n/a",
            load, f"{r['share']:.2f}" if r["share"] else "n/a",
            fmt_rate(r["rate_cpu"])]) + " |")
    return "\n".join(out)


def append_results(path: Path, meta: dict, args, results: list, table: str, gf) -> None:
    lines = [
        "", f"## terrain_settling — {meta['date']}", "",
        f"- Machine: {meta['cpu']}, {meta['cores']} cores (`lscpu`), "
        f"load average at the end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
        f"- LIGGGHTS: {meta['liggghts']}; grainflow: {meta['grainflow']}"
        + ("" if gf else " (binary not found)"),
        f"- Threads/ranks: {args.threads} ("
        + ("serial, OMP_NUM_THREADS=1" if args.threads == 1 else
           f"grainflow --threads {args.threads} vs mpirun -np {args.threads} liggghts") + "); "
        "double precision; Hertz-Mindlin with tangential history, no rolling friction",
        f"- dt {DT:g} s ({DT / rayleigh_time():.3f} t_R), skin {SKIN:g} m, "
        f"kick +-{args.jitter:g} m/s, dense phase {args.dense_steps} steps; settle times: "
        + ", ".join(f"N {r['geo'].n}: {r['settle_time']:g} s" for r in results),
        "- Memory baseline (tiny N = "
        + f"{BASELINE_N}): " + (", ".join(f"{k} {v / 2**20:.1f} MiB" for k, v in
                                         meta["baseline"].items() if v) or "none"),
    ]
    for r in results:
        for name, x in r["per"].items():
            if not x["ok"]:
                lines.append(f"- N {r['geo'].n} {name}: n/a — {x.get('why')}")
            elif x.get("neighs") is not None:
                lines.append(f"- N {r['geo'].n} {name}: {x['neighs']:.2f} neighbours/atom at the "
                             f"end; after settling KE (translational) {x.get('ke_end', float('nan')):.2e} J, "
                             f"max z {x.get('zmax_end', float('nan')):.4f} m, "
                             f"coordination {x.get('coord_end', float('nan')):.3f}")
            elif x.get("series_end"):
                e = x["series_end"]
                lines.append(f"- N {r['geo'].n} {name}: after settling KE "
                             f"{e.get('kinetic_energy', float('nan')):.2e} J, max z "
                             f"{e.get('max_z', float('nan')):.4f} m, coordination "
                             f"{e.get('coordination_number', float('nan')):.3f}; neighbour builds "
                             f"(settle, dense as reported) {x.get('neighbor_builds')}; "
                             f"summary peak RSS {x.get('summary_peak_rss')}")
    append_section(path, lines, args.note, ["", table, ""])


if __name__ == "__main__":
    sys.exit(main())
