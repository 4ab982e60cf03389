#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Speed of non-spherical grains: particle-steps per second of grainflow on the shipped shape
cases (spherocylinders in 3D, polygons and disks in 2D), from a settled state.

Each case first runs --settle seconds of simulated time from its fill (writing a checkpoint),
then --steps further steps restarted from that checkpoint (the dense phase, where contacts
dominate); the rate is N x steps / loop wall time from summary.json, with the contact count.
No peer runs here: LIGGGHTS-PUBLIC 3.8 from Debian has no spherocylinders or polygons (its
superquadrics are not compiled in), and LAMMPS's body styles (rounded/polygon) use a different
contact model; see bench/RESULTS.md. Appends a dated section to bench/RESULTS.md unless
--no-record.

  /usr/bin/python3 bench/shapes/run.py --settle 0.3 --steps 2000
"""
from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CASES = {
    "rods_in_box (2000 spherocylinders, AR 4)": ROOT / "cases/dem/rods_in_box/case.yaml",
    "polygon_heap (600 polygons, 5-7 vertices)": ROOT / "cases/dem2d/polygon_heap/case.yaml",
    "disk_heap (600 disks)": ROOT / "cases/dem2d/disk_heap/case.yaml",
}


def run(exe, case, out, extra, threads):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_WAIT_POLICY="passive")
    cmd = [exe, "run", str(case), "--output", str(out), "--overwrite", "--quiet",
           "--threads", str(threads)] + extra
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    return json.loads((out / "summary.json").read_text())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--grainflow", default=str(ROOT / "build/release/grainflow"))
    ap.add_argument("--settle", type=float, default=0.3, help="simulated seconds before timing")
    ap.add_argument("--steps", type=int, default=2000, help="timed steps from the settled state")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--no-record", action="store_true")
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, case in CASES.items():
            tag = case.parent.name
            settle = Path(tmp) / (tag + "_settle")
            # Settle: as many steps as --settle seconds at the case's dt (read from case.yaml).
            text = case.read_text()
            step = float(text.split("step:")[1].split(",")[0])
            n_settle = int(round(a.settle / step))
            run(a.grainflow, case, settle, ["--steps", str(n_settle)], a.threads)
            ckpts = sorted(settle.glob("checkpoint_*.h5")) or sorted(settle.glob("*.h5"))
            if not ckpts:
                raise SystemExit(f"{case}: no checkpoint written by the settling run")
            dense = Path(tmp) / (tag + "_dense")
            d = run(a.grainflow, case, dense, ["--restart", str(ckpts[-1]), "--steps", str(a.steps)],
                    a.threads)
            rate = d["particle_steps_per_second"]
            rows.append((name, d["n_particles"], a.steps, rate, d.get("stages", {})))
            print(f"{name}: {rate / 1e6:.3f} million particle-steps/s ({a.threads} thread(s))")
    if a.no_record:
        return
    lines = [f"\n## shapes — {_dt.datetime.now(_dt.timezone.utc).isoformat(timespec='seconds')}\n",
             f"- Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
             f"threads {a.threads}; settle {a.settle} s then {a.steps} timed steps "
             f"(bench/shapes/run.py)\n\n",
             "| case | N | particle-steps/s (millions) | force / neighbor / integrate s |\n",
             "|---|---|---|---|\n"]
    for name, n, steps, rate, st in rows:
        lines.append(f"| {name} | {n} | {rate / 1e6:.3f} | {st.get('force', 0):.2f} / "
                     f"{st.get('neighbor', 0):.2f} / {st.get('integrate', 0):.2f} |\n")
    with open(ROOT / "bench/RESULTS.md", "a") as f:
        f.writelines(lines)


if __name__ == "__main__":
    main()
