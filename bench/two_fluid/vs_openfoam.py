#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""grainflow's two-fluid model against OpenFOAM's twoPhaseEulerFoam on the same bubbling bed, in the same run.

cases/two_fluid/bubbling_bed (20 x 60 cells, 0.5 mm glass beads in air, a central jet), run by
grainflow as shipped (only time.end and output.vtk_every changed: snapshots every --write
seconds, as OpenFOAM writes its fields) and by twoPhaseEulerFoam on the case openfoam_case.py
writes from the same case file, for the same simulated time, one thread each, one after the other.

Prints the wall time of each process and their ratio, the wall time per simulated second, the
time steps and cell-steps per second (cells x steps / wall time of the process; OpenFOAM does 3
PIMPLE outer corrections per step, grainflow one pass), the CPU time and CPU share of each, and a
physics cross-check: the pressure drop between the centres of the bottom and top cell rows
(grainflow's series `pressure_drop`; OpenFOAM: volume averages of p over the two rows, every
step), the bed height (the level below which 95 % of the solids lie: grainflow's `bed_height`;
OpenFOAM: from alpha.particles written every --write s, by the same rule) and the largest solids
fraction, as means over each fifth of the run and over [--skip, --end], next to the bed's weight
per unit area (what a fully fluidised bed's pressure drop equals).

    /usr/bin/python3 bench/two_fluid/vs_openfoam.py [--grainflow build/release/grainflow]
        [--end 1.0] [--skip 0.2] [--write 0.01] [--fixed-dt S] [--keep] [--append]

Needs Debian's `openfoam` (scripts/setup-debian.sh --bench) and `python3-yaml`. blockMesh,
topoSet, setFields and writeCellCentres are not timed. A missing or failing code gives n/a rows.
`--append` adds a dated section to bench/RESULTS-two_fluid.md.
"""
import argparse, datetime, os, re, resource, shutil, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import openfoam_case  # noqa: E402

NAN = float("nan")
OPENFOAM_BASHRC = "/usr/share/openfoam/etc/bashrc"


def machine():
    model, cores = "n/a", str(os.cpu_count())
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return model, cores


def openfoam_env():
    """The environment twoPhaseEulerFoam runs in: Debian's binaries are on PATH and need only
    WM_PROJECT_DIR (as bench/cfd_dem/vs_openfoam.py); otherwise the environment of OpenFOAM's
    bashrc. None when twoPhaseEulerFoam is not found."""
    env = dict(os.environ, WM_PROJECT_DIR=os.environ.get("WM_PROJECT_DIR", "/usr/share/openfoam"))
    if shutil.which("twoPhaseEulerFoam", path=env.get("PATH")):
        return env
    if os.path.exists(OPENFOAM_BASHRC):
        p = subprocess.run(["bash", "-c", f"source {OPENFOAM_BASHRC} >/dev/null 2>&1; env -0"],
                           capture_output=True)
        env = dict(kv.split("=", 1) for kv in p.stdout.decode().split("\0") if "=" in kv)
        if shutil.which("twoPhaseEulerFoam", path=env.get("PATH")):
            return env
    return None


def timed(cmd, **kw):
    """Runs cmd; returns (CompletedProcess, wall s, CPU s of the child)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return p, wall, cpu


def run_grainflow(grainflow, case, end, write_every, folder):
    out = os.path.join(folder, "out")
    cmd = [grainflow, "run", case, "--set", f"two_fluid.time.end={end}",
           "--set", f"two_fluid.output.vtk_every={write_every}", "--threads", "1", "-q",
           "--output", out]
    try:
        p, wall, cpu = timed(cmd, env=dict(os.environ, OMP_NUM_THREADS="1"), cwd=folder)
    except OSError as e:
        print(f"grainflow failed: {e}", file=sys.stderr)
        return None
    if p.returncode != 0:
        print(f"grainflow failed ({p.returncode}): {p.stderr[-2000:]}", file=sys.stderr)
        return None
    summary = open(os.path.join(out, "two_fluid_summary.txt")).read()
    steps = int(re.search(r"^steps (\d+)", summary, re.M).group(1))
    own_wall = float(re.search(r"^wall time ([0-9.eE+-]+) s", summary, re.M).group(1))
    series = {"time": [], "pressure_drop": [], "bed_height": [], "max_solids_fraction": []}
    with open(os.path.join(out, "two_fluid_series.csv")) as f:
        head = f.readline().strip().split(",")
        for line in f:
            v = line.strip().split(",")
            for k in series:
                series[k].append(float(v[head.index(k)]))
    dp = list(zip(series["time"], series["pressure_drop"]))[1:]  # t = 0: no flow solved yet
    return {"wall": wall, "cpu": cpu, "own_wall": own_wall, "steps": steps, "dp": dp,
            "height": list(zip(series["time"], series["bed_height"])),
            "amax": list(zip(series["time"], series["max_solids_fraction"]))}


def read_internal(path):
    text = open(path).read()
    m = re.search(r"internalField\s+nonuniform\s+List<(\w+)>\s*(\d+)\s*\((.*)\)\s*;", text, re.S)
    if m:
        if m.group(1) == "vector":
            return [tuple(float(x) for x in v.split()) for v in re.findall(r"\(([^()]*)\)", m.group(3))]
        return [float(x) for x in m.group(3).split()]
    m = re.search(r"internalField\s+uniform\s+([0-9.eE+-]+)\s*;", text)
    return float(m.group(1)) if m else None


def bed_height(alpha, ys, hy, ny):
    """The level (from the bottom) below which 95 % of the solids lie, by rows: grainflow's rule."""
    layer = [0.0] * ny
    for a, y in zip(alpha, ys):
        layer[min(ny - 1, int(y / hy))] += a
    total, acc = sum(layer), 0.0
    for i, add in enumerate(layer):
        if acc + add >= 0.95 * total and add > 0:
            return (i + (0.95 * total - acc) / add) * hy
        acc += add
    return NAN


def read_dat(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            rows.append((float(v[0]), float(v[1])))
    return rows


def run_openfoam(env, case, end, write_every, folder, opts):
    openfoam_case.make(folder, end, case, write_every, **opts)
    c = openfoam_case.load(case)
    try:
        for pre in (["blockMesh"], ["topoSet"], ["setFields"],
                    ["postProcess", "-func", "writeCellCentres", "-time", "0"]):
            p = subprocess.run(pre, capture_output=True, text=True, cwd=folder, env=env)
            if p.returncode != 0:
                raise RuntimeError(f"{pre[0]}: {p.stdout[-1500:]}{p.stderr[-1500:]}")
        p, wall, cpu = timed(["twoPhaseEulerFoam"], cwd=folder, env=env)
        with open(os.path.join(folder, "log.twoPhaseEulerFoam"), "w") as f:
            f.write(p.stdout + p.stderr)
        if p.returncode != 0:
            raise RuntimeError(p.stdout[-2000:] + p.stderr[-2000:])
    except (OSError, RuntimeError) as e:
        print(f"twoPhaseEulerFoam failed: {e}", file=sys.stderr)
        return None
    log = p.stdout
    steps = len(re.findall(r"^Time = ", log, re.M))
    exec_s = float(re.findall(r"ExecutionTime = ([0-9.eE+-]+) s", log)[-1])
    pp = os.path.join(folder, "postProcessing")
    bottom = read_dat(os.path.join(pp, "bottomRow", "0", "volFieldValue.dat"))
    top = read_dat(os.path.join(pp, "topRow", "0", "volFieldValue.dat"))
    dp = [(t, pb - pt) for (t, pb), (_, pt) in zip(bottom, top)]
    amax = read_dat(os.path.join(pp, "alphaMax", "0", "volFieldValue.dat"))
    ys = [v[1] - c["lo"][1] for v in read_internal(os.path.join(folder, "0", "C"))]
    hy = (c["hi"][1] - c["lo"][1]) / c["cells"][1]
    height = []
    for d in os.listdir(folder):
        if re.fullmatch(r"[0-9.eE+-]+", d) and float(d) > 0:
            a = read_internal(os.path.join(folder, d, "alpha.particles"))
            if isinstance(a, list):
                height.append((float(d), bed_height(a, ys, hy, c["cells"][1])))
    height.sort()
    return {"wall": wall, "cpu": cpu, "exec": exec_s, "steps": steps, "dp": dp, "height": height,
            "amax": amax}


def mean(series, t0, t1, weighted=False):
    """Mean of (t, v) samples with t0 < t <= t1; weighted: by the step length (OpenFOAM's steps
    vary)."""
    pts = [(t, v) for t, v in series if t0 < t <= t1 + 1e-12]
    if not pts:
        return NAN
    if not weighted:
        return sum(v for _, v in pts) / len(pts)
    num = den = 0.0
    prev = max([t for t, _ in series if t <= t0] or [t0])
    for t, v in pts:
        num += v * (t - prev)
        den += t - prev
        prev = t
    return num / den if den > 0 else NAN


def at_times(series, times):
    """The samples of series at the given times (the nearest sample within 1e-6 s)."""
    out = []
    for t in times:
        best = min(series, key=lambda s: abs(s[0] - t), default=None)
        if best is not None and abs(best[0] - t) < 1e-6:
            out.append(best)
    return out


def fmt(x, spec):
    return "n/a" if x is None or x != x else format(x, spec)


def versions(grainflow):
    v = {}
    try:
        v["grainflow"] = subprocess.run([grainflow, "--version"], capture_output=True,
                                        text=True).stdout.strip()
        v["binary"] = datetime.datetime.fromtimestamp(os.path.getmtime(grainflow)).strftime(
            "%Y-%m-%d %H:%M")
    except OSError:
        v["grainflow"] = "n/a"
    v["commit"] = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                                 capture_output=True, text=True).stdout.strip()
    v["openfoam"] = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", "openfoam"],
                                   capture_output=True, text=True).stdout.strip() or "n/a"
    return v


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--grainflow", default=os.path.join(ROOT, "build/release/grainflow"))
    ap.add_argument("--case", default=openfoam_case.CASE)
    ap.add_argument("--end", type=float, default=1.0, help="simulated time, s (default 1.0)")
    ap.add_argument("--skip", type=float, default=0.2,
                    help="start of the averaging window, s (the first bubble; default 0.2)")
    ap.add_argument("--write", type=float, default=0.01,
                    help="field / VTK snapshot interval of both codes, s (default 0.01)")
    ap.add_argument("--fixed-dt", type=float, default=None,
                    help="OpenFOAM: a fixed step (the tutorial's 2e-4) instead of maxCo 0.5, maxDeltaT 5e-4")
    ap.add_argument("--alpha-delta-min", type=float, default=0.05,
                    help="OpenFOAM: floor of alphaMax - a in the Johnson-Jackson pressure (default 0.05)")
    ap.add_argument("--keep", action="store_true", help="keep the run folders under bench/runs/")
    ap.add_argument("--append", action="store_true", help="append a section to bench/RESULTS-two_fluid.md")
    a = ap.parse_args()
    c = openfoam_case.load(a.case)
    n_cells = c["cells"][0] * c["cells"][1]
    # Weight of the bed per unit area (buoyant), and that above the centre of the first row.
    (bx0, by0), (bx1, by1) = c["bed_lo"], c["bed_hi"]
    width = c["hi"][0] - c["lo"][0]
    g = abs(c["gravity"][1])
    w_bed = c["bed_fraction"] * (c["rho_s"] - c["rho_f"]) * g * (by1 - by0) * (bx1 - bx0) / width
    hy = (c["hi"][1] - c["lo"][1]) / c["cells"][1]
    w_above = w_bed * (by1 - by0 - 0.5 * hy) / (by1 - by0)

    if a.keep:
        base = os.path.join(ROOT, "bench", "runs", "two_fluid_" + time.strftime("%Y%m%d_%H%M%S"))
        os.makedirs(base)
        tmp = None
    else:
        tmp = tempfile.TemporaryDirectory()
        base = tmp.name
    os.makedirs(f"{base}/g"), os.makedirs(f"{base}/o")
    load0 = os.getloadavg()[0]
    grainflow = os.path.abspath(a.grainflow)
    v = versions(grainflow)  # before the run: others may rebuild the binary meanwhile
    gf = run_grainflow(grainflow, os.path.abspath(a.case), a.end, a.write, f"{base}/g") \
        if os.path.exists(grainflow) else None
    load1 = os.getloadavg()[0]
    env = openfoam_env()
    if env is None:
        print("twoPhaseEulerFoam not found: scripts/setup-debian.sh --bench", file=sys.stderr)
    of = run_openfoam(env, os.path.abspath(a.case), a.end, a.write, f"{base}/o",
                      {"fixed_dt": a.fixed_dt, "alpha_delta_min": a.alpha_delta_min}) if env else None
    load2 = os.getloadavg()[0]

    def get(r, k):
        return r[k] if r else NAN

    rows = ["| code | wall s | CPU s (share) | wall s per simulated s | time steps | cell-steps/s |",
            "|---|---|---|---|---|---|"]
    for name, r in (("grainflow", gf), ("twoPhaseEulerFoam", of)):
        if r:
            rows.append(f"| {name} | {r['wall']:.2f} | {r['cpu']:.2f} ({r['cpu'] / r['wall']:.2f}) | "
                        f"{r['wall'] / a.end:.4g} | {r['steps']} | {n_cells * r['steps'] / r['wall']:.3g} |")
        else:
            rows.append(f"| {name} | n/a | n/a | n/a | n/a | n/a |")
    # The physics: means over fifths and over the window.
    g_h = at_times(gf["height"], [t for t, _ in of["height"]]) if gf and of else (gf or {}).get("height", [])
    rows += ["", f"| mean over | pressure drop, Pa: grainflow | twoPhaseEulerFoam | bed height, m: grainflow | "
                 f"twoPhaseEulerFoam | max solids fraction: grainflow | twoPhaseEulerFoam |",
             "|---|---|---|---|---|---|---|"]
    windows = [(i * a.end / 5, (i + 1) * a.end / 5) for i in range(5)] + [(a.skip, a.end)]
    summary = {}
    for t0, t1 in windows:
        vals = (mean(get(gf, "dp") if gf else [], t0, t1), mean(get(of, "dp") if of else [], t0, t1, True),
                mean(g_h, t0, t1), mean(get(of, "height") if of else [], t0, t1),
                mean(get(gf, "amax") if gf else [], t0, t1), mean(get(of, "amax") if of else [], t0, t1, True))
        label = f"{t0:.3g}-{t1:.3g} s" + (" (window)" if (t0, t1) == (a.skip, a.end) else "")
        rows.append(f"| {label} | " + " | ".join(
            fmt(v, s) for v, s in zip(vals, (".0f", ".0f", ".4f", ".4f", ".3f", ".3f"))) + " |")
        summary[(t0, t1)] = vals
    gdp, odp = summary[(a.skip, a.end)][:2]
    ratio = of["wall"] / gf["wall"] if gf and of else NAN
    text = "\n".join(rows) + (
        f"\n\nBed weight per unit area (buoyant) {w_bed:.0f} Pa, {w_above:.0f} Pa above the centre "
        f"of the first row (initial packing). Mean pressure drop over {a.skip}-{a.end} s: "
        f"grainflow {fmt(gdp, '.0f')} Pa ({fmt(gdp / w_bed, '.2f')} of the weight), "
        f"twoPhaseEulerFoam {fmt(odp, '.0f')} Pa ({fmt(odp / w_bed, '.2f')}).\n\n"
        f"twoPhaseEulerFoam / grainflow wall time for the same {a.end} s of the bed: "
        f"**{fmt(ratio, '.1f')}**; cell-steps/s grainflow / twoPhaseEulerFoam: "
        f"{fmt((gf['steps'] / gf['wall']) / (of['steps'] / of['wall']) if gf and of else NAN, '.1f')}. "
        f"grainflow's own loop time {fmt(get(gf, 'own_wall'), '.2f')} s; OpenFOAM's ExecutionTime "
        f"{fmt(get(of, 'exec'), '.2f')} s. 1 thread each, run one after the other; OpenFOAM step "
        + (f"fixed {a.fixed_dt} s" if a.fixed_dt else "adjustable (maxCo 0.5, maxDeltaT 5e-4 s)")
        + f", alphaDeltaMin {a.alpha_delta_min}; 1-minute load average {load0:.2f} -> {load1:.2f} "
          f"-> {load2:.2f}\n")
    print(text)
    if a.keep:
        print(f"run folders: {base}")
    if a.append:
        model, cores = machine()
        date = subprocess.run(["date"], capture_output=True, text=True).stdout.strip()
        lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines()
        keep = ("Architecture", "CPU(s):", "Model name", "Thread(s) per core", "Core(s) per socket",
                "Socket(s)", "Hypervisor vendor")
        lscpu = "\n".join(line for line in lscpu if line.startswith(keep))
        head = (f"\n## {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}: bubbling_bed against "
                f"OpenFOAM twoPhaseEulerFoam ({v['openfoam']}, Debian), {a.end} s\n\n"
                f"`{date}`; machine: {model}, {cores} CPUs (nproc {os.cpu_count()}; shared machine). "
                f"{v['grainflow']} (build/release binary of {v.get('binary', 'n/a')}, repository "
                f"HEAD {v['commit']}). `bench/two_fluid/vs_openfoam.py --end {a.end} --skip {a.skip}"
                + (f" --fixed-dt {a.fixed_dt}" if a.fixed_dt else "") + "`.\n\n"
                f"```\n{lscpu}\n```\n\n")
        with open(os.path.join(ROOT, "bench/RESULTS-two_fluid.md"), "a") as f:
            f.write(head + text)
    if tmp:
        tmp.cleanup()


if __name__ == "__main__":
    main()
