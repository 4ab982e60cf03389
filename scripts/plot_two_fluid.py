#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots of the two-fluid model validation (tests/validation/test_two_fluid_validation.cpp).

Usage: /usr/bin/python3 scripts/plot_two_fluid.py [--out DIR] [BUILD_DIR]   (default build/release)

Runs gf_validation_tests --gtest_filter='ValidationTwoFluid*' with GF_VALIDATION_OUT set and
writes docs/validation/two_fluid.png: batch sedimentation (front against Kynch's line, with
Richardson & Zaki's speed for comparison; the sediment's solids pressure against the buoyant
weight above), the packed bed's pressure against Ergun, the fluidised beds' pressure drops (a
liquid-fluidised bed and a slugging gas-fluidised column) against the weight of the mixture,
homogeneous cooling against Haff's law, Couette flow (no-slip and Johnson-Jackson walls) against
the kinetic-theory state, a mu(I) layer on an incline against Bagnold's profile and a
liquid-fluidised bed with a particle pressure against the uniform expansion. The errors in the titles are computed
here from the tests' CSV files, the way the tests compute them. With --out DIR, into DIR (created
if missing) instead. Uses Debian's python3-numpy and python3-matplotlib."""
import math
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import validation_run  # noqa: E402

# The test's batch-sedimentation set-up (BatchSedimentationFollowsKynch): 200 um glass beads
# (2500 kg/m^3) in water, a0 = 0.2 up to h0 = 0.07 m, front speed fitted between 0.5 and 4.5 s.
G = 9.81
RHO_S, RHO_F, MU_F, D_SED = 2500.0, 1000.0, 1e-3, 2e-4
A0, H0 = 0.2, 0.07
FIT = (0.5, 4.5)
SEDIMENT_CELLS = (0, 15)  # cells whose solids-pressure difference the test checks
PACKED_CELLS = (2, 10)    # cells whose pressure difference the test checks against Ergun
U_WALL = 0.5              # Couette: walls at -U and +U
# The fluidised bed (PackedBedFollowsErgunThenFluidises): 500 um beads, a0 = 0.55 packed 30 mm
# deep, U = 2 U_mf; `gidaspow` drag is Ergun's below eps = 0.8.
D_BED, A_BED, H_BED, U_RATIO = 5e-4, 0.55, 0.030, 2.0


def load(folder, name):
    return np.genfromtxt(os.path.join(folder, name + ".csv"), delimiter=",", names=True)


def bisect(f, lo, hi):
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(mid) < 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def richardson_zaki_speed():
    """Richardson & Zaki's hindered settling speed u_t eps^n of the test's suspension: u_t the
    terminal speed of one grain with the single-grain drag of `di_felice` (Dallavalle's C_D0), n
    from Rowe (1987). Returns (u_t, n, u_t eps0^n)."""
    vp = math.pi * D_SED ** 3 / 6.0
    weight = vp * (RHO_S - RHO_F) * G

    def excess(u):
        re = RHO_F * u * D_SED / MU_F
        cd = (0.63 + 4.8 / math.sqrt(re)) ** 2
        return cd * 0.5 * RHO_F * u * u * math.pi * D_SED ** 2 / 4.0 - weight

    u_t = bisect(excess, 1e-9, 10.0)
    re_t = RHO_F * u_t * D_SED / MU_F
    n = (4.7 + 0.41 * re_t ** 0.75) / (1.0 + 0.175 * re_t ** 0.75)
    return u_t, n, u_t * (1.0 - A0) ** n


def ergun(a, u):
    """Ergun's pressure gradient [Pa/m] through grains at fraction a, superficial velocity u."""
    e = 1.0 - a
    return (150 * MU_F * a * a * u / (e ** 3 * D_BED ** 2)
            + 1.75 * RHO_F * a * u * u / (e ** 3 * D_BED))


def expanded_height():
    """Height of the bed at U = U_RATIO U_mf if it expanded uniformly to the fraction whose drag
    carries its buoyant weight (Ergun = a (rho_s - rho_f) g)."""
    def excess(a, u):
        return ergun(a, u) - a * (RHO_S - RHO_F) * G

    u_mf = bisect(lambda u: excess(A_BED, u), 0.0, 1.0)
    a_eq = bisect(lambda a: excess(a, U_RATIO * u_mf), 0.01, A_BED)
    return a_eq, H_BED * A_BED / a_eq


