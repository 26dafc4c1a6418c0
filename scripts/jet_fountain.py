#!/usr/bin/env python3
"""The jet column of a time-averaged jetting bed: how high the fountain rises and how fast the particles in the jet
move (seed chapter 5: "the height to which the fountain rises is close to 120 mm", "the central solid velocity ...
about 0.85 m/s"). Reads analysis.h5: the solid fraction and particle velocity of the particle-grid column holding
the jet (--x, default the middle of the bed), averaged over the depth. The fountain height at a threshold is where
the column's solid fraction, scanned down from the top, first reaches the threshold (linear between cell centres):
the seed reads it off void-fraction contours, so several thresholds are given. Prints the figures and, with
--json, writes them.

--since takes an earlier copy of the same run's analysis.h5 (written with -average_output_interval): the averages
are running means over the samples, so the window between the two copies is (N2 m2 - N1 m1) / (N2 - N1) for the
solid fraction and the solid flux; the particle velocity is then the flux over the solid fraction (the
volume-weighted mean, the same as sum v / sum N for equal particles). This leaves a start-up transient out.

--snapshots t0,t1 measures the fountain from the snapshots written in [t0, t1] instead of the running averages: the
gas's void fraction (in a two-grid run that of the particle cells) over the fluid cells whose centres lie in the jet's
particle-grid column, averaged over the depth and over the snapshots. With --blocks N the snapshots are also cut into N
consecutive blocks, each measured alone: the spread of the blocks' heights gives the window's statistical uncertainty
(the standard error of their mean), and two runs on different grids (grid sensitivity) compare by the same method.

--merge x1,x2 takes two jets (seed Fig. 5.13: the double jets "merge near the distributor plate"): the merge height
is the lowest point where the solid fraction of the column midway between them, scanned up from the bottom, first
falls to the mean of the two jet columns' (linear between cell centres): below it the two jets are separate voids
with denser solid between them, above it one.

    scripts/jet_fountain.py output/run [--x 0.0282] [--thresholds 0.1,0.05,0.02] [--below 0.25] [--since early/analysis.h5]
                            [--merge 0.0137,0.0427] [--snapshots 5.0,8.0 --blocks 6] [--json jet.json]"""

import json
import os

from fluidbed_tools import plot as fp
from fluidbed_tools.stats import standard_error
import numpy as np


def column_index(origin, spacing, cells, x):
    """The particle-grid column holding x (clamped to the grid)."""
    return int(min(max(np.floor((x - origin) / spacing), 0), cells - 1))


def fountain_height(heights, solid_fraction, threshold):
    """Highest point where the profile solid_fraction(heights) (cell centres, increasing) reaches threshold, scanning
    down from the top and interpolating linearly between the two cell centres that bracket the crossing; NaN when
    the column never reaches it; the top cell centre when the top cell is at or above it."""
    h = np.asarray(heights, dtype=float)
    s = np.asarray(solid_fraction, dtype=float)
    above = np.nonzero(s >= threshold)[0]
    if above.size == 0:
        return float("nan")
    k = above[-1]
    if k == len(s) - 1:
        return float(h[k])
    return float(h[k] + (s[k] - threshold) / (s[k] - s[k + 1]) * (h[k + 1] - h[k]))


def merge_height(heights, solid_fraction_mid, solid_fraction_jets):
    """Lowest point where solid_fraction_mid (the column between two jets) first falls to solid_fraction_jets (the
    jet columns' mean), scanning up from the bottom cell centre and interpolating linearly between the two cell
    centres that bracket the crossing; NaN when it never does; the bottom cell centre when it already has."""
    h = np.asarray(heights, dtype=float)
    d = np.asarray(solid_fraction_mid, dtype=float) - np.asarray(solid_fraction_jets, dtype=float)
    at = np.nonzero(d <= 0)[0]
    if at.size == 0:
        return float("nan")
    k = at[0]
    if k == 0:
        return float(h[0])
    return float(h[k - 1] + d[k - 1] / (d[k - 1] - d[k]) * (h[k] - h[k - 1]))


def window_between(early, late):
    """The averages over the samples of `late` that came after those of `early` (two copies of one run's
    analysis.h5, dicts of arrays): solid fraction and solid flux by difference of the running means, velocity as
    flux / solid fraction (NaN where no solid)."""
    n1, n2 = float(early["measures/samples"][0]), float(late["measures/samples"][0])
    if not n2 > n1:
        fp.die("--since: the earlier file has %d samples, the run %d: give a copy written earlier in the same run" % (n1, n2))
    for key in ("grid/origin", "grid/spacing", "grid/cells"):
        if not np.array_equal(early[key], late[key]):
            fp.die("--since: the two files have different grids (%s)" % key)
    w = dict(late)
    sf = (n2 * late["fields/solid_fraction"] - n1 * early["fields/solid_fraction"]) / (n2 - n1)
    flux = (n2 * late["fields/solid_flux"] - n1 * early["fields/solid_flux"]) / (n2 - n1)
    with np.errstate(invalid="ignore", divide="ignore"):
        w["fields/velocity"] = np.where(sf[..., None] > 0, flux / sf[..., None], np.nan)
    w["fields/solid_fraction"] = sf
    w["fields/solid_flux"] = flux
    w["measures/samples"] = np.array([n2 - n1])
    w["measures/window_start"] = early["measures/window_end"]
    return w


