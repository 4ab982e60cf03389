# SPDX-License-Identifier: GPL-3.0-or-later
# Makes bench/terrain_settling/ importable by the peer scripts (they share bench/terrain_settling/run.py).
