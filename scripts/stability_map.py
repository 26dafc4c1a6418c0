#!/usr/bin/env python3
"""The stability map: where the single grid and the two grids hold on a 2D pseudo-bed of the seed's 750 um jet.

Every point is one run of examples/stability/jet750_2d.opts from the same settled bed, with its gas grid, slit, time
step, jet and substeps replaced, classified by the run-time guards (docs/reliability.md) and, for the runs that
finish, by its answers against the reference point (two grids on the seed's fine grid, dt = t_cr/20, 45.3 m/s):
  stable      finished, every measure within its threshold of the reference (two grids on the seed's fine grid, t_cr/20);
  inaccurate  finished, some measure outside (which one is said);
  unstable    a guard stopped the run (which guard, when), or the start-up refused it.
Maps: cell_dt (gas cell width / d against -dem_dt_factor), jet_sub (jet velocity against -couple_substeps), closed
(the closed-box energy of a pure DEM granular gas against -dem_dt_factor), ratio (the particle grid's cells, in gas
cells, on the reference's gas grid and step: the two-grid method's own knob, -pgrid_ratio; RATIOS), kn (the spring stiffness
-dem_kn, walls too, on the cheap front point of the two grids, 3 d gas cells: the soft-spring trade in a jetted bed, where a
longer step also moves the jet's particles further per step; KNS). A finished point is never rerun, so the
study resumes where it stopped; --jobs runs points side by side and --ranks runs each on more ranks. docs/stability.md
has the results; the table goes to --csv, the figure to --png.

example:
  scripts/stability_map.py --jobs 2                      # every map, resuming
  scripts/stability_map.py --maps cell_dt --ranks 2 --jobs 8
  scripts/stability_map.py --ci --out build/stability_ci # the short version tests/analysis/test_stability_map.py runs
  scripts/stability_map.py --maps ratio --jobs 2 --csv docs/stability/pgrid_ratio.csv   # the ratio map, its own table
  scripts/stability_map.py --maps kn --jobs 2 --csv docs/stability/kn_map.csv           # the stiffness map, its own table
"""
import argparse
import csv
import glob
import json
import math
import os
import sys

import numpy as np

from fluidbed_tools import outputs, run, study

ROOT = run.ROOT
SCENE = os.path.join(ROOT, "examples", "stability", "jet750_2d.opts")
CLOSED = os.path.join(ROOT, "examples", "dem", "granular_gas.opts")
SCENE3D = os.path.join(ROOT, "examples", "twogrid_750_jet1_u301.opts")  # the seed's 3D bed, 50,000 particles
BED3D = os.path.join(ROOT, "examples", "dem", "bed750.opts")  # the same particles settled without gas
GRIDS3D = {"fine": (175, 200, 5, "7,2,5"), "coarse": (105, 150, 3, "5,2,3")}  # the seed's grids (chapter 5)
D, LX, LY, LZ = 7.5e-4, 0.0564, 0.140, 0.00075
RHO_P, RHO_G, G = 2500.0, 1.205, 9.81
NXP, NYP, HY = 25, 50, 0.0014  # particle cells along x (2.256 mm = 3 d) and y (2.8 mm); gas cell height below 3 d
JET_X, JET_W, JET_V = 0.0282, 0.001611429, 45.3  # the seed's slit (5 cells of its 0.322 mm fine grid) and jet
# The reference: two grids on the seed's fine grid (0.43 d wide gas cells) at t_cr/20, the finest point that holds (at the
# seed's t_cr/10 the explicit gas step exceeds its limit in the jet for longer than the Courant guard allows).
REFERENCE = {"map": "cell_dt", "method": "two", "cell_d": 0.43, "dt_factor": 0.05, "jet": 45.3, "substeps": 1}
# The ratio map's particle cells, in gas cells of the reference's 0.322 x 1.4 mm grid (175 x 100: x divides by 5, 7,
# 25; y by 2, 4): 1.61 x 1.4 mm (2.1 x 1.9 d), 1.61 x 2.8 (2.1 x 3.7 d), the reference's 2.26 x 2.8 (3 x 3.7 d, the
# seed's choice), 2.26 x 5.6 (3 x 7.5 d) and 8.05 x 5.6 mm (10.7 x 7.5 d, seven particle cells across the bed).
RATIOS = [(5, 1), (5, 2), (7, 4), (25, 4)]
# The kn map: -dem_kn (N/m) at -dem_dt_factor of each spring's own t_cr, on the two grids with 3 d gas cells (the front's
# cheap point, 0.8% from the reference at t_cr/4); the seed's 800 N/m run again there so that the costs compare. The third
# figure is -couple_gas_substeps: gas steps per DEM step, for a DEM step longer than the jet's explicit gas limit.
KNS = [(0.25, 800, 1), (0.25, 400, 1), (0.25, 200, 1), (0.25, 100, 1), (0.1, 200, 1), (0.1, 50, 1), (0.25, 400, 2), (0.25, 200, 2),
       (0.25, 100, 3)]

