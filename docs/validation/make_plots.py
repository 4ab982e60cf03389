#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs the DEM validation tests with curve output switched on and plots them against the references.
"""Usage: /usr/bin/python3 docs/validation/make_plots.py [--out DIR] [BUILD_DIR]
(BUILD_DIR default build/release)

Writes docs/validation/dem_*.png, dem2d_disk_polygon.png and dem2d_silo.png, or with --out DIR
into DIR (created if missing). Uses Debian's python3-numpy and python3-matplotlib."""
import glob
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# scripts/validation_run.py, found from this file's own place (whatever the working folder, also
# through a symbolic link to this file) and ahead of any other module of that name.
HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, os.path.normpath(os.path.join(HERE, os.pardir, os.pardir, "scripts")))
import validation_run  # noqa: E402

args = validation_run.parser(__doc__).parse_args()
PLOT_DIR = args.out
os.makedirs(PLOT_DIR, exist_ok=True)


def load(path):
    return np.genfromtxt(path, delimiter=",", names=True)


with validation_run.validation_run(args.build, "Validation*:AllLaws*:Laws*:*/ValidationFixedBounce.*") as out:
    # Chung & Ooi test 1: force against overlap, with Hertz theory and the published extrema.
    d = load(os.path.join(out, "chung_ooi_test1.csv"))
    E, nu, R = 48e9, 0.2, 0.010
    e_star, r_eff = E / (2 * (1 - nu * nu)), R / 2
    delta = np.linspace(0, d["overlap"].max(), 200)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(d["overlap"] * 1e6, d["force"] / 1e3, ".", ms=2, label="grainflow (hertz_mindlin)")
    ax[0].plot(delta * 1e6, 4 / 3 * e_star * math.sqrt(r_eff) * delta ** 1.5 / 1e3, "k-", lw=0.8,
               label="Hertz theory")
    ax[0].plot([274.1], [10.70], "r*", ms=12, label="Chung & Ooi (2011): 274.1 um, 10.70 kN")
    ax[0].set_xlabel("overlap (um)")
    ax[0].set_ylabel("normal force (kN)")
    ax[0].legend(fontsize=8)
    t0 = d["t"][0]
    ax[1].plot((d["t"] - t0) * 1e6, d["force"] / 1e3, "-")
    ax[1].axvline(40.3, color="r", ls="--", label="contact time 40.3 us")
    ax[1].set_xlabel("time in contact (us)")
    ax[1].set_ylabel("normal force (kN)")
    ax[1].legend(fontsize=8)
    fig.suptitle("Two glass spheres, 10 m/s head-on (Chung & Ooi 2011, test 1)")
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_chung_ooi_test1.png"), dpi=120)

    # Realised restitution.
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    for model, marker in (("hooke", "o"), ("hertz_mindlin", "s")):
        for where, fill in (("pair", "full"), ("wall", "none")):
            rows = [load(f) for f in sorted(glob.glob(os.path.join(out, f"restitution_{model}_{where}_*.csv")))]
            req = np.array([float(r["requested"]) for r in rows])
            got = np.array([float(r["realised"]) for r in rows])
            ax.plot(req, (got / req - 1) * 100, marker, fillstyle=fill, label=f"{model}, sphere-{where}")
    ax.axhspan(-1, 1, color="0.9", label="required: 1 %")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("requested restitution e")
    ax.set_ylabel("realised / requested - 1 (%)")
    ax.set_ylim(-1.5, 1.5)
    ax.legend(fontsize=8)
    ax.set_title("Realised restitution of binary collisions (dt = t_c/1000)")
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_restitution.png"), dpi=120)

    # Energy of an elastic, frictionless gas.
    d = load(os.path.join(out, "energy_elastic_gas.csv"))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(d["step"], d["relative_error"], "-")
    ax.axhline(1e-4, color="r", ls="--", label="required bound 1e-4")
    ax.axhline(-1e-4, color="r", ls="--")
    ax.set_xlabel("step")
    ax.set_ylabel("(E - E0) / E0")
    ax.set_title("Elastic frictionless Hertz gas, 300 spheres, periodic box")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_energy_conservation.png"), dpi=120)

    # Floor force over bed weight during settling.
    d = load(os.path.join(out, "floor_force.csv"))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(d["t"], d["floor_over_weight"], "-", lw=0.8)
    ax.axhspan(0.99, 1.01, color="0.85", label="1 % band")
    ax.set_ylim(0, 2)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("floor force / bed weight")
    ax.set_title("Settling bed, periodic sides")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_floor_force.png"), dpi=120)

    # Sliding to rolling.
    d = load(os.path.join(out, "sliding_rolling.csv"))
    mu, g, v0 = 0.3, 9.81, 1.0
    t = np.linspace(0, d["t"].max(), 200)
    t_roll = 2 * v0 / (7 * mu * g)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(d["t"], d["v"], ".", ms=3, label="v (grainflow)")
    ax.plot(d["t"], d["omega_r"], ".", ms=3, label="omega r (grainflow)")
    ax.plot(t, np.where(t < t_roll, v0 - mu * g * t, 5 * v0 / 7), "k-", lw=0.8, label="theory")
    ax.plot(t, np.where(t < t_roll, 2.5 * mu * g * t, 5 * v0 / 7), "k-", lw=0.8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("m/s")
    ax.set_title("Sphere launched sliding, mu = 0.3: rolling at t = 2 v0 / (7 mu g)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_sliding_rolling.png"), dpi=120)

    # Mesh (STL) walls (tests/validation/test_mesh_wall_validation.cpp).
    dm = load(os.path.join(out, "mesh_incline_mesh.csv"))
    dp = load(os.path.join(out, "mesh_incline_plane.csv"))
    rb = load(os.path.join(out, "mesh_rebound.csv"))
    theta, g = math.radians(20), 9.81
    t = np.linspace(0, dm["t"].max(), 200)
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    ax[0].plot(dm["t"], dm["s"] * 1e3, "o", ms=3, mfc="none", label="meshed incline (384 triangles)")
    ax[0].plot(dp["t"], dp["s"] * 1e3, ".", ms=3, label="plane wall")
    ax[0].plot(t, 0.5 * 5 / 7 * g * math.sin(theta) * t ** 2 * 1e3, "k-", lw=0.8,
               label="rolling: s = (5/14) g sin(theta) t^2")
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("distance rolled (mm)")
    ax[0].set_title("Sphere rolling down a 20 degree incline")
    ax[0].legend(fontsize=8)
    n = min(len(dm), len(dp))
    ax[1].semilogy(dm["t"][:n], np.abs(dm["s"][:n] - dp["s"][:n]) + 1e-18, ".", ms=3)
    ax[1].axhline(1e-9 * dp["s"].max(), color="r", ls="--", lw=0.8, label="test bound 1e-9 of the distance")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("|s_mesh - s_plane| (m)")
    ax[1].set_title("Mesh against plane: ~30 triangle edges crossed")
    if not np.any(dm["s"][:n] != dp["s"][:n]):
        ax[1].text(0.5, 0.3, "identical to the bit at every sample\n(zero drawn at 1e-18)",
                   transform=ax[1].transAxes, ha="center", fontsize=9)
    ax[1].legend(fontsize=8)
    labels = ["plane", "roof ridge\n(2 triangles\nper edge point)", "apex of a flat fan\n(8 triangles)"]
    ax[2].bar(range(3), rb["vz"], color=["C0", "C1", "C2"])
    ax[2].axhline(0.5, color="k", lw=0.8, label="e v0 = 0.5 m/s")
    # If every triangle at the edge / vertex counted the contact: k, c x count, damping ratio x
    # sqrt(count) for the linear spring-dashpot.
    for x, count in ((1, 2), (2, 8)):
        zeta = -math.log(0.5) / math.sqrt(math.pi ** 2 + math.log(0.5) ** 2) * math.sqrt(count)
        e_count = math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2)) if zeta < 1 else 0.0
        ax[2].plot([x], [e_count], "rx", ms=10, label="counted per triangle" if x == 1 else None)
    ax[2].set_xticks(range(3))
    ax[2].set_xticklabels(labels, fontsize=8)
    ax[2].set_ylabel("rebound speed (m/s)")
    ax[2].set_title("1 m/s head-on impact, hooke e = 0.5")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_mesh_walls.png"), dpi=120)

    # Spherocylinders on mesh walls (the same test file).
    fm = load(os.path.join(out, "mesh_rod_floor_mesh.csv"))
    fp = load(os.path.join(out, "mesh_rod_floor_plane.csv"))
    ti = load(os.path.join(out, "mesh_rod_table_in.csv"))
    to = load(os.path.join(out, "mesh_rod_table_out.csv"))
    bar = load(os.path.join(out, "mesh_rod_bar.csv"))
    r_rod = 0.0015
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    ax[0].plot(fm["x"] * 1e3, fm["y"] * 1e3, "o", ms=3, mfc="none", label="meshed floor (200 triangles)")
    ax[0].plot(fp["x"] * 1e3, fp["y"] * 1e3, ".", ms=3, label="plane wall")
    n = min(len(fm), len(fp))
    dev = np.max(np.hypot(fm["x"][:n] - fp["x"][:n], fm["y"][:n] - fp["y"][:n]))
    ax[0].set_xlabel("x (mm)")
    ax[0].set_ylabel("y (mm)")
    ax[0].set_title("Rod dropped spinning: centre path\n(largest distance mesh-plane %.1e m)" % dev,
                    fontsize=10)
    ax[0].legend(fontsize=8)
    ax[1].plot(ti["t"], ti["z"] * 1e3, "-", label="centre of mass over the table: stays")
    ax[1].plot(to["t"], to["z"] * 1e3, "-", label="centre of mass beyond the edge: tips off")
    ax[1].axhline(r_rod * 1e3, color="k", lw=0.8, ls="--", label="resting height r")
    ax[1].set_ylim(-30, 5)
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("centre height (mm)")
    ax[1].set_title("Rod let go across a table's edge (meshed box)", fontsize=10)
    ax[1].legend(fontsize=8)
    ax[2].plot(bar["t"], np.degrees(bar["tilt"]), "-")
    ax[2].set_xlabel("t (s)")
    ax[2].set_ylabel("tilt of the axis (degrees)")
    ax[2].set_title("Rod dropped across a 6 mm bar, 1 mm off centre:\nrests on both edges", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_mesh_rods.png"), dpi=120)

    # Non-spherical grains and Gear (tests/validation/test_shape_validation.cpp).
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    a = ax[0, 0]
    for pattern, marker, label in (("shape_restitution_capsule_flat_hooke_*", "o", "capsule flat on plane, hooke"),
                                   ("shape_restitution_capsule_flat_hertz_mindlin_*", "s", "capsule flat on plane, hertz_mindlin"),
                                   ("shape_restitution_capsule_pair_*", "^", "capsule pair, crossed / parallel"),
                                   ("shape_restitution_square_*", "D", "2D square on floor / pair")):
        req, got = [], []
        for f in sorted(glob.glob(os.path.join(out, pattern + ".csv"))):
            d = load(f)
            req.append(float(d["requested"]))
            got.append(float(d["realised"]))
        a.plot(req, got, marker, ls="none", label=label)
    a.plot([0.2, 0.9], [0.2, 0.9], "k-", lw=0.8)
    a.set_xlabel("requested restitution")
    a.set_ylabel("realised restitution")
    a.set_title("Impacts of non-spherical grains (1 % tolerance)")
    a.legend(fontsize=7)
    d = load(os.path.join(out, "shape_capsule_tilted.csv"))
    a = ax[0, 1]
    a.plot(d["t"] * 1e3, d["omega_y"], label="omega_y (rad/s)")
    a2 = a.twinx()
    a2.plot(d["t"] * 1e3, d["axis_z"], "C1", label="axis z component")
    a2.plot(d["t"] * 1e3, d["energy_ratio"], "C2--", label="E / E0")
    a.set_xlabel("t (ms)")
    a.set_ylabel("omega_y (rad/s)")
    a2.set_ylabel("axis z, E/E0")
    a.set_title("Capsule tilted 30 deg hits a plane: turns towards flat")
    a.legend(fontsize=7, loc="upper left")
    a2.legend(fontsize=7, loc="lower left")
    d = load(os.path.join(out, "shape_free_rotation.csv"))
    a = ax[1, 0]
    a.plot(d["t"], np.abs(d["energy_error"]) + 1e-18, label="|dE/E|")
    a.plot(d["t"], np.abs(d["momentum_error"]) + 1e-18, label="|dL|/|L|")
    a.set_yscale("log")
    a.set_xlabel("t (s)")
    a.set_title("Free rotation of a capsule (closed-form symmetric top)")
    a.legend(fontsize=7)
    a = ax[1, 1]
    for integ, marker in (("gear5", "o-"), ("velocity_verlet", "s-")):
        rows = sorted((float(load(f)["steps_per_contact"]), float(load(f)["restitution_error"]))
                      for f in glob.glob(os.path.join(out, f"gear_collision_{integ}_*.csv")))
        a.loglog([r[0] for r in rows], [r[1] for r in rows], marker, label=integ)
    a.set_xlabel("steps per contact time")
    a.set_ylabel("relative restitution error")
    a.set_title("Clipped spring-dashpot collision, e = 0.7")
    a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_shapes.png"), dpi=120)

    # Fixed grains (tests/validation/test_fixed_particles_validation.cpp).
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    d = load(os.path.join(out, "fixed_bed_load.csv"))
    a = ax[0]
    a.plot(d["t"], d["fixed_force_z_over_weight"], "-", lw=0.8)
    a.axhline(1.0, color="k", lw=0.8)
    a.set_ylim(0, 2)
    a.set_xlabel("t (s)")
    a.set_ylabel("load on the fixed bed / weight of the free grains")
    a.set_title("150 spheres settling on 100 fixed spheres (periodic sides)")
    a = ax[1]
    rows = [(os.path.basename(f)[len("fixed_bounce_"):-4], load(f))
            for f in sorted(glob.glob(os.path.join(out, "fixed_bounce_*.csv")))]
    x = np.arange(len(rows))
    req = np.array([float(r["requested"]) for _, r in rows])
    a.plot(x, [float(r["on_fixed"]) / q for (_, r), q in zip(rows, req)], "o",
           label="on a fixed grain")
    a.plot(x, [float(r["on_heavy"]) / q for (_, r), q in zip(rows, req)], "x",
           label="on a free grain 1e6 times heavier")
    a.plot(x, [float(r["real_mass_linear"]) / q for (_, r), q in zip(rows, req)], "s",
           fillstyle="none", label="fixed grain's real mass in the damping (linear law)")
    a.axhspan(0.99, 1.01, color="0.85", label="1 % tolerance")
    a.set_xticks(x, [n for n, _ in rows], rotation=30, fontsize=7)
    a.set_ylabel("realised / requested restitution")
    a.set_title("Bounces on a fixed grain")
    a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem_fixed_particles.png"), dpi=120)

    # Disks with polygons, polygons in drums (tests/validation/test_disk_polygon_validation.cpp).
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    a = ax[0]
    rows = [("disk on a square", "disk_square_stack_disk_on_top"),
            ("square on a disk", "disk_square_stack_disk_below"),
            ("square in a drum\n(on its two corners)", "square_in_drum_rest")]
    x = np.arange(len(rows))
    ratio = [float(load(os.path.join(out, f + ".csv"))["relative_error"]) for _, f in rows]
    a.bar(x, np.abs(ratio) + 1e-16, color="C0")
    a.axhline(1e-3, color="r", ls="--", lw=0.8, label="tolerance 1e-3")
    a.set_yscale("log")
    a.set_xticks(x, [n for n, _ in rows], fontsize=8)
    a.set_ylabel("|A(measured depth) / (m g l_c / k) - 1|")
    a.set_title("At rest: exact overlap area against the weight it carries", fontsize=10)
    a.legend(fontsize=7)
    a = ax[1]
    d = load(os.path.join(out, "square_in_drum_turning.csv"))
    s = load(os.path.join(out, "square_in_drum_slip.csv"))
    a.plot(d["t"], d["angle_deg"], "-", label="square's angular position")
    k = int(np.argmin(np.abs(d["t"] - 0.2)))  # (after the drop and first slide, ~0.05 s)
    a.plot(d["t"], d["drum_deg"] - d["drum_deg"][k] + d["angle_deg"][k], "k--", lw=0.8,
           label="turning with the drum")
    a.axhline(float(s["friction_angle_deg"]), color="C2", lw=0.8, label="atan(mu)")
    a.axhline(float(s["expected_deg"]), color="C3", ls=":", lw=1,
              label="expected 10 % lag (load shift + deceleration)")
    a.set_xlabel("t (s)")
    a.set_ylabel("angle from the bottom (degrees)")
    a.set_title("Square in a drum turning at 0.5 rad/s (R = 0.5 m, mu = 0.5)", fontsize=10)
    a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem2d_disk_polygon.png"), dpi=120)

    # Silo discharge through an orifice (tests/validation/test_silo_validation.cpp).
    d = load(os.path.join(out, "silo_discharge.csv"))
    r = load(os.path.join(out, "silo_rates.csv"))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    a = ax[0]
    for q, n in zip(r["D_over_d"], r["count"]):
        s = (d["D_over_d"] == q) & (d["count"] == n)
        a.plot(d["t"][s], d["mass"][s] * 1e3, "-" if n == 2000 else ":",
               label=f"D = {q:g} d" + ("" if n == 2000 else ", half the grains"))
    a.axvline(0.5, color="k", lw=0.5, ls="--")
    a.set_xlabel("t (s); the gate opens at 0.3 s, the rate is fitted from 0.5 s")
    a.set_ylabel("mass through the outlet (g)")
    a.set_title("2D silo, 40 d wide, grains recirculated to the top", fontsize=10)
    a.legend(fontsize=7)
    a = ax[1]
    full = r["count"] == 2000
    dd = r["D_over_d"][full] * 0.002
    w23 = r["rate"][full] ** (2 / 3)
    slope, icpt = np.polyfit(dd, w23, 1)
    k = -icpt / slope / 0.002
    c = slope ** 1.5 / (np.mean(r["solid_fraction"][full]) * 2500 * math.sqrt(9.81) * 0.002)
    line = np.linspace(k * 0.002, dd.max() * 1.05, 50)
    a.plot(r["D_over_d"][full], w23, "o", label="grainflow, bed 85 mm")
    a.plot(r["D_over_d"][~full], r["rate"][~full] ** (2 / 3), "s", mfc="none",
           label="D = 8 d, bed 52 mm (Hagen: same rate)")
    a.plot(line / 0.002, slope * line + icpt, "k-", lw=0.8,
           label=f"Beverloo: C = {c:.2f}, k = {k:.2f}")
    # The flow meter 2 mm under the floor (flow_meters: in the case file) against the outlet.
    ratio = r["meter_rate"][full] / r["rate"][full]
    a.plot(r["D_over_d"][full], r["meter_rate"][full] ** (2 / 3), "x", color="C3", ms=8,
           label="flow meter under the orifice\n(its rate / the outlet's: "
                 + " / ".join(f"{v:.4f}" for v in ratio) + ")")
    a.set_xlim(0, None)
    a.set_ylim(0, None)
    a.set_xlabel("orifice D / grain diameter d")
    a.set_ylabel("W^(2/3) (kg/s)^(2/3)")
    a.set_title("W = C rho_b sqrt(g) t (D - k d)^(3/2)", fontsize=10)
    a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(PLOT_DIR, "dem2d_silo.png"), dpi=120)

print("plots written to", PLOT_DIR)