def jet_column(a, x):
    """Heights, solid fraction and vertical particle velocity of the column holding x (depth means)."""
    lo, h, n = a["grid/origin"], a["grid/spacing"], a["grid/cells"].astype(int)
    dim = a["fields/solid_fraction"].ndim
    i = column_index(lo[0], h[0], n[0], x)
    sf = fp.depth_mean(a["fields/solid_fraction"], dim)[:, i]
    with np.errstate(invalid="ignore"):
        vy = fp.depth_mean(a["fields/velocity"], dim)[:, i, 1]
    y = lo[1] + (np.arange(n[1]) + 0.5) * h[1]
    return i, lo[0] + (i + 0.5) * h[0], y, sf, vy


def snapshot_column(run, x0, x1, t0, t1):
    """Solid fraction (1 - the gas's void fraction, depth mean) of the fluid cells whose centres lie in [x0, x1], per
    snapshot written in [t0, t1]: (times, heights of the fluid cell centres, profiles (snapshots, ny))."""
    lo, hi = fp.box(run)
    times, profiles = [], []
    for path in fp.snapshots(run):
        void, time, source = fp.snapshot_void_fraction(path, lo, hi, (1, 1, 1))
        if not t0 - 1e-5 <= time <= t1 + 1e-5:  # a snapshot lands within a step of its time
            continue
        if source != "gas":
            fp.die("--snapshots: %s holds no gas void fraction" % path)
        ny, nx = void.shape
        xc = lo[0] + (np.arange(nx) + 0.5) * (hi[0] - lo[0]) / nx
        cols = (xc >= x0) & (xc <= x1)
        if not cols.any():
            fp.die("--snapshots: no fluid cell centre lies in the column %g-%g m" % (x0, x1))
        times.append(time)
        profiles.append(1.0 - void[:, cols].mean(axis=1))
    if len(times) < 1:
        fp.die("--snapshots %g,%g: no snapshot of %s was written in that window" % (t0, t1, run))
    ny = len(profiles[0])
    y = lo[1] + (np.arange(ny) + 0.5) * (hi[1] - lo[1]) / ny
    return np.array(times), y, np.array(profiles)


def snapshot_fountain(y, profiles, thresholds, blocks, below):
    """Fountain heights of the mean of the profiles and, with blocks > 1, of each of `blocks` consecutive blocks of
    them, with the blocks' mean and its standard error."""
    if below is not None:
        keep = y < below
        y, profiles = y[keep], profiles[:, keep]
    out = {"snapshots": len(profiles),
           "fountain_height_m": {"%g" % t: fountain_height(y, profiles.mean(axis=0), t) for t in thresholds}}
    if blocks > 1:
        if blocks > len(profiles):
            fp.die("--blocks %d: only %d snapshots in the window" % (blocks, len(profiles)))
        parts = np.array_split(profiles, blocks)
        per = {"%g" % t: [fountain_height(y, b.mean(axis=0), t) for b in parts] for t in thresholds}
        out["blocks"] = {k: {"heights_m": v, "mean_m": float(np.mean(v)),
                             "standard_error_m": standard_error(v)} for k, v in per.items()}
    return out