# "inaccurate" thresholds (docs/stability.md): relative to the reference, or absolute where said
THRESHOLDS = {"dp_rel": 0.10, "bed_height_rel": 0.10, "jet_rel": 0.25, "eps_rms_ratio": 2.0, "floor_share": 0.0, "overlap": 0.05}


def grid(cell_d):
    """Gas grid for gas cells cell_d particle diameters wide: (nx, ny, ratio_x, ratio_y). Below 3.5 d the particle
    cells stay 2.256 x 2.8 mm (3 x 3.7 d) and the gas cells are 1.4 mm tall (the seed's fine grid); above, square
    cells of cell_d d serve both (ratio 1, the single grid is the only choice)."""
    if cell_d >= 3.5:
        nx = int(round(LX / (cell_d * D)))
        return nx, int(round(LY / (LX / nx))), 1, 1
    rx = max(1, int(round(3.0 / cell_d)))
    return NXP * rx, int(round(LY / HY)), rx, 2


def cells(p):
    """The point's gas grid and particle cells (nx, ny, ratio_x, ratio_y): grid(cell_d), with the ratio map's own
    particle cells."""
    nx, ny, rx, ry = grid(p["cell_d"])
    return (nx, ny) + tuple(p["ratio"]) if p.get("ratio") else (nx, ny, rx, ry)


def slit(nx, jet):
    """The slit nearest the seed's width whose edges lie on gas cell faces, centred at JET_X, carrying the seed's flow
    scaled by jet / 45.3: (width, velocity)."""
    h = LX / nx
    centre = JET_X / h  # in cells: whole on a face (an even count), half on a cell centre (odd)
    odd = abs(centre - math.floor(centre) - 0.5) < 1e-6
    n = max(1, int(round(JET_W / h)))
    if (n % 2 == 1) != odd:
        n = n + 1 if abs((n + 1) * h - JET_W) < abs((n - 1) * h - JET_W) or n == 1 else n - 1
    w = n * h
    return w, jet * JET_W / w


def point_id(p):
    """The point's run directory: points of two maps with the same options share one run."""
    if p["map"] == "jet_sub" and all(p[k] == REFERENCE[k] for k in ("method", "cell_d", "dt_factor", "jet", "substeps")):
        return point_id(REFERENCE)
    if p["map"] == "closed":
        return "closed_dt%g" % p["dt_factor"]
    if p["map"] == "3d":
        return "3d_%s_%s_dt%g" % (p["grid3d"], p["method"], p["dt_factor"])
    ratio = "_p%dx%d" % tuple(p["ratio"]) if p.get("ratio") else ""
    kn = "_kn%g" % p["kn"] if p.get("kn") else ""
    kn += "_g%d" % p["gas_substeps"] if p.get("gas_substeps", 1) > 1 else ""
    return "%s_%s_cell%g_dt%g_jet%g_sub%d%s%s%s" % (p["map"], p["method"], p["cell_d"], p["dt_factor"], p["jet"], p["substeps"], ratio, kn, p.get("tag", ""))