def sedimentation_front(ax, folder):
    d = load(folder, "two_fluid_sedimentation_front")
    t, y, kynch = d["t"], d["front"], d["kynch"]
    u_hs = (kynch[0] - kynch[-1]) / (t[-1] - t[0])
    y0, y1 = np.interp(FIT, t, y)
    speed = (y0 - y1) / (FIT[1] - FIT[0])
    err = 100 * (speed / u_hs - 1)
    u_t, n, u_rz = richardson_zaki_speed()
    final = y[-1]
    ax.plot(t, y * 1e3, "-", lw=2, label="grainflow: front (a = a0/2)")
    show = kynch >= final
    ax.plot(t[show], kynch[show] * 1e3, "k--", label=f"Kynch, u_hs = {u_hs * 1e3:.3f} mm/s")
    rz = H0 - u_rz * t
    ax.plot(t[rz >= final], rz[rz >= final] * 1e3, "k:",
            label=f"Richardson-Zaki u_t eps^n, n = {n:.2f}")
    ax.axvspan(*FIT, color="0.93", label="fit window")
    ax.axhline(final * 1e3, color="0.5", lw=0.8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("front height (mm)")
    ax.set_title(f"Batch sedimentation, a0 = {A0}: front speed {err:+.3f} % of Kynch\n"
                 f"(drag's u_hs vs Richardson-Zaki: {100 * (u_hs / u_rz - 1):+.1f} %)",
                 fontsize=9)
    ax.legend(fontsize=7)


def sediment_profile(ax, folder):
    d = load(folder, "two_fluid_sediment_profile")
    order = np.argsort(d["y"])  # written top down
    y, a, ps, w = (d[k][order] for k in ("y", "alpha", "solids_pressure", "weight_above"))
    h = y[1] - y[0]
    # Delta rho g from the file itself: consecutive weight_above differ by h drho_g (a_j + a_j+1)/2.
    k = np.argmax(a[:-1] + a[1:])
    drho_g = (w[k] - w[k + 1]) / (0.5 * h * (a[k] + a[k + 1]))
    j0, j1 = SEDIMENT_CELLS
    between = sum((0.5 if j in (j0, j1) else 1.0) * a[j] * h * drho_g for j in range(j0, j1 + 1))
    err = 100 * ((ps[j0] - ps[j1]) / between - 1)
    floor = 100 * (ps[0] / w[0] - 1)
    top = y[a > 1e-3].max() + 0.5 * h
    s = y <= top + h
    ax.plot(ps[s], y[s] * 1e3, "o-", ms=3, label="grainflow: solids pressure P_s")
    ax.plot(w[s], y[s] * 1e3, "k--", label="buoyant weight of the grains above")
    ax.axhspan(y[j0] * 1e3, y[j1] * 1e3, color="0.93", label=f"checked: cells {j0}-{j1}")
    ax.set_xlabel("pressure (Pa)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"Sediment at rest (t = 7 s): P_s difference {err:+.2f} % of the weight\n"
                 f"(at the floor P_s is {floor:+.1f} % of the weight above)", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")


def packed_bed(ax, folder):
    d = load(folder, "two_fluid_packed_bed")
    y, a, p, grad = d["y"], d["alpha"], d["pressure"], d["ergun_gradient"]
    h = y[1] - y[0]
    j0, j1 = PACKED_CELLS
    ref = sum((0.5 if j in (j0, j1) else 1.0) * h * grad[j] for j in range(j0, j1 + 1))
    rel = (p[j0] - p[j1]) / ref - 1
    # Ergun + hydrostatic integrated down from the top cell (trapezoid between cell centres).
    integ = np.zeros_like(p)
    integ[-1] = p[-1]
    for j in range(len(p) - 2, -1, -1):
        integ[j] = integ[j + 1] + 0.5 * h * (grad[j] + grad[j + 1])
    bed = a > 1e-3
    ax.plot(p, y * 1e3, "o", ms=3, label="grainflow: fluid pressure")
    ax.plot(integ, y * 1e3, "k-", lw=0.9, label="Ergun + rho_f g (cell fractions), integrated")
    ax.axhspan(y[j0] * 1e3, y[j1] * 1e3, color="0.93", label=f"checked: cells {j0}-{j1}")
    ax.axhline((y[bed].max() + 0.5 * h) * 1e3, color="0.5", lw=0.8, ls="--", label="bed top")
    ax.set_xlabel("p (Pa)")
    ax.set_ylabel("y (mm)")
    off = p[0] - integ[0]
    ax.set_title(f"Packed bed, U = U_mf / 2: p drop vs Ergun {rel:+.1e}\n"
                 f"(floor: p - ref = {off:+.1f} Pa = {100 * off / (p[0] - p[-1]):+.2f} %, "
                 f"from the bed top)", fontsize=9)
    ax.legend(fontsize=7)


def fluidised_bed(ax, folder):
    d = load(folder, "two_fluid_fluidised_bed")
    t, dp, w, top = d["t"], d["pressure_drop"], d["mixture_weight"], d["bed_top"]
    err = 100 * (dp.mean() / w.mean() - 1)
    ax.plot(t, dp, "-", label="grainflow: p(0) - p(50)")
    ax.plot(t, w, "k--", label="weight of the mixture between")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("pressure drop (Pa)")
    ax.set_title(f"Fluidised bed, U = 2 U_mf: mean pressure drop {err:+.3f} % of the weight",
                 fontsize=9)
    tw = ax.twinx()
    tw.plot(t, top * 1e3, "C2-", lw=0.9, label="bed top (a = 0.2), right axis")
    tw.axhline(H_BED * 1e3, color="C2", lw=0.6, ls=":")
    a_eq, h_eq = expanded_height()
    tw.axhline(h_eq * 1e3, color="C2", lw=0.8, ls="--",
               label=f"uniform expansion to the drag balance (a = {a_eq:.3f})")
    tw.set_ylabel("bed top (mm; packed 30 mm)", color="C2")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = tw.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="center right")


def haff(ax, folder):
    d = load(folder, "two_fluid_haff")
    t, th, ref = d["t_over_tau"], d["theta"], d["haff"]
    err = 100 * np.abs(th / ref - 1).max()
    tt = np.linspace(0, t.max(), 200)
    theta0 = ref[0] * (1 + t[0]) ** 2
    ax.semilogy(tt, theta0 / (1 + tt) ** 2, "k-", lw=0.9, label="Haff: Theta0 / (1 + t/tau)^2")
    ax.semilogy(t, th, "o", ms=4, mfc="none", label="grainflow (transported Theta)")
    ax.set_xlabel("t / tau")
    ax.set_ylabel("Theta (m^2/s^2)")
    ax.set_title(f"Homogeneous cooling, a = 0.3, e = 0.8 (lun), dt = tau/400:\n"
                 f"max |Theta / Haff - 1| = {err:.3f} %", fontsize=9)
    ax.legend(fontsize=7)


def couette_error(d):
    eu = np.abs(d["u"] - d["u_theory"]).max() / U_WALL
    et = np.abs(d["theta"] / d["theta_theory"] - 1).max()
    return eu, et


def fmt_error(e):
    # The CSV keeps 10 significant digits: a zero difference means below that.
    return "< 1e-10" if e == 0 else f"{e:.1e}"


def couette_velocity(ax, folder):
    parts = []
    for name, label, style in (("noslip", "no-slip walls", "o"),
                               ("jj", "Johnson-Jackson walls", "s")):
        d = load(folder, "two_fluid_couette_" + name)
        y = d["y"] * 1e3
        ax.plot(d["u"], y, style, ms=4, mfc="none", label=f"grainflow, {label}")
        ax.plot(d["u_theory"], y, "k-", lw=0.8)
        eu, _ = couette_error(d)
        parts.append(f"{label.split()[0]} {fmt_error(eu)}")
    H = 2 * load(folder, "two_fluid_couette_noslip")["y"].mean() * 1e3
    ax.plot([-U_WALL, U_WALL], [0, H], "k^", ms=6, label="wall velocities -U, +U")
    ax.plot([], [], "k-", lw=0.8, label="kinetic theory (JJ: slip mu_s / C)")
    ax.set_xlabel("u_s (m/s)")
    ax.set_ylabel("y (mm)")
    ax.set_title("Couette flow, a = 0.3, 200 steps from the state:\n|u - u_th| / U: "
                 + ", ".join(parts), fontsize=9)
    ax.legend(fontsize=7)


def couette_temperature(ax, folder):
    parts = []
    for name, label, style in (("noslip", "no-slip walls", "o"),
                               ("jj", "Johnson-Jackson walls", "s")):
        d = load(folder, "two_fluid_couette_" + name)
        y = d["y"] * 1e3
        ax.plot(d["theta"] * 1e3, y, style, ms=4, mfc="none", label=f"grainflow, {label}")
        ax.plot(d["theta_theory"] * 1e3, y, "k-", lw=0.8)
        _, et = couette_error(d)
        parts.append(f"{label.split()[0]} {fmt_error(et)}")
    ax.plot([], [], "k-", lw=0.8, label="(mu_s / gamma_s)(a, 1) gamma_dot^2")
    ax.set_xlabel("Theta (1e-3 m^2/s^2)")
    ax.set_ylabel("y (mm)")
    ax.set_title("Couette flow, algebraic Theta (syamlal):\n|Theta / theory - 1|: "
                 + ", ".join(parts), fontsize=9)
    ax.legend(fontsize=7)


def fractions(ax, folder):
    s = load(folder, "two_fluid_sediment_profile")
    p = load(folder, "two_fluid_packed_bed")
    ax.plot(s["alpha"], s["y"] * 1e3, "o-", ms=3, label="sediment (t = 7 s, a0 = 0.2)")
    ax.plot(p["alpha"], p["y"] * 1e3, "s-", ms=3, label="packed bed (t = 3 s, a0 = 0.55)")
    ax.axvline(0.5, color="0.5", lw=0.8, ls=":", label="frictional a_min = 0.5")
    ax.set_ylim(0, 40)
    ax.set_xlabel("solids volume fraction a")
    ax.set_ylabel("y (mm)")
    ax.set_title("Volume fraction of the sediment and the packed bed", fontsize=9)
    ax.legend(fontsize=7)


def incline(ax, folder):
    d = load(folder, "two_fluid_incline")
    inside = d["y"] < 0.8 * 0.01
    err = np.max(np.abs(d["u"][inside] - d["u_bagnold"][inside])) / d["u_bagnold"][inside][-1]
    ax.plot(d["u"], d["y"] * 1e3, "o", ms=3, label="grainflow (mu_i_switch)")
    ax.plot(d["u_bagnold"], d["y"] * 1e3, "k-", lw=1,
            label="mu(I), Bagnold: normal stress = cos(theta) x weight")
    ax.plot(d["u_mu_i"], d["y"] * 1e3, ":", color="0.5", lw=1,
            label="mu(I) at the closure pressure alone (jitters +-1 %)")
    ax.set_ylim(0, 12)
    ax.set_xlim(0, 1.3 * d["u_bagnold"].max())  # the empty faces above fall at metres per second
    ax.set_xlabel("u_s (m/s)")
    ax.set_ylabel("y (mm)")
    ax.set_title("Dense layer on a 25 deg incline, mu(I) regime switch:\n"
                 f"max error {100 * err:.2f} % of Bagnold's u at 0.8 h (lower 80 % of the layer)",
                 fontsize=9)
    ax.legend(fontsize=7)


def gas_column(ax, folder):
    d = load(folder, "two_fluid_gas_column")
    t, dp, w, top = d["t"], d["pressure_drop"], d["mixture_weight"], d["bed_top"]
    err = 100 * (dp.mean() / w.mean() - 1)
    ax.plot(t, dp, "-", lw=0.6, label="grainflow: p(0) - p(top)")
    running = np.cumsum(dp) / np.arange(1, len(dp) + 1)
    ax.plot(t, running, "C3-", lw=1.2, label="its running mean")
    ax.plot(t, w, "k--", label="weight of the mixture")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("pressure drop (Pa)")
    ax.set_title("Gas-fluidised column (0.5 mm glass in air, 2 U_mf; it slugs):\n"
                 f"mean pressure drop over 0.5-2 s {err:+.2f} % of the weight", fontsize=9)
    tw = ax.twinx()
    tw.plot(t, top * 1e3, "C2-", lw=0.6, label="bed top (a = 0.2), right axis")
    tw.set_ylabel("bed top (mm; packed 100 mm)", color="C2")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = tw.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="lower right")


