#!/usr/bin/env python3
"""Minimum fluidization velocity of the Muller particles from a pressure-drop sweep (seed Table 2.1).

The small bed of examples/coupling/small_bed.opts (3000 spheres of 1.2 mm, 1000 kg/m^3) settles in still gas; the
superficial velocity then rises in steps and falls back, each step continued from the previous one's checkpoint
(-restart with a new -inlet_velocity). The pressure drop across the bed (the cross-section average at the
distributor, extrapolated from the two lowest cell centres, minus the one above the bed and the gas column) is
averaged over the second half of each step. U_mf is where the packed-bed branch, fitted as a U + b U^2 (Ergun's
form), meets the fluidized plateau (the mean of the steps at or above --plateau-from); it is compared with Ergun's
U_mf for the packed bed's measured voidage (layer by layer, and as one bulk or whole-bed voidage; the rising curve
against the settled bed, the falling one against the bed it leaves) and with the seed's measured 0.30 m/s.

    scripts/umf_sweep.py [--out DIR] [--velocities 0.05,0.1,...] [--step 0.3] [--np 1] [--reuse] [--plot FILE] [--json FILE]"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np

from fluidbed_tools import outputs, reference
from fluidbed_tools.run import EXE, ROOT, command

# the particles and gas of examples/coupling/small_bed.opts (seed Table 2.1)
D, RHO_P, MU, RHO_G, G = 1.2e-3, 1000.0, 1.8e-5, 1.205, 9.81
SEED_UMF = 0.30  # m/s, measured by Muller et al. (2009), seed Table 2.1
LX, LZ = 0.02, 0.01  # m, the bed's cross-section
LAYER, LAYERS = 0.06 / 18, 18  # m: the fluid grid's cell layers (-grid_ny 18 over -domain_ly 0.06)


def ergun_gradient(eps, u):
    """Ergun pressure gradient (Pa/m) through a packed bed of the Muller particles at superficial velocity u
    (reference.ergun_gradient, seed eq. 2.11)."""
    return reference.ergun_gradient(eps, u, D, MU, RHO_G)


def ergun_umf(eps, d=D):
    """Ergun's minimum fluidization velocity of the Muller particles (spheres of diameter d) at voidage eps
    (reference.ergun_umf)."""
    return reference.ergun_umf(eps, d, RHO_P, RHO_G, MU, G)


def sphere_volume_in_slab(y, d, lo, hi):
    """Volume of each sphere (centre height y, diameter d) lying between the heights lo and hi."""
    r = 0.5 * d
    a, b = np.clip(lo - y, -r, r), np.clip(hi - y, -r, r)
    return np.pi * ((r * r * b - b ** 3 / 3) - (r * r * a - a ** 3 / 3))


def bed_height(particles, lx, columns):
    """Height of a settled bed: the mean over columns (along x) of the top of the highest particle in each."""
    x, y, d = particles["x"], particles["y"], particles["d"]
    edges = np.linspace(0.0, lx, columns + 1)
    return float(np.mean([np.max(y[(x >= a) & (x < b)] + 0.5 * d[(x >= a) & (x < b)]) for a, b in zip(edges[:-1], edges[1:])]))


def packed_voidage(particles, lx, lz, columns=6, margin=0.2):
    """(bulk voidage, mean voidage, height) of a packed bed. The bulk voidage counts the exact sphere volume between
    margin H and (1 - margin) H, away from the layering at the distributor and the rough surface, the homogeneous
    packing that Ergun's correlation describes; the mean voidage is the particle volume over the whole bed volume
    A H, with H the bed height of bed_height."""
    y, d = particles["y"], particles["d"]
    height = bed_height(particles, lx, columns)
    lo, hi = margin * height, (1 - margin) * height
    bulk = 1.0 - np.sum(sphere_volume_in_slab(y, d, lo, hi)) / (lx * lz * (hi - lo))
    mean = 1.0 - np.sum(np.pi / 6 * d ** 3) / (lx * lz * height)
    return float(bulk), float(mean), height


def layered_ergun_umf(particles, lx, lz, layer=LAYER, layers=LAYERS):
    """(U_mf, layer voidages): Ergun for the bed's measured voidage layer by layer. Each fluid-grid layer's voidage
    counts the particles whose centres lie in it (as the coupling does, eq. 5.2); U_mf is where the pressure drop
    summed over the layers, sum h Ergun(eps_j, U), carries the buoyant weight per area of all of them. A packed bed is
    looser at the distributor and at its surface than in its bulk, and Ergun's gradient is far from linear in the
    voidage, so no single voidage stands for the layers."""
    j = np.clip((particles["y"] / layer).astype(int), 0, layers - 1)
    solid = np.bincount(j, weights=np.pi / 6 * particles["d"] ** 3, minlength=layers)
    eps = 1.0 - solid / (lx * lz * layer)
    weight = np.sum(solid) * (RHO_P - RHO_G) * G / (lx * lz)
    lo, hi = 0.0, 10.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        dp = sum(layer * ergun_gradient(e, mid) for e in eps if e < 1.0)
        lo, hi = (mid, hi) if dp < weight else (lo, mid)
    return 0.5 * (lo + hi), eps


def bed_pressure_drop(mon):
    """Pressure drop across the bed (Pa) in each monitor row of a small_bed run, with its probes at the centres of
    the two lowest cells and one above the bed."""
    p1, p2, top = mon["p_y1_667mm_avg"], mon["p_y5mm_avg"], mon["p_y50mm_avg"]
    p0 = p1 + 0.5 * (p1 - p2)  # at the distributor
    return p0 - top - RHO_G * G * 0.05


def umf_from_curve(u, dp, plateau_from):
    """(U_mf, plateau, a, b): the plateau is the mean pressure drop at u >= plateau_from; the packed branch, the
    points below 85% of it, is fitted as a u + b u^2 through the origin; U_mf solves a u + b u^2 = plateau."""
    u, dp = np.asarray(u), np.asarray(dp)
    plateau = float(np.mean(dp[u >= plateau_from - 1e-12]))
    packed = dp < 0.85 * plateau
    A = np.vstack([u[packed], u[packed] ** 2]).T
    (a, b), *_ = np.linalg.lstsq(A, dp[packed], rcond=None)
    umf = (-a + math.sqrt(a * a + 4 * b * plateau)) / (2 * b) if b > 0 else plateau / a
    return umf, plateau, float(a), float(b)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "umf_sweep"), help="working directory of the runs")
    ap.add_argument("--velocities", default="0.05,0.1,0.15,0.2,0.25,0.3,0.35,0.4,0.45,0.5,0.6,0.7",
                    help="rising superficial velocities (m/s); the sweep then falls back through them")
    ap.add_argument("--settle", type=float, default=0.3, help="settling time in still gas (s)")
    ap.add_argument("--step", type=float, default=0.3, help="bed time per velocity (s); the second half is averaged")
    ap.add_argument("--plateau-from", type=float, default=0.5, help="velocities at or above this form the plateau (m/s)")
    ap.add_argument("--np", type=int, default=1, help="MPI ranks")
    ap.add_argument("--exe", default=EXE, help="the fluidbed executable (default $FLUIDBED_EXE, else build/fluidbed)")
    ap.add_argument("--reuse", action="store_true", help="keep the runs already in --out (same schedule) and run only the missing ones")
    ap.add_argument("--plot", default=None, help="PNG of the curve")
    ap.add_argument("--json", default=None, help="results as JSON")
    args = ap.parse_args()

    rising = [float(v) for v in args.velocities.split(",")]
    schedule = [("rising", v) for v in rising] + [("falling", v) for v in reversed(rising[:-1])]
    scene = os.path.join(ROOT, "examples", "coupling", "small_bed.opts")
    if os.path.isdir(args.out) and not args.reuse:
        shutil.rmtree(args.out)
    os.makedirs(args.out, exist_ok=True)

    def run(outdir, t_final, extra):
        if args.reuse and os.path.isfile(os.path.join(outdir, "summary.json")):
            return
        cmd = command(["-options_file", scene, "-output_dir", outdir, "-t_final", repr(t_final), "-checkpoint_interval", repr(t_final),
                       "-progress_interval", "0", "-output_particles", "1"] + extra, args.np, args.exe)
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode:
            sys.exit("umf_sweep: fluidbed failed (%d): %s\n%s%s" % (p.returncode, " ".join(cmd), p.stdout[-2000:], p.stderr[-2000:]))

    settle = os.path.join(args.out, "settle")
    run(settle, args.settle, ["-inlet_velocity", "0"])
    particles = outputs.table(os.path.join(settle, "particles.csv"))
    n = len(particles["id"])
    weight = n * math.pi / 6 * D ** 3 * (RHO_P - RHO_G) * G / (LX * LZ)
    beds = {"rising": packed_voidage(particles, LX, LZ) + layered_ergun_umf(particles, LX, LZ)}
    print("settled bed: %d particles, height %.2f mm, bulk voidage %.4f (mean %.4f); buoyant weight / area %.2f Pa"
          % (n, 1e3 * beds["rising"][2], beds["rising"][0], beds["rising"][1], weight))

    rows, prev, t = [], settle, args.settle
    for k, (branch, u) in enumerate(schedule):
        t_end = t + args.step
        out = os.path.join(args.out, "step%02d" % k)
        run(out, t_end, ["-restart", os.path.join(prev, "checkpoint.h5"), "-inlet_velocity", repr(u)])
        mon = outputs.table(os.path.join(out, "monitor.csv"))
        late = mon["time"] >= t + 0.5 * args.step
        dp = bed_pressure_drop(mon)[late]
        rows.append({"branch": branch, "u": u, "dp": float(dp.mean()), "dp_std": float(dp.std()), "t0": t, "t1": t_end})
        print("%-8s U = %.3f m/s: pressure drop %7.2f Pa (rms %.2f) over t = %.2f..%.2f s" % (branch, u, dp.mean(), dp.std(), t + 0.5 * args.step, t_end))
        prev, t = out, t_end
    # the falling branch ends on the bed that settled as the gas slowed down
    last = outputs.table(os.path.join(prev, "particles.csv"))
    beds["falling"] = packed_voidage(last, LX, LZ) + layered_ergun_umf(last, LX, LZ)

    res = {"particles": n, "weight_per_area_Pa": weight, "steps": rows, "umf_seed_measured": SEED_UMF}
    for branch in ("rising", "falling"):
        # the falling branch starts from the top of the rising one
        pts = [r for r in rows if r["branch"] == branch or (branch == "falling" and r["u"] == rising[-1])]
        umf, plateau, a, b = umf_from_curve([r["u"] for r in pts], [r["dp"] for r in pts], args.plateau_from)
        bulk, mean, height, layered, layer_eps = beds[branch]
        res[branch] = {"umf": umf, "plateau_Pa": plateau, "fit": [a, b], "bed_height_m": height, "bulk_voidage": bulk,
                       "mean_voidage": mean, "umf_ergun_layers": layered, "layer_voidage": [float(e) for e in layer_eps], "umf_ergun_bulk": ergun_umf(bulk), "umf_ergun_mean": ergun_umf(mean)}
        r = res[branch]
        print("%-8s curve: U_mf %.4f m/s (plateau %.1f Pa); packed bed %.2f mm high: Ergun layer by layer %.4f m/s (curve %+.1f%%); "
              "bulk voidage %.4f -> Ergun %.4f m/s (%+.1f%%); mean voidage %.4f -> Ergun %.4f m/s (%+.1f%%)"
              % (branch, umf, plateau, 1e3 * height, layered, 100 * (umf / layered - 1), bulk, r["umf_ergun_bulk"],
                 100 * (umf / r["umf_ergun_bulk"] - 1), mean, r["umf_ergun_mean"], 100 * (umf / r["umf_ergun_mean"] - 1)))
    # the sphericity phi that would bring Ergun (spheres of diameter phi d) to the measured 0.30 m/s at the bulk voidage
    eps = res["falling"]["bulk_voidage"]
    lo, hi = 0.3, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ergun_umf(eps, mid * D) < SEED_UMF else (lo, mid)
    res["sphericity_for_seed_umf"] = 0.5 * (lo + hi)
    print("seed (measured, poppy seeds): %.2f m/s; the falling curve is %+.1f%% from it; Ergun for spheres of diameter phi d gives it at phi = %.3f"
          % (SEED_UMF, 100 * (res["falling"]["umf"] / SEED_UMF - 1), res["sphericity_for_seed_umf"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(res, f, indent=1)
    if args.plot:
        plot(res, args.plot)


def plot(res, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for branch, style in (("rising", "o-"), ("falling", "s--")):
        pts = [r for r in res["steps"] if r["branch"] == branch]
        ax.errorbar([r["u"] for r in pts], [r["dp"] for r in pts], yerr=[r["dp_std"] for r in pts], fmt=style, ms=4, capsize=2,
                    label="%s velocity" % branch)
    for branch, color in (("rising", "C0"), ("falling", "C1")):
        r = res[branch]
        u = np.linspace(0, r["umf_ergun_layers"], 50)
        ax.plot(u, sum(LAYER * ergun_gradient(e, u) for e in r["layer_voidage"] if e < 1.0), ":", color=color, lw=1.2,
                label="Ergun layer by layer, %s bed (%.1f mm, bulk voidage %.3f)" % ("settled" if branch == "rising" else "defluidized",
                                                                                   1e3 * r["bed_height_m"], r["bulk_voidage"]))
    f = res["falling"]
    ax.axhline(res["weight_per_area_Pa"], color="gray", lw=0.8, label="buoyant bed weight / area")
    ax.axvline(f["umf"], color="C1", lw=0.8, ls="--", label="U_mf from the falling curve %.3f m/s" % f["umf"])
    ax.axvline(f["umf_ergun_layers"], color="k", lw=0.8, ls=":", label="U_mf Ergun, layer by layer %.3f m/s" % f["umf_ergun_layers"])
    ax.axvline(res["umf_seed_measured"], color="C3", lw=0.8, label="U_mf measured (seed, poppy seeds) %.2f m/s" % res["umf_seed_measured"])
    ax.set_xlabel("superficial gas velocity U (m/s)")
    ax.set_ylabel("pressure drop across the bed (Pa)")
    ax.set_title("Muller particles (1.2 mm, 1000 kg/m$^3$): pressure drop sweep")
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    main()