def options(p, args, settled):
    if p["map"] == "closed":
        return ["-options_file", CLOSED, "-max_steps", "-1", "-t_final", args.closed_time, "-dem_dt_factor", p["dt_factor"],
                "-guard_energy_interval", "10", "-output_particles", "0"]
    if p["map"] == "3d":
        nx, ny, nz, ratio = GRIDS3D[p["grid3d"]]
        t = args.t3d
        return ["-options_file", SCENE3D, "-grid_nx", nx, "-grid_ny", ny, "-grid_nz", nz, "-pgrid_ratio", ratio, "-couple_grid", p["method"],
                "-dem_dt_factor", p["dt_factor"], "-insert_type", "file", "-insert_file", settled[1], "-t_final", t, "-average_start", 0.5 * t,
                "-average_interval", 5e-4, "-output_interval", t / 20, "-checkpoint_interval", "0", "-output_particles", "0",
                "-fluid_output_cells", "0", "-monitor_dt", 5e-4]
    settled = settled[0] if settled else None
    nx, ny, rx, ry = cells(p)
    w, v = slit(nx, p["jet"])
    t = args.t_final
    o = ["-options_file", SCENE, "-grid_nx", nx, "-grid_ny", ny, "-pgrid_ratio", "%d,%d" % (rx, ry), "-couple_grid", p["method"],
         "-inlet_jets", "%.9g,%.9g,%.9g" % (JET_X, w, v), "-dem_dt_factor", p["dt_factor"], "-couple_substeps", p["substeps"],
         "-t_final", t, "-average_start", 0.5 * t, "-average_interval", 5e-4, "-output_interval", t / 20, "-output_particles", "0",
         "-fluid_output_cells", "0", "-monitor_dt", 5e-4]
    if p.get("kn"):  # walls follow (-wall_kn defaults to -dem_kn), and the step follows the spring's own t_cr
        o += ["-dem_kn", p["kn"]]
    if p.get("gas_substeps", 1) > 1:
        o += ["-couple_gas_substeps", p["gas_substeps"]]
    if settled:  # the reference's "_mirror" twin starts from the same bed mirrored about the slit: its own noise
        o += ["-insert_type", "file", "-insert_file", settled.replace(".csv", "_mirror.csv") if p.get("tag") == "_mirror" else settled]
    return o


def eps_rms(outdir, t0):
    """Mean over the bed's gas cells (time-mean void fraction below 0.9) of the standard deviation in time of the cell
    void fraction, over the snapshots from t0 on."""
    frames = []
    for path in sorted(glob.glob(os.path.join(outdir, "snapshot_*.h5"))):
        import h5py
        with h5py.File(path, "r") as f:
            if float(f.attrs["time"]) >= t0 - 1e-12 and "fluid" in f:
                frames.append(np.asarray(f["fluid/void_fraction"]).ravel())
    if len(frames) < 3:
        return float("nan")
    a = np.array(frames)
    bed = a.mean(axis=0) < 0.9
    return float(a.std(axis=0)[bed].mean()) if bed.any() else float("nan")


