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