def liquid_bed(ax, folder):
    """The liquid-fluidised bed with Gidaspow & Ettehadieh's particle pressure: the deviation
    from the uniform expansion, and the decay per cell the linearised face balance predicts."""
    a_eq, h_eq = expanded_height()

    def excess(a):
        u_mf = bisect(lambda u: ergun(A_BED, u) - A_BED * (RHO_S - RHO_F) * G, 0.0, 1.0)
        return ergun(a, U_RATIO * u_mf) - a * (RHO_S - RHO_F) * G

    slope = (excess(a_eq + 1e-6) - excess(a_eq - 1e-6)) / 2e-6
    modulus = 10 ** (5.43 - 8.76 * (1 - a_eq))
    parts = []
    for name, style in (("2mm", "o-"), ("1mm", "s-")):
        d = load(folder, "two_fluid_liquid_bed_" + name)
        y, a = d["y"], d["alpha"]
        h = y[1] - y[0]
        bed = d["alpha_uniform"] > 0
        dev = 100 * (a[bed] / a_eq - 1)
        q = (slope * h + 2 * modulus) / (slope * h - 2 * modulus)
        ax.plot(dev, y[bed] * 1e3, style, ms=3, lw=0.7, label=f"grainflow, h = {name[0]} mm")
        # the envelope q^(j - j_top) through the cell below the surface cell
        j = np.arange(bed.sum())
        env = abs(dev[-2]) * q ** (j - (len(j) - 2))
        ax.plot(env, y[bed] * 1e3, "k:", lw=0.8)
        ax.plot(-env, y[bed] * 1e3, "k:", lw=0.8)
        parts.append(f"{name[0]} mm: q = {q:.3f}")
    ax.plot([], [], "k:", lw=0.8, label="decay q per cell, linearised face balance")
    ax.axhline(h_eq * 1e3, color="C2", lw=0.8, ls="--", label=f"uniform height {h_eq * 1e3:.2f} mm")
    ax.set_xlim(-12, 12)
    ax.set_xlabel("a / a* - 1 (%)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"Liquid-fluidised bed, 2 U_mf, elastic modulus (G(a*) = {modulus:.2f} Pa):\n"
                 f"deviation from a* = {a_eq:.4f} at 6 s; " + ", ".join(parts), fontsize=9)
    ax.legend(fontsize=7, loc="lower left")


def plot(folder, out):
    fig, axes = plt.subplots(3, 4, figsize=(21, 13.5))
    ax = axes.ravel()
    sedimentation_front(ax[0], folder)
    sediment_profile(ax[1], folder)
    fractions(ax[2], folder)
    packed_bed(ax[3], folder)
    fluidised_bed(ax[4], folder)
    haff(ax[5], folder)
    couette_velocity(ax[6], folder)
    couette_temperature(ax[7], folder)
    incline(ax[8], folder)
    gas_column(ax[9], folder)
    liquid_bed(ax[10], folder)
    for a in ax[11:]:
        a.axis("off")
    for a in ax[:11]:
        a.grid(alpha=0.3)
    fig.suptitle("Two-fluid model (KTGF solids in a fluid) against analytic references "
                 "(tests/validation/test_two_fluid_validation.cpp)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "two_fluid.png"), dpi=100)


def main():
    validation_run.plot_main(__doc__, "ValidationTwoFluid*", [plot], OMP_NUM_THREADS="1")


if __name__ == "__main__":
    main()