def measure(p, s, status, wall, outdir, args):
    """The point's figures from its summary.json and snapshots."""
    m = {"id": point_id(p), "exit_status": status, "wall_s": round(wall, 2)}
    m.update({k: p.get(k) for k in ("map", "method", "cell_d", "dt_factor", "jet", "substeps", "kn", "gas_substeps")})
    if p["map"] == "3d":
        nx, ny, nz, ratio = GRIDS3D[p["grid3d"]]
        m.update({"gas_cells": "%dx%dx%d" % (nx, ny, nz), "cells_per_particle_cell": ratio.replace(",", "x"), "cell_d": round(LX / nx / D, 3)})
    elif p["map"] != "closed":
        nx, ny, rx, ry = cells(p)
        m.update({"gas_cells": "%dx%d" % (nx, ny), "cells_per_particle_cell": "%dx%d" % (rx, ry), "slit_mm": round(1e3 * slit(nx, p["jet"])[0], 4)})
    if s is None:
        m["status"] = "refused" if status == 2 else "failed"
        return m
    gf = s.get("guard_figures", {})
    m.update({"status": s["status"], "guard": s.get("guard", ""), "guard_time": s.get("guard_time", ""), "t_end": s["time"],
              "overlap_max": gf.get("overlap_max"), "displacement_max": gf.get("displacement_max"), "energy_growth_max": gf.get("energy_growth_max"),
              "floor_share_max": gf.get("floor_share_max"), "eps_raw_min": gf.get("eps_raw_min"), "courant_max": gf.get("courant_max"),
              "particles_out": s.get("particles_outlet"), "particles": s.get("particles_inserted"), "ranks": s.get("ranks")})
    if "fluid" in s:
        m["ksp_its"] = s["fluid"].get("pressure_iterations_per_solve")
    if s["time"] > 0:
        cost, share = outputs.run_cost(s)
        m["cost_s_per_s_core"] = round(cost, 1)
        m["cpu_share"] = round(share, 3) if share == share else ""
    av = s.get("averages")
    if av and av.get("samples", 0) > 0 and s["status"] != "stopped":
        depth = 0.00495 if p["map"] == "3d" else LZ
        weight = s["particles_inserted"] * math.pi / 6 * D ** 3 * (RHO_P - RHO_G) * G / (LX * depth)
        m.update({"dp_over_weight": av["pressure_drop_mean_Pa"] / weight, "bed_height_mm": 1e3 * av["expanded_bed_height_volume_m"],
                  "jet_mm": 1e3 * av["jet_penetration_height_m"], "eps_rms": eps_rms(outdir, 0.5 * args.t_final)})
    return m


def classify(m, ref, tol):
    """stable / inaccurate / unstable, and why."""
    if m.get("status") in ("stopped", "refused", "failed"):
        why = m.get("guard") or m.get("status")
        return "unstable", why
    if m["map"] == "closed" or "dp_over_weight" not in m:
        return "stable", ""
    off = []
    ref = ref or {}
    rel = lambda k: abs(m[k] / ref[k] - 1) if ref.get(k) else 0.0  # noqa: E731
    if rel("dp_over_weight") > tol["dp_rel"]:
        off.append("dp %+.0f%%" % (100 * (m["dp_over_weight"] / ref["dp_over_weight"] - 1)))
    if rel("bed_height_mm") > tol["bed_height_rel"]:
        off.append("bed height %+.0f%%" % (100 * (m["bed_height_mm"] / ref["bed_height_mm"] - 1)))
    if ref.get("jet_mm", 0) > 0 and rel("jet_mm") > tol["jet_rel"]:
        off.append("jet %+.0f%%" % (100 * (m["jet_mm"] / ref["jet_mm"] - 1)))
    if ref.get("eps_rms") and m["eps_rms"] > tol["eps_rms_ratio"] * ref["eps_rms"]:
        off.append("eps rms x%.1f" % (m["eps_rms"] / ref["eps_rms"]))
    if (m.get("floor_share_max") or 0) > tol["floor_share"]:
        off.append("cells at the floor")
    if (m.get("overlap_max") or 0) > tol["overlap"]:
        off.append("overlap %.2f d" % m["overlap_max"])
    out = m.get("particles_out") or 0
    note = "%.0f%% of the bed left through the top" % (100.0 * out / m["particles"]) if out and m.get("particles") else ""
    return ("inaccurate", "; ".join(off + ([note] if note else []))) if off else ("stable", note)


def reference_of(m, results, ref):
    """What a point is judged against: the reference for the cell_dt map and for the seed's jet at one gas step per DEM
    step; a jet_sub point with substeps against the same method and jet at one substep (whether substepping changes
    the answer), and at another jet with one substep nothing (only the absolute measures: overlap, cells at the floor),
    since a faster jet makes another bed; a 3D point against the 3D fine grid at t_cr/20 (when it has run)."""
    if m["map"] == "3d":  # against the 3D reference, the fine grid at t_cr/20 (a 2D bed is another bed)
        r3 = results.get(("3d", "3d_fine_two_dt0.05"))
        return r3 if r3 and r3.get("status") != "stopped" and m["id"] != r3["id"] else None
    if m["map"] != "jet_sub":
        return ref
    if m["substeps"] > 1:
        p = {k: m[k] for k in ("map", "method", "cell_d", "dt_factor", "jet")}
        p["substeps"] = 1
        one = results.get(("jet_sub", point_id(p))) or results.get(("cell_dt", point_id(p)))
        return one if one and one.get("status") != "stopped" else None
    return ref if m["jet"] == REFERENCE["jet"] else None


