#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""GPU scaling of the terrain-settling case: grainflow's CUDA back end against its host step.

The case of run.py (glass spheres on a cubic lattice in a box with an open top, Hertz-Mindlin
with tangential history, dt = 2e-5 s), for each size N:
  (1) settle: `--device cuda` from the lattice for --settle-steps steps, ending with a checkpoint;
  (2) dense:  --dense-steps further steps from that checkpoint, once with `--device cuda` and
              once on the host with --threads T (every core of the machine by default): the
              same state, the same steps, so the ratio is the device's speed-up on this machine.
Prints particle-steps per second (N x steps / loop wall time, from summary.json) and, with
--record, appends a dated section to bench/RESULTS.md. The seed's anchor is Chrono::GPU's linear
scaling to 250 million spheres on one P100 (DESIGN.md, headline case 1).

Example, on a machine with a GPU (from the repository root, after `cmake --preset cuda` and
`cmake --build --preset cuda`):
  /usr/bin/python3 bench/terrain_settling/gpu.py --sizes 100000,1000000 --record
  (--settle-steps and --dense-steps take one value or one per size)
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))
from bench.terrain_settling.run import (DT, append_section, choose_geometry,  # noqa: E402
                                        grainflow_case, lscpu_model)

ROOT = HERE.parent.parent


def gpu_name() -> str:
    try:
        out = subprocess.run(["nvidia-smi", "--query-gpu=name,memory.total,driver_version",
                              "--format=csv,noheader"], capture_output=True, text=True, timeout=30)
        return out.stdout.strip().splitlines()[0] if out.returncode == 0 else "unknown GPU"
    except (OSError, subprocess.TimeoutExpired, IndexError):
        return "unknown GPU"


def run(exe: str, case: Path, out: Path, device: str, threads: int, restart: Path | None,
        timeout: float) -> dict:
    cmd = [exe, "run", str(case), "--output", str(out), "--overwrite", "--quiet",
           "--device", device, "--threads", str(threads)]
    if restart is not None:
        cmd += ["--restart", str(restart)]
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()[-600:]}")
    s = json.loads((out / "summary.json").read_text())
    s["wall"] = wall
    return s


def last_series_row(out: Path) -> dict:
    """The last row of series.csv (kinetic energy, max z, coordination number at the end)."""
    lines = (out / "series.csv").read_text().strip().splitlines()
    return dict(zip(lines[0].split(","), (float(x) for x in lines[-1].split(","))))


def max_position_gap(a: Path, b: Path) -> float | None:
    """Largest |x_a - x_b| over grains matched by id in two checkpoints (None without h5py)."""
    try:
        import h5py  # not a Debian dependency of the project: optional here
        import numpy as np
    except ImportError:
        return None

    def load(path: Path):
        with h5py.File(path, "r") as f:
            ids, x = np.asarray(f["particles/id"][()]), np.asarray(f["particles/position"][()])
        if x.dtype.names:  # a compound (x, y, z) element
            x = np.stack([x[k] for k in x.dtype.names], axis=-1)
        return ids.reshape(-1), x.reshape(len(ids.reshape(-1)), -1)

    try:
        ia, xa = load(a)
        ib, xb = load(b)
    except (KeyError, OSError, ValueError) as e:
        print(f"positions not compared: {e}", file=sys.stderr)
        return None
    if len(ia) != len(ib):
        return float("inf")
    oa, ob = np.argsort(ia, kind="stable"), np.argsort(ib, kind="stable")
    if not np.array_equal(ia[oa], ib[ob]):
        return float("inf")
    return float(np.max(np.abs(xa[oa] - xb[ob])))


