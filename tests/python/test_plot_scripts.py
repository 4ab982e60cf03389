#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs every plot script into a temporary folder: each writes its PNG files and nothing else, and
# nothing lands in docs/validation.
"""Test of the plot scripts (scripts/plot_*.py, scripts/rheology_windows.py,
docs/validation/make_plots.py) with Debian's python3-numpy and python3-matplotlib.

Usage (how CTest calls it):

    /usr/bin/python3 tests/python/test_plot_scripts.py GRAINFLOW_BINARY SOURCE_DIR

Checks:
- scripts/rheology_windows.py on the rheology.csv of a short lees_edwards_spheres run continued
  once with --restart (both files given): four windows of five samples, the CFD-DEM columns
  (fluid and slip temperature) kept, --csv appends with one header and the --label; on synthetic
  tables: windows of width 0.1 hold ten samples each (no drift of the bounds), a later file's
  samples replace an earlier file's at the same strain, a table without samples exits non-zero;
- scripts/plot_sweep.py on the committed dry rod table (prefix "rheology_rods_" gives
  rheology_rods_*.png, alignment included), with --only contacts on the committed rod table
  that has the contact columns (that figure alone), and on the sweep.csv of a short `grainflow sweep` of
  spheres (no alignment plot; the contacts plot from its coordination and fabric columns; between
  Lees-Edwards images no momentum-balance plot), with --only momentum_balance on that of a
  short sweep between walls;
- scripts/plot_force_chains.py on the contacts_*.vtp of a short run between walls
  (output.contacts_vtk);
- scripts/plot_dem_vs_continuum.py on the committed mu(I), collapse, deposit and dam-break tables;
- scripts/plot_cfd_dem.py --shear on the committed dry / air / water tables, --slip on the
  committed windows table and on the windows of the run above;
- where BUILD_DIR/tests/gf_validation_tests exists (BUILD_DIR: the folder of GRAINFLOW_BINARY),
  the modes that run it: plot_cfd_dem.py BUILD_DIR, plot_drag.py, plot_fluid_fv.py and
  make_plots.py, plot_momentum_balance.py (seconds each on one core), plot_rheology_spheres.py
  (45 s), plot_continuum.py (25 s), plot_two_fluid.py (15 s).
Every script is given --out (or its output folder) as a folder that does not exist yet, must
exit 0 and write exactly the expected files, each a non-empty PNG; docs/validation (names, sizes,
modification times) is the same afterwards. The scripts run at most os.cpu_count() at a time.

Exit codes: 0 passed, 1 a check failed, 2 bad usage, 77 skipped (numpy/matplotlib not importable).
"""

import concurrent.futures
import csv
import os
import subprocess
import sys
import tempfile
import time

SKIP = 77
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import Checks  # noqa: E402

check = Checks()


def snapshot(folder):
    """Every file under folder with its size and modification time."""
    files = {}
    for root, _, names in os.walk(folder):
        for n in names:
            p = os.path.join(root, n)
            st = os.stat(p)
            files[os.path.relpath(p, folder)] = (st.st_size, st.st_mtime_ns)
    return files


def run(argv, cwd):
    # (the slowest, plot_continuum.py, takes ~2 min alone on one core; 10 min leaves room for a
    # loaded machine)
    return subprocess.run(argv, capture_output=True, text=True, cwd=cwd, env=ENV, timeout=600)