def main():
    ap = fp.parser(__doc__, single_run=False)
    ap.add_argument("run", help="run directory (fluidbed -output_dir) holding analysis.h5")
    ap.add_argument("--x", type=float, help="x of the jet in m (default: the middle of the bed)")
    ap.add_argument("--thresholds", default="0.1,0.05,0.02", help="solid fractions that mark the fountain's top")
    ap.add_argument("--below", type=float, help="consider only cells whose centres lie below this height (m), e.g. to leave out "
                    "particles held against a closed top")
    ap.add_argument("--since", help="an earlier copy of the run's analysis.h5: report the window between the two")
    ap.add_argument("--merge", help="x1,x2 of two jets in m: report where they merge (the midway column's solid fraction "
                    "falls to the jet columns' mean)")
    ap.add_argument("--snapshots", help="t0,t1 in s: measure the fountain from the snapshots written in this window")
    ap.add_argument("--blocks", type=int, default=1, help="with --snapshots: also measure it in this many consecutive blocks "
                    "of the snapshots (their spread gives the uncertainty)")
    ap.add_argument("--json", help="write the figures to this file")
    args = ap.parse_args()

    a = fp.read_analysis(args.run)
    if args.since:
        if not os.path.isfile(args.since):
            fp.die("--since: no file %s" % args.since)
        a = window_between(fp.read_h5(args.since), a)
    lo, h, n = a["grid/origin"], a["grid/spacing"], a["grid/cells"].astype(int)
    x = args.x if args.x is not None else lo[0] + 0.5 * n[0] * h[0]
    i, xc, y, sf, vy = jet_column(a, x)
    cross = np.nanmean(fp.depth_mean(a["fields/solid_fraction"], a["fields/solid_fraction"].ndim), axis=1)
    if args.below is not None:
        keep = y < args.below
        if not keep.any():
            fp.die("--below %g: no cell centre lies below it" % args.below)
        y, sf, vy, cross = y[keep], sf[keep], vy[keep], cross[keep]
    thresholds = [float(s) for s in args.thresholds.split(",")]
    out = {
        "window_s": [float(a["measures/window_start"][0]), float(a["measures/window_end"][0])],
        "samples": int(a["measures/samples"][0]),
        "column": i,
        "column_x_m": [float(lo[0] + i * h[0]), float(lo[0] + (i + 1) * h[0])],
        "fountain_height_m": {"%g" % t: fountain_height(y, sf, t) for t in thresholds},
        # the highest layer whose cross-section mean solid fraction reaches 0.1, as fountain_height finds it
        "bed_height_cross_section_0.1_m": fountain_height(y, cross, 0.1),
        "below_m": args.below,
        "jet_max_velocity_y_m_s": float(np.nanmax(vy)),
        "jet_max_velocity_y_height_m": float(y[int(np.nanargmax(vy))]),
    }
    if args.blocks != 1 and not args.snapshots:
        fp.die("--blocks %d: give --snapshots t0,t1 as well (the blocks cut the snapshots' window)" % args.blocks)
    if args.snapshots:
        try:
            t0, t1 = (float(v) for v in args.snapshots.split(","))
        except ValueError:
            fp.die("--snapshots %s: give a window in s, t0,t1" % args.snapshots)
        if args.blocks < 1:
            fp.die("--blocks %d: give at least 1" % args.blocks)
        times, ys, profiles = snapshot_column(args.run, out["column_x_m"][0], out["column_x_m"][1], t0, t1)
        out["from_snapshots"] = snapshot_fountain(ys, profiles, thresholds, args.blocks, args.below)
        out["from_snapshots"]["window_s"] = [float(times.min()), float(times.max())]
    if args.merge:
        try:
            x1, x2 = (float(v) for v in args.merge.split(","))
        except ValueError:
            fp.die("--merge %s: give two x positions in m, x1,x2" % args.merge)
        cols = [jet_column(a, xj) for xj in (x1, x2, 0.5 * (x1 + x2))]
        if len({c[0] for c in cols}) < 3:
            fp.die("--merge %s: the two jets and the column midway between them must be three different particle-grid "
                   "columns (%d, %d, %d)" % (args.merge, cols[0][0], cols[1][0], cols[2][0]))
        keep = slice(None) if args.below is None else cols[2][2] < args.below
        jets = 0.5 * (cols[0][3] + cols[1][3])
        mid_sf, mid_vy, ym = cols[2][3][keep], cols[2][4][keep], cols[2][2][keep]
        out["merge"] = {
            "jet_columns": [cols[0][0], cols[1][0]],
            "mid_column": cols[2][0],
            "merge_height_m": merge_height(ym, mid_sf, jets[keep]),
            "mid_solid_fraction_bottom": float(mid_sf[0]),
            "mid_max_velocity_y_m_s": float(np.nanmax(mid_vy)),
            "mid_max_velocity_y_height_m": float(ym[int(np.nanargmax(mid_vy))]),
        }
    print("window %.3f-%.3f s (%d samples); jet column %d (x %.2f-%.2f mm)" %
          (out["window_s"][0], out["window_s"][1], out["samples"], i, out["column_x_m"][0] * fp.MM, out["column_x_m"][1] * fp.MM))
    for t, v in out["fountain_height_m"].items():
        print("fountain height at solid fraction %s: %.1f mm" % (t, v * fp.MM))
    print("bed height (cross-section mean solid fraction 0.1): %.1f mm" % (out["bed_height_cross_section_0.1_m"] * fp.MM))
    print("largest upward particle velocity in the jet column: %.3f m/s at %.1f mm" %
          (out["jet_max_velocity_y_m_s"], out["jet_max_velocity_y_height_m"] * fp.MM))
    if args.snapshots:
        sn = out["from_snapshots"]
        print("from %d snapshots, %.3f-%.3f s:" % (sn["snapshots"], sn["window_s"][0], sn["window_s"][1]))
        for k, v in sn["fountain_height_m"].items():
            line = "  fountain height at solid fraction %s: %.1f mm" % (k, v * fp.MM)
            if "blocks" in sn:
                b = sn["blocks"][k]
                line += "; %d blocks: %.1f +- %.1f mm (%s)" % (len(b["heights_m"]), b["mean_m"] * fp.MM, b["standard_error_m"] * fp.MM,
                                                            ", ".join("%.1f" % (z * fp.MM) for z in b["heights_m"]))
            print(line)
    if args.merge:
        m = out["merge"]
        print("jets in columns %d and %d merge at %.1f mm (midway column %d: solid fraction %.3f at the bottom; largest "
              "upward particle velocity %.3f m/s at %.1f mm)" % (m["jet_columns"][0], m["jet_columns"][1], m["merge_height_m"] * fp.MM,
              m["mid_column"], m["mid_solid_fraction_bottom"], m["mid_max_velocity_y_m_s"], m["mid_max_velocity_y_height_m"] * fp.MM))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