def points(maps, ci):
    pts = []
    if ci:  # one stable and one unstable point per method, on a short window
        for method, cell, dt in (("two", 0.43, 0.1), ("two", 0.43, 1.5), ("single", 3, 0.1), ("single", 0.43, 0.1)):
            pts.append({"map": "cell_dt", "method": method, "cell_d": cell, "dt_factor": dt, "jet": JET_V, "substeps": 1})
        return pts
    if "cell_dt" in maps:
        for cell in (4, 3, 1.5, 1, 0.43):
            for dt in (0.05, 0.1, 0.25, 0.5, 1.0, 1.5):
                for method in (("single",) if cell >= 3.5 else ("two", "single")):
                    pts.append({"map": "cell_dt", "method": method, "cell_d": cell, "dt_factor": dt, "jet": JET_V, "substeps": 1})
        pts.append(dict(REFERENCE, tag="_mirror"))
    if "jet_sub" in maps:
        for jet in (45.3, 68.0, 100.0, 150.0):
            for sub in (1, 2, 4, 10):
                # each method at its own best cells and the reference's step: the two grids at the seed's 0.43 d, the
                # single grid at 4 d (its finer cells overfill with particle centres, the cell_dt map shows)
                for method, cell in (("two", 0.43), ("single", 4)):
                    pts.append({"map": "jet_sub", "method": method, "cell_d": cell, "dt_factor": REFERENCE["dt_factor"], "jet": jet, "substeps": sub})
    if "3d" in maps:  # the most telling points on the seed's own 3D grids
        for g3, method, dt in (("fine", "two", 0.1), ("fine", "two", 0.05), ("fine", "single", 0.1), ("coarse", "two", 0.1),
                               ("coarse", "single", 0.1), ("coarse", "two", 0.5), ("coarse", "two", 1.0)):
            pts.append({"map": "3d", "grid3d": g3, "method": method, "dt_factor": dt, "jet": JET_V, "substeps": 1})
    if "ratio" in maps:
        for r in RATIOS:
            pts.append({k: REFERENCE[k] for k in ("method", "cell_d", "dt_factor", "jet", "substeps")} | {"map": "ratio", "ratio": r})
    if "kn" in maps:
        for dt, kn, gas in KNS:
            pts.append({"map": "kn", "method": "two", "cell_d": 3, "dt_factor": dt, "jet": JET_V, "substeps": 1, "kn": kn, "gas_substeps": gas})
    if "closed" in maps:
        for dt in (0.05, 0.1, 0.25, 0.5, 1.0, 1.5):
            pts.append({"map": "closed", "dt_factor": dt})
    return pts


