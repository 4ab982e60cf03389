# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared parts of the plot scripts that run gf_validation_tests (scripts/plot_drag.py,
scripts/plot_fluid_fv.py, scripts/plot_cfd_dem.py, docs/validation/make_plots.py): the command
line [--out DIR] [BUILD_DIR] and the run of BUILD_DIR/tests/gf_validation_tests with
--gtest_filter=... and GF_VALIDATION_OUT set to a temporary folder that the plots read.

Not a script of its own. The scripts in this folder import it directly (Python puts a script's
folder first on sys.path); docs/validation/make_plots.py adds this folder to sys.path itself."""
import argparse
import contextlib
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VALIDATION_DIR = os.path.join(ROOT, "docs", "validation")


def parser(doc, out=True):
    """The argument parser of a plot script: the script's docstring as description, the optional
    positional BUILD_DIR (default build/release) and, with out, --out DIR (default
    docs/validation). A script with options of its own passes out=False, adds them, then calls
    add_out so that --out comes after them in --help as before."""
    ap = argparse.ArgumentParser(description=doc,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", nargs="?", metavar="BUILD_DIR",
                    default=os.path.join(ROOT, "build", "release"),
                    help="build folder with tests/gf_validation_tests (default build/release)")
    if out:
        add_out(ap)
    return ap


def add_out(ap):
    """--out DIR, default docs/validation."""
    ap.add_argument("--out", metavar="DIR", default=VALIDATION_DIR,
                    help="output folder (default docs/validation)")


@contextlib.contextmanager
def validation_run(build, gtest_filter, **env):
    """Runs BUILD_DIR/tests/gf_validation_tests --gtest_filter=gtest_filter (its stdout dropped)
    with GF_VALIDATION_OUT set to a temporary folder and yields that folder, removed on leaving.
    env: further environment variables for the run (e.g. OMP_NUM_THREADS="1"). A failing run
    raises subprocess.CalledProcessError."""
    binary = os.path.join(build, "tests", "gf_validation_tests")
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([binary, "--gtest_filter=" + gtest_filter],
                       env=dict(os.environ, GF_VALIDATION_OUT=folder, **env), check=True,
                       stdout=subprocess.DEVNULL)
        yield folder


def plot_main(doc, gtest_filter, plots, **env):
    """The whole main() of a script that only plots one filter of gf_validation_tests: parses
    [--out DIR] [BUILD_DIR], creates DIR, runs the tests (validation_run), calls
    plot(folder, DIR) for each of plots and prints "plots written to DIR"."""
    args = parser(doc).parse_args()
    os.makedirs(args.out, exist_ok=True)
    with validation_run(args.build, gtest_filter, **env) as folder:
        for plot in plots:
            plot(folder, args.out)
    print("plots written to", args.out)