def rate(s: dict) -> float:
    return s["n_particles"] * s["steps"] / s["loop_seconds"] if s["loop_seconds"] > 0 else 0.0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="100000,1000000", help="target particle counts")
    ap.add_argument("--settle-steps", default="15000",
                    help="steps of the settling run: one value, or one per size")
    ap.add_argument("--dense-steps", default="2000",
                    help="steps of the dense runs: one value, or one per size")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1,
                    help="host threads of the comparison runs (default: every core)")
    ap.add_argument("--scan-threads", default="",
                    help="also time the host's dense run at these thread counts (e.g. 1,4,8): "
                         "its thread scaling on this machine")
    ap.add_argument("--grainflow", default=str(ROOT / "build" / "cuda" / "grainflow"))
    ap.add_argument("--timeout", type=float, default=1800.0)
    ap.add_argument("--device", default="cuda",
                    help="device of the settle and 'device' runs (cpu: a dry run of the script "
                         "where no GPU is)")
    ap.add_argument("--record", action="store_true", help="append to bench/RESULTS.md")
    ap.add_argument("--results", default=str(ROOT / "bench" / "RESULTS.md"))
    args = ap.parse_args(argv)

    sizes = [int(float(x)) for x in args.sizes.split(",") if x.strip()]

    def per_size(text: str, what: str) -> list[int]:
        v = [int(float(x)) for x in text.split(",") if x.strip()]
        if len(v) not in (1, len(sizes)):
            sys.exit(f"{what}: give one value or one per size")
        return v * len(sizes) if len(v) == 1 else v

    settle_steps = per_size(args.settle_steps, "--settle-steps")
    dense_steps = per_size(args.dense_steps, "--dense-steps")
    machine = f"{lscpu_model()}, {os.cpu_count()} cores; {gpu_name()}"
    print(f"machine: {machine}")
    rows = []
    with tempfile.TemporaryDirectory(prefix="gf-gpu-bench-") as tmp:
        root = Path(tmp)
        for target, n_settle, n_dense in zip(sizes, settle_steps, dense_steps):
            geo = choose_geometry(target)
            end = n_settle * DT
            case = root / f"settle_{geo.n}.yaml"
            case.write_text(grainflow_case(geo, end, end, f"settle_{geo.n}", 0.05, 1))
            dense = root / f"dense_{geo.n}.yaml"
            dense.write_text(grainflow_case(geo, end + n_dense * DT, 0.0,
                                            f"dense_{geo.n}", 0.05, 1))
            settle = run(args.grainflow, case, root / f"settle_{geo.n}", args.device, 1, None,
                         args.timeout)
            ckpt = root / f"settle_{geo.n}" / "checkpoint_final.h5"
            d_gpu = run(args.grainflow, dense, root / f"gpu_{geo.n}", args.device, 1, ckpt,
                        args.timeout)
            scan = {}
            for t in [int(x) for x in args.scan_threads.split(",") if x.strip()]:
                if t != args.threads:
                    scan[t] = rate(run(args.grainflow, dense, root / f"cpu{t}_{geo.n}", "cpu", t,
                                       ckpt, args.timeout))
            d_cpu = run(args.grainflow, dense, root / f"cpu_{geo.n}", "cpu", args.threads, ckpt,
                        args.timeout)
            row = {"n": geo.n, "settle": rate(settle), "settle_steps": settle["steps"],
                   "gpu": rate(d_gpu), "cpu": rate(d_cpu), "dense_steps": d_gpu["steps"]}
            row["ratio"] = row["gpu"] / row["cpu"] if row["cpu"] > 0 else float("nan")
            scan[args.threads] = row["cpu"]
            row["scan"] = ", ".join(f"{t}: {scan[t]:.3g} ({scan[t] / scan[min(scan)]:.2f}x)"
                                    for t in sorted(scan)) if len(scan) > 1 else ""
            # The same state, the same steps: the two ends differ only by the rounding the
            # chaotic dense bed amplifies (the unit tests pin the step itself to ~1e-15 m).
            eg, ec = last_series_row(root / f"gpu_{geo.n}"), last_series_row(root / f"cpu_{geo.n}")
            gap = max_position_gap(root / f"gpu_{geo.n}" / "checkpoint_final.h5",
                                   root / f"cpu_{geo.n}" / "checkpoint_final.h5")
            row["agree"] = (f"KE {eg['kinetic_energy']:.6g} vs {ec['kinetic_energy']:.6g} J, "
                            f"Z {eg['coordination_number']:.4f} vs {ec['coordination_number']:.4f}"
                            + ("" if gap is None else f", largest position gap {gap:.2g} m"))
            print(f"N = {geo.n}: settle (device) {row['settle']:.3g} particle-steps/s over "
                  f"{row['settle_steps']} steps; dense: device {row['gpu']:.3g}, host "
                  f"({args.threads} threads) {row['cpu']:.3g}, ratio {row['ratio']:.2f}; device vs "
                  f"host at the end: {row['agree']}"
                  + (f"; host by threads: {row['scan']}" if row["scan"] else ""),
                  flush=True)
            rows.append(row)
    if args.record and rows:
        stamp = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
        head = [f"\n## terrain_settling on the GPU — {stamp}\n",
                f"- Machine: {machine}; {platform.platform()}",
                f"- grainflow `--device cuda` vs `--device cpu --threads {args.threads}`, "
                f"double precision, dt {DT:g} s; settle = the device run from the lattice, "
                f"dense = further steps from its checkpoint (the same state for both); "
                f"particle-steps per second", ""]
        body = ["| N | settle steps | settle, device | dense steps | dense, device | dense, host "
                "| device / host | end of dense: device vs host |", "|---|---|---|---|---|---|---|---|"]
        body += [f"| {r['n']} | {r['settle_steps']} | {r['settle']:.3g} | {r['dense_steps']} | "
                 f"{r['gpu']:.3g} | {r['cpu']:.3g} | {r['ratio']:.1f} | {r['agree']} |"
                 for r in rows]
        body += [f"- Host dense run by threads, N = {r['n']} (particle-steps/s, speed-up over the "
                 f"fewest): {r['scan']}" for r in rows if r["scan"]]
        append_section(Path(args.results), head, None, body + [""])
    return 0


if __name__ == "__main__":
    sys.exit(main())
