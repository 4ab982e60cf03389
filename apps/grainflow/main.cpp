// SPDX-License-Identifier: GPL-3.0-or-later
// The grainflow command line (placeholder while the foundation is assembled).
int main() { return 0; }