def settle(args):
    """The settled bed every point starts from (and its mirror image about the slit): the scene's particles settled
    without gas for --settle seconds."""
    path = os.path.join(args.out, "settled", "particles.csv")
    s, status, _, reused = study.run(["-options_file", SCENE, "-fluid", "0", "-t_final", args.settle, "-output_particles", "1",
                                      "-domain_top_outlet", "0"], os.path.dirname(path), args.ranks, args.exe)
    if status != 0:
        sys.exit("stability_map: settling the bed failed (exit %d), see %s/stdout.txt" % (status, os.path.dirname(path)))
    mirror = path.replace(".csv", "_mirror.csv")
    if not os.path.isfile(mirror) or not reused:
        outputs.mirror_particles(path, mirror, LX)
    study.log("settled bed: %d particles (%s)" % (s["particles"], "reused" if reused else "settled for %g s" % args.settle))
    path3d = args.bed3d
    if "3d" in args.maps.split(",") and not path3d:
        path3d = os.path.join(args.out, "settled3d", "particles.csv")
        s3, status, _, _ = study.run(["-options_file", BED3D, "-output_particles", "1"], os.path.dirname(path3d), max(args.ranks, 2), args.exe)
        if status != 0:
            sys.exit("stability_map: settling the 3D bed failed (exit %d)" % status)
        study.log("settled 3D bed: %d particles" % s3["particles"])
    return path, path3d


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    style = {"stable": ("o", "tab:green"), "inaccurate": ("^", "tab:orange"), "unstable": ("x", "tab:red")}
    fig, axes = plt.subplots(2, 3, figsize=(15, 9))
    for col, method in enumerate(("two", "single")):
        for row, (mp, xk, yk, xl, yl) in enumerate((("cell_dt", "cell_d", "dt_factor", "gas cell width / d", "-dem_dt_factor"),
                                                    ("jet_sub", "jet", "substeps", "jet velocity (m/s)", "-couple_substeps"))):
            ax = axes[row][col]
            for r in rows:
                if r["map"] != mp or r["method"] != method or r.get("id", "").endswith("_mirror"):
                    continue
                mk, c = style[r["class"]]
                ax.scatter(float(r[xk]), float(r[yk]), marker=mk, c=c, s=80)
                if r["class"] != "stable":
                    ax.annotate((r["why"] or "")[:14], (float(r[xk]), float(r[yk])), fontsize=6, xytext=(4, 4), textcoords="offset points")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel(xl)
            ax.set_ylabel(yl)
            ax.set_title("%s grid%s: %s" % ("two" if method == "two" else "single", "s" if method == "two" else "", mp))
    ax = axes[0][2]
    closed = sorted((r for r in rows if r["map"] == "closed"), key=lambda r: float(r["dt_factor"]))
    if closed:
        x = [float(r["dt_factor"]) for r in closed]
        for key, lab in (("energy_growth_max", "energy growth"), ("overlap_max", "largest overlap / d"),
                         ("displacement_max", "largest step displacement / d")):
            ax.semilogy(x, [max(float(r.get(key) or 0), 1e-6) for r in closed], "-", lw=1, label=lab + " (1e-6: none)")
            for xi, r in zip(x, closed):
                mk, c = style[r["class"]]
                ax.scatter(xi, max(float(r.get(key) or 0), 1e-6), marker=mk, c=c, s=50, zorder=3)
        ax.axhline(0.1, color="grey", ls=":", lw=1)
        ax.set_xlabel("-dem_dt_factor")
        ax.set_ylabel("closed-box measure (dotted: 0.1)")
        ax.set_title("closed box: 3000 spheres, pure DEM")
        ax.legend(fontsize=7)
    axes[1][2].axis("off")
    for k, (mk, c) in style.items():
        axes[1][2].scatter([], [], marker=mk, c=c, label=k)
    axes[1][2].legend(loc="center", fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--maps", default="cell_dt,jet_sub,closed", help="which maps (comma-separated): cell_dt, jet_sub, closed, 3d, ratio, kn")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "stability"), help="working directory of the runs (kept: the study resumes)")
    ap.add_argument("--csv", default=os.path.join(ROOT, "docs", "stability", "stability_map.csv"), help="the table of every point")
    ap.add_argument("--png", default=os.path.join(ROOT, "docs", "figures", "stability_map.png"), help="the map")
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks per point")
    ap.add_argument("--jobs", type=int, default=1, help="points run side by side")
    ap.add_argument("--t-final", type=float, default=0.05, help="bed time per point (s); the second half is averaged")
    ap.add_argument("--settle", type=float, default=0.25, help="settling time of the shared initial bed (s)")
    ap.add_argument("--closed-time", type=float, default=0.01, help="bed time of the closed-box points (s)")
    ap.add_argument("--t3d", type=float, default=0.03, help="bed time of the 3D points (s)")
    ap.add_argument("--bed3d", default=None, help="a settled 3D bed (particles.csv of examples/dem/bed750.opts) instead of settling one")
    ap.add_argument("--exe", default=run.EXE)
    ap.add_argument("--fresh", action="store_true", help="run every point again (its cost measured anew), even if finished")
    ap.add_argument("--report", action="store_true", help="only tabulate and draw the points already finished (run nothing)")
    ap.add_argument("--ci", action="store_true", help="two points per method from a lattice (no settling), a short window")
    args = ap.parse_args()
    maps = args.maps.split(",")
    if args.ci:
        args.t_final = min(args.t_final, 0.003)
    os.makedirs(args.out, exist_ok=True)
    settled = None if args.ci else settle(args)

    def work(p):
        outdir = os.path.join(args.out, point_id(p))
        s, status, wall, reused = study.run(options(p, args, settled), outdir, args.ranks, args.exe, fresh=args.fresh)
        return measure(p, s, status, wall, outdir, args), reused

    pts = points(maps, args.ci)
    if args.report:
        pts = [p for p in pts if run.done(options(p, args, settled), os.path.join(args.out, point_id(p)), args.ranks, args.exe)]
    results = {}
    ref_point = [p for p in pts if point_id(p) == point_id(REFERENCE)] or ([] if args.ci else [REFERENCE])
    if ref_point and not args.ci and (not args.report or ref_point[0] in pts):  # the reference first: the others are judged against it
        results[("cell_dt", point_id(REFERENCE))] = work(REFERENCE)[0]
    for p, (m, reused) in study.run_all([p for p in pts if (p["map"], point_id(p)) not in results], args.jobs, work):
        results[(m["map"], m["id"])] = m
        study.log("%-55s %-8s %s%s" % (m["id"], m.get("status"), m.get("guard", ""), " (reused)" if reused else " %.0f s" % m["wall_s"]))
    ref = results.get(("cell_dt", point_id(REFERENCE)))
    tol = dict(THRESHOLDS)
    mirror = results.get(("cell_dt", point_id(dict(REFERENCE, tag="_mirror"))))
    if ref and mirror and "dp_over_weight" in mirror and "dp_over_weight" in ref:
        # the reference's own spread (the same bed mirrored) sets a floor under the relative thresholds
        for k, key in (("dp_rel", "dp_over_weight"), ("bed_height_rel", "bed_height_mm"), ("jet_rel", "jet_mm")):
            if ref.get(key):
                tol[k] = max(tol[k], 2 * abs(mirror[key] / ref[key] - 1))
    rows = []
    for m in results.values():
        m["class"], m["why"] = classify(m, reference_of(m, results, ref) if not args.ci else None, tol)
        rows.append(m)
    rows.sort(key=lambda r: r["id"])
    keys = ["id", "map", "method", "cell_d", "dt_factor", "kn", "jet", "substeps", "gas_substeps", "gas_cells", "cells_per_particle_cell", "slit_mm", "class", "why",
            "status", "exit_status", "guard", "guard_time", "t_end", "dp_over_weight", "bed_height_mm", "jet_mm", "eps_rms", "floor_share_max",
            "eps_raw_min", "overlap_max", "displacement_max", "energy_growth_max", "courant_max", "ksp_its", "particles_out", "ranks", "wall_s",
            "cost_s_per_s_core", "cpu_share"]
    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.4g" % r[k] if isinstance(r.get(k), float) else r.get(k, "")) for k in keys})
    with open(os.path.splitext(args.csv)[0] + "_thresholds.json", "w") as f:
        json.dump({"thresholds": tol, "reference": ref}, f, indent=1)
    if not args.ci and set(maps) & {"cell_dt", "jet_sub", "closed"}:  # the map's panels (the 3d and ratio points are tables)
        os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
        plot(rows, args.png)
    counts = {c: sum(r["class"] == c for r in rows) for c in ("stable", "inaccurate", "unstable")}
    study.log("stability map: %d points (%s); table %s" % (len(rows), ", ".join("%d %s" % (n, c) for c, n in counts.items()), args.csv))


if __name__ == "__main__":
    main()