def script(*args):
    return [sys.executable, *args]


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def write_table(path, strains, value):
    """A rheology.csv of the columns rheology_windows.py needs, every quantity equal to value."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "strain"] + QUANTITIES)
        for s in strains:
            w.writerow([s, f"{s:.10g}"] + [value] * len(QUANTITIES))


def check_pngs(name, folder, expected):
    """folder holds exactly the expected files, each a non-empty PNG."""
    found = sorted(os.listdir(folder)) if os.path.isdir(folder) else []
    check(found == sorted(expected), f"{name}: wrote {found}, expected {sorted(expected)}")
    for f in expected:
        p = os.path.join(folder, f)
        head = open(p, "rb").read(8) if os.path.isfile(p) else b""
        check(head == PNG_SIGNATURE and os.path.getsize(p) > 1000,
              f"{name}: {f} is a non-empty PNG")


if len(sys.argv) != 3:
    print(__doc__)
    sys.exit(2)
try:
    import matplotlib  # noqa: F401
    import numpy  # noqa: F401
except ImportError as e:
    print(f"skipped: {e}")
    sys.exit(SKIP)

GF = os.path.abspath(sys.argv[1])
SRC = os.path.abspath(sys.argv[2])
SCRIPTS = os.path.join(SRC, "scripts")
VALIDATION = os.path.join(SRC, "docs", "validation")
VALIDATION_TESTS = os.path.join(os.path.dirname(GF), "tests", "gf_validation_tests")
LEES_EDWARDS = os.path.join(SRC, "cases", "rheology", "lees_edwards_spheres", "case.yaml")
WALL_BOX = os.path.join(SRC, "cases", "rheology", "shear_box_spheres", "case.yaml")
# Samples every 20 steps (strain 0.001 at 100 1/s, dt = 5e-7 s).
SAMPLES = ["--set", "analysis.rheology.every_strain=0.001"]
QUANTITIES = ["granular_temperature", "pressure", "sigma_xz", "order_parameter",
              "alignment_angle", "volume_fraction", "shear_rate"]
ENV = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"), MPLBACKEND="Agg")

start = time.monotonic()
before = snapshot(VALIDATION)
with tempfile.TemporaryDirectory() as TMP:
    plots = os.path.join(TMP, "plots")  # every script's output folder is created below it

    # --- rheology_windows.py on a run and its continuation ---
    r = run([GF, "run", LEES_EDWARDS, "--output", "a", "--quiet", "--threads", "1",
             "--steps", "200", *SAMPLES], TMP)
    check(r.returncode == 0, f"lees_edwards_spheres, 200 steps: {r.stderr}")
    r = run([GF, "run", LEES_EDWARDS, "--output", "b", "--quiet", "--threads", "1",
             "--steps", "200", "--restart", os.path.join("a", "checkpoint_final.h5"), *SAMPLES],
            TMP)
    check(r.returncode == 0, f"lees_edwards_spheres continued 200 steps: {r.stderr}")
    windows = os.path.join(TMP, "windows.csv")
    r = run(script(os.path.join(SCRIPTS, "rheology_windows.py"), "--width", "0.005",
                   "--csv", windows, "--label", "phi_0.1_rate_100",
                   os.path.join("a", "rheology.csv"), os.path.join("b", "rheology.csv")), TMP)
    check(r.returncode == 0, f"rheology_windows.py: {r.stderr}")
    rows = read_rows(windows) if os.path.exists(windows) else [[]]
    check(rows[0][:4] == ["run", "strain_from", "strain_to", "samples"]
          and rows[0][-2:] == ["fluid_temperature", "slip_temperature"],
          f"rheology_windows.py --csv header: {rows[0]}")
    check([(row[0], row[3]) for row in rows[1:]] == [("phi_0.1_rate_100", "5")] * 4,
          f"two files of ten samples give four windows of five: {rows[1:]}")
    check(len(r.stdout.splitlines()) == 5, f"rheology_windows.py prints a header and 4 rows:\n"
          f"{r.stdout}")
    r = run(script(os.path.join(SCRIPTS, "rheology_windows.py"), "--width", "0.01", "--csv",
                   windows, "--label", "phi_0.1_rate_100", os.path.join("a", "rheology.csv")),
            TMP)
    rows = read_rows(windows)
    check(r.returncode == 0 and len(rows) == 6 and rows[0][0] == "run"
          and rows[5][:4] == ["phi_0.1_rate_100", "0", "0.01", "10"],
          f"--csv appends to an existing table without a second header: {rows}")

    # Synthetic tables: bounds of width 0.1, a continuation that repeats strains, no samples.
    write_table(os.path.join(TMP, "first.csv"), [i * 0.01 for i in range(1, 61)], 1.0)
    write_table(os.path.join(TMP, "second.csv"), [i * 0.01 for i in range(51, 101)], 2.0)
    synthetic = os.path.join(TMP, "synthetic.csv")
    r = run(script(os.path.join(SCRIPTS, "rheology_windows.py"), "--width", "0.1",
                   "--csv", synthetic, "first.csv", "second.csv"), TMP)
    rows = read_rows(synthetic) if os.path.exists(synthetic) else [[]]
    check(r.returncode == 0 and [row[3] for row in rows[1:]] == ["10"] * 10,
          f"100 samples, width 0.1: ten windows of ten samples: {rows}")
    check(len(rows) == 11 and [float(row[4]) for row in rows[1:]] == [1.0] * 5 + [2.0] * 5,
          f"the later file's samples replace the earlier file's: {rows}")
    write_table(os.path.join(TMP, "empty.csv"), [], 1.0)
    r = run(script(os.path.join(SCRIPTS, "rheology_windows.py"), "empty.csv"), TMP)
    check(r.returncode != 0 and "no samples" in r.stderr,
          f"a table without samples is an error: {r.returncode} {r.stderr}")

    # A short sweep of spheres: the table as `grainflow sweep` writes it now.
    r = run([GF, "sweep", LEES_EDWARDS, "--output", "sweep", "--no-plots", "-j", "1",
             "--steps", "100", *SAMPLES, "--set", "sweep.volume_fraction=[0.1, 0.2]",
             "--set", "sweep.shear_rate=[50, 100]"], TMP)
    check(r.returncode == 0, f"grainflow sweep of four short runs: {r.stderr}")
    # ... and between walls (the walls' tractions: the momentum-balance figure).
    r = run([GF, "sweep", WALL_BOX, "--output", "sweep_walls", "--no-plots", "-j", "1",
             "--steps", "200", *SAMPLES, "--set", "sweep.volume_fraction=[0.1, 0.2]",
             "--set", "sweep.shear_rate=[100]"], TMP)
    check(r.returncode == 0, f"grainflow sweep of two short runs between walls: {r.stderr}")
    # ... and a short run between walls that writes its contact network as VTK lines.
    r = run([GF, "run", WALL_BOX, "--output", "chains", "--quiet", "--threads", "1",
             "--steps", "200", "--set", "particles[0].fill.volume_fraction=0.3",
             "--set", "output.contacts_vtk.every=1.0e-4"], TMP)
    check(r.returncode == 0, f"shear_box_spheres with contacts_vtk, 200 steps: {r.stderr}")

    # --- the plots: (name, command, output folder, expected files) ---
    def out(name):
        return os.path.join(plots, name)

    def table(name):
        return os.path.join(VALIDATION, name)

    rods = ["rheology_rods_stresses.png", "rheology_rods_friction_normal_stress.png",
            "rheology_rods_alignment.png"]
    jobs = [
        ("plot_sweep.py (dry rods)",
         script(os.path.join(SCRIPTS, "plot_sweep.py"), table("cfd_dem_shear_box_dry.csv"),
                out("sweep_rods"), "rheology_rods_"), out("sweep_rods"), rods),
        ("plot_sweep.py --only contacts (committed rod table with contacts)",
         script(os.path.join(SCRIPTS, "plot_sweep.py"), table("rheology_rods_contacts.csv"),
                out("sweep_contacts"), "rheology_rods_", "--only", "contacts"),
         out("sweep_contacts"), ["rheology_rods_contacts.png"]),
        ("plot_sweep.py --only momentum_balance (fresh sweep between walls)",
         script(os.path.join(SCRIPTS, "plot_sweep.py"),
                os.path.join(TMP, "sweep_walls", "sweep.csv"), out("sweep_walls"), "--only",
                "momentum_balance"), out("sweep_walls"), ["rheology_momentum_balance.png"]),
        ("plot_force_chains.py (the network of the run above)",
         script(os.path.join(SCRIPTS, "plot_force_chains.py"),
                os.path.join(TMP, "chains", "contacts_000000200.vtp"), "--strongest", "0.5",
                "--out", os.path.join(out("chains"), "force_chains.png")), out("chains"),
         ["force_chains.png"]),
        ("plot_sweep.py (fresh sweep of spheres)",
         script(os.path.join(SCRIPTS, "plot_sweep.py"), os.path.join(TMP, "sweep", "sweep.csv"),
                out("sweep_spheres")), out("sweep_spheres"),
         ["rheology_stresses.png", "rheology_friction_normal_stress.png",
          "rheology_contacts.png"]),
        ("plot_cfd_dem.py --shear",
         script(os.path.join(SCRIPTS, "plot_cfd_dem.py"), "--out", out("shear"), "--shear",
                table("cfd_dem_shear_box_dry.csv"), table("cfd_dem_shear_box_air.csv"),
                table("cfd_dem_shear_box_water.csv")), out("shear"),
         ["cfd_dem_shear_box_stresses.png", "cfd_dem_shear_box_temperature.png"]),
        ("plot_cfd_dem.py --slip (committed windows)",
         script(os.path.join(SCRIPTS, "plot_cfd_dem.py"), "--slip",
                table("cfd_dem_shear_box_water_slip.csv"), "--out", out("slip")), out("slip"),
         ["cfd_dem_shear_box_slip.png"]),
        ("plot_cfd_dem.py --slip (windows of the run above)",
         script(os.path.join(SCRIPTS, "plot_cfd_dem.py"), "--slip", windows,
                "--out", out("slip_run")), out("slip_run"), ["cfd_dem_shear_box_slip.png"]),
        ("plot_dem_vs_continuum.py (committed tables)",
         script(os.path.join(SCRIPTS, "plot_dem_vs_continuum.py"), "--out", out("dem_continuum")),
         out("dem_continuum"), ["continuum_vs_dem.png"]),
    ]
    build = os.path.dirname(GF)
    if os.path.exists(VALIDATION_TESTS):
        jobs += [
            ("plot_cfd_dem.py BUILD_DIR",
             script(os.path.join(SCRIPTS, "plot_cfd_dem.py"), "--out", out("cfd_dem"), build),
             out("cfd_dem"), ["cfd_dem_ergun.png", "cfd_dem_hindered_settling.png"]),
            ("plot_drag.py BUILD_DIR",
             script(os.path.join(SCRIPTS, "plot_drag.py"), build, "--out", out("drag")),
             out("drag"), ["drag_terminal.png", "drag_laws.png", "drag_hs_rod.png"]),
            ("plot_rheology_spheres.py BUILD_DIR",
             script(os.path.join(SCRIPTS, "plot_rheology_spheres.py"), "--out",
                    out("rheology_spheres"), build),
             out("rheology_spheres"), ["rheology_spheres_kinetic_theory.png"]),
            ("plot_momentum_balance.py BUILD_DIR",
             script(os.path.join(SCRIPTS, "plot_momentum_balance.py"), "--out",
                    out("momentum_balance"), build),
             out("momentum_balance"), ["rheology_momentum_balance.png"]),
            ("plot_fluid_fv.py BUILD_DIR",
             script(os.path.join(SCRIPTS, "plot_fluid_fv.py"), "--out", out("fluid_fv"), build),
             out("fluid_fv"), ["fluid_fv_cavity.png", "fluid_fv_convergence.png"]),
            ("plot_continuum.py BUILD_DIR",
             script(os.path.join(SCRIPTS, "plot_continuum.py"), "--out", out("continuum"), build),
             out("continuum"), ["continuum_sph.png"]),
            ("plot_two_fluid.py BUILD_DIR",
             script(os.path.join(SCRIPTS, "plot_two_fluid.py"), "--out", out("two_fluid"), build),
             out("two_fluid"), ["two_fluid.png"]),
            ("make_plots.py BUILD_DIR",
             script(os.path.join(VALIDATION, "make_plots.py"), "--out", out("dem"), build),
             out("dem"), ["dem_chung_ooi_test1.png", "dem_restitution.png",
                          "dem_energy_conservation.png", "dem_floor_force.png",
                          "dem_sliding_rolling.png", "dem_shapes.png", "dem_mesh_walls.png",
                          "dem_mesh_rods.png", "dem_fixed_particles.png",
                          "dem2d_disk_polygon.png", "dem2d_silo.png"]),
        ]
    else:
        print(f"note: {VALIDATION_TESTS} not built; the BUILD_DIR modes are not run")

    def timed(job):
        t0 = time.monotonic()
        return run(job[1], TMP), time.monotonic() - t0

    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        results = list(pool.map(timed, jobs))
    for (name, _, folder, expected), (r, seconds) in zip(jobs, results):
        print(f"{name}: {seconds:.1f} s")
        check(r.returncode == 0, f"{name} exits 0, got {r.returncode}:\n{r.stderr[-3000:]}")
        check_pngs(name, folder, expected)
    check(sorted(os.listdir(TMP)) == sorted(["a", "b", "windows.csv", "first.csv", "second.csv",
                                             "synthetic.csv", "empty.csv", "sweep", "sweep_walls",
                                             "chains", "plots"]),
          f"nothing else is written into the working folder: {sorted(os.listdir(TMP))}")

after = snapshot(VALIDATION)
check(after == before, "docs/validation is unchanged: "
      f"new {sorted(set(after) - set(before))}, gone {sorted(set(before) - set(after))}, "
      f"changed {sorted(k for k in set(after) & set(before) if after[k] != before[k])}")

check.exit(f" ({time.monotonic() - start:.1f} s)")
