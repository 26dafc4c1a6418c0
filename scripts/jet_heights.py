#!/usr/bin/env python3
"""Instantaneous jet heights of a jetting bed's snapshots at several void-fraction thresholds. The run measures its
jet heights as it goes (seed chapter 4, first bubble detachment; analysis.h5 /series/jet_height) at one threshold,
-average_jet_void_fraction; this reads the gas void fraction of the snapshots written after --from and gives, for
each threshold, the distribution of the heights of the region connected to each inlet: how much the figure owes to
the threshold. The region and its height are those of include/fluidbed/kernels/jet_height.hpp (cells above the
threshold connected through faces to the inlet's bottom-row cells; the top crossing interpolated between cell
centres; a region reaching the top layer gives the grid height), on a 2D run's grid or a 3D run's averaged over the
depth. --max-height leaves out regions that join a bubble reaching the freeboard.

    scripts/jet_heights.py output/run [--from 5.0] [--thresholds 0.8,0.7,0.6,0.5] [--max-height 0.1] [--json jets.json]"""

import json

from fluidbed_tools import plot as fp
import h5py
import numpy as np


def inlet_cells(slot, x0, hx, nx):
    """The bottom-row columns of a slit [x_lo, x_hi]: those whose centre lies in it, or, for a slit narrower than a
    cell, the one holding its centre (kernels/jet_height.hpp, jet_inlet_cells)."""
    centres = x0 + (np.arange(nx) + 0.5) * hx
    cells = [i for i in range(nx) if slot[0] <= centres[i] <= slot[1]]
    return cells or [min(max(int((0.5 * (slot[0] + slot[1]) - x0) // hx), 0), nx - 1)]


def region(void, inlets, threshold):
    """Cells of void (ny, nx) above threshold connected through faces to the bottom-row cells inlets (a flag array)."""
    above = void > threshold
    r = np.zeros_like(above)
    r[0, inlets] = above[0, inlets]
    if not r.any():
        return r
    while True:
        n = r.copy()
        n[1:] |= r[:-1]
        n[:-1] |= r[1:]
        n[:, 1:] |= r[:, :-1]
        n[:, :-1] |= r[:, 1:]
        n &= above
        if (n == r).all():
            return r
        r = n


def height(void, r, threshold, hy):
    """Top of the region r: the highest upward crossing of threshold, linear between cell centres (m)."""
    top = 0.0
    for j, i in zip(*np.nonzero(r)):
        if j == void.shape[0] - 1:
            return void.shape[0] * hy
        if r[j + 1, i]:
            continue
        e, ea = void[j, i], void[j + 1, i]
        top = max(top, (j + 0.5) * hy + hy * (e - threshold) / (e - ea))
    return top


def main():
    ap = fp.parser(__doc__, single_run=False)
    ap.add_argument("run", help="run directory (fluidbed -output_dir) with snapshots and analysis.h5 (its grid and jets)")
    ap.add_argument("--from", dest="start", type=float, default=0.0, help="first snapshot time used, s (default 0)")
    ap.add_argument("--thresholds", default="0.8,0.7,0.6,0.5", help="comma-separated void fractions (default 0.8,0.7,0.6,0.5)")
    ap.add_argument("--max-height", type=float, default=float("inf"), help="leave out heights above this, m (default: none)")
    ap.add_argument("--json", help="write the figures here")
    args = ap.parse_args()
    thresholds = [float(s) for s in args.thresholds.split(",")]
    for v in thresholds:
        if not 0 < v < 1:
            fp.die("--thresholds: %g is not a void fraction between 0 and 1" % v)

    a = fp.read_analysis(args.run)
    lo, h = a["grid/origin"], a["grid/spacing"]
    slots = np.atleast_2d(a["jets/slots"]) if "jets/slots" in a else np.zeros((0, 2))
    if not len(slots):
        fp.die("%s has no jets (analysis.h5 /jets/slots)" % args.run)
    voids = []
    for path in fp.snapshots(args.run):
        with h5py.File(path, "r") as f:
            # the snapshot at t = 0 comes before the first gas step (the run's series holds NaN there)
            if "fluid/void_fraction" not in f or f.attrs["time"] < args.start or f.attrs["time"] <= 0:
                continue
            v = f["fluid/void_fraction"][()]
        voids.append(v.mean(axis=0) if v.ndim == 3 else v)  # 3D: (nz, ny, nx) averaged over the depth
    if not voids:
        fp.die("%s has no snapshot with the gas void fraction from t = %g s" % (args.run, args.start))
    ny, nx = voids[0].shape
    hx, hy = (a["grid/cells"][0] * h[0]) / nx, (a["grid/cells"][1] * h[1]) / ny  # the fluid grid's cells
    inlets = [inlet_cells(s, lo[0], hx, nx) for s in slots]
    out = {"run": args.run, "snapshots": len(voids), "from": args.start, "jets": len(inlets), "thresholds": {}}
    print("%s: %d snapshots from t = %g s, %d jets; heights in mm" % (args.run, len(voids), args.start, len(inlets)))
    print("| threshold | heights | mean | median | 90th percentile | largest |\n|---|---|---|---|---|---|")
    for thr in thresholds:
        hs = np.array([height(v, region(v, i, thr), thr, hy) for v in voids for i in inlets])
        hs = hs[hs <= args.max_height]
        row = {"count": int(hs.size)}
        if hs.size:
            row.update(mean=float(hs.mean()), median=float(np.median(hs)), p90=float(np.percentile(hs, 90)), max=float(hs.max()))
            print("| %.3g | %d | %.1f | %.1f | %.1f | %.1f |" % (thr, hs.size, 1e3 * row["mean"], 1e3 * row["median"], 1e3 * row["p90"], 1e3 * row["max"]))
        out["thresholds"]["%.6g" % thr] = row
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
