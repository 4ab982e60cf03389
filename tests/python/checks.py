# SPDX-License-Identifier: GPL-3.0-or-later
"""Counting of checks, shared by the Python tests (not a test itself: CTest runs test_*.py)."""
import sys


class Checks:
    """check(cond, what) counts a passed or a failed check (printing what failed); exit() prints
    the counts and ends the test with status 1 if any check failed."""

    def __init__(self):
        self.passed = self.failed = 0

    def __call__(self, cond, what):
        if cond:
            self.passed += 1
        else:
            self.failed += 1
            print("FAIL:", what)

    def exit(self, note=""):
        print(f"{self.passed} passed, {self.failed} failed{note}")
        sys.exit(1 if self.failed else 0)


# A small fluid_fem case: a disk in a channel 1 m x 0.4 m, inflow from the left (edge 3), outflow
# on the right (edge 1), walls elsewhere.
FEM_CHANNEL_BLOCK = """fluid_fem:
  fluid: {density: 1.0, viscosity: 0.01}
  domain:
    outline: [[0, 0], [1, 0], [1, 0.4], [0, 0.4]]
    boundaries:
      - {edges: [1], type: outflow}
      - {edges: [3], type: inflow, u_max: 0.5}
  bodies:
    - {name: disk, circle: {centre: [0.3, 0.2], radius: 0.05}}
  mesh: {h_max: 0.08, h_body: 0.03}
  time: {mode: unsteady, scheme: bdf2, step: 0.01, end: 1.0}
"""
