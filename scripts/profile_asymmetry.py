#!/usr/bin/env python3
"""Left-right asymmetry of a bed's voidage profile against the averaging window, from a run's snapshots.

The seed's Muller bed profiles (Fig. 2.6: voidage across the bed at 16.4 and 31.2 mm) are time averages; a short
average of a bubbling bed can keep one side wetter than the other because bubbles prefer one path for a while.
This reads every snapshot_*.h5 of a run at or after --start, takes the gas cells' void fraction in the row of cells
holding --height (averaged over the depth), and reports for growing windows [start, start + w]:
  - the mirror asymmetry of the time-averaged profile, mean over x of |eps(x) - eps(L - x)| / 2;
  - the left-minus-right difference D of the half-bed means, with its standard error from block averages of the
    snapshot series (blocks of --block s, so that correlated samples are not counted as independent).
An asymmetry that shrinks like the standard error as the window grows is noise that a longer average settles; one
that stays several standard errors away from zero persists (a preferred bubble path). The domain size is read from
the run's options file (command.txt) unless --lx / --ly are given. --json writes the figures."""
import argparse
import glob
import json
import os
import sys

import h5py
import numpy as np

from fluidbed_tools import outputs


def read_rows(run, height, start, ly):
    """Times and the depth-averaged void-fraction rows at height of every snapshot at or after start."""
    times, rows = [], []
    for path in sorted(glob.glob(os.path.join(run, "snapshot_*.h5"))):
        with h5py.File(path, "r") as f:
            t = float(f.attrs["time"])
            if t < start - 1e-9 or "fluid/void_fraction" not in f:
                continue
            eps = f["fluid/void_fraction"][...]  # (nz, ny, nx) in 3D, (ny, nx) in 2D
        if eps.ndim == 2:
            eps = eps[None]
        ny = eps.shape[1]
        j = min(int(height / (ly / ny)), ny - 1)
        times.append(t)
        rows.append(eps[:, j, :].mean(axis=0))
    order = np.argsort(times)
    return np.array(times)[order], np.array(rows)[order]


def block_error(series, times, block):
    """Standard error of the mean of a time series from the means of consecutive blocks of length block (s)."""
    if len(series) < 2:
        return float("nan")
    edges = np.arange(times[0], times[-1] + block, block)
    means = [series[(times >= a) & (times < a + block)].mean() for a in edges if ((times >= a) & (times < a + block)).any()]
    if len(means) < 2:
        return float("nan")
    return float(np.std(means, ddof=1) / np.sqrt(len(means)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="run directory (fluidbed -output_dir) holding snapshot_*.h5")
    ap.add_argument("--height", type=float, default=0.0312, help="height of the profile in m (default 0.0312, the seed's 31.2 mm)")
    ap.add_argument("--start", type=float, default=1.0, help="first snapshot time of the average in s (default 1.0)")
    ap.add_argument("--windows", default="0.5,1,2,3,4", help="window lengths in s, comma-separated")
    ap.add_argument("--block", type=float, default=0.5, help="block length in s for the standard error (default 0.5)")
    ap.add_argument("--lx", type=float, help="bed width in m (default: from the run's options)")
    ap.add_argument("--ly", type=float, help="bed height in m (default: from the run's options)")
    ap.add_argument("--json", help="write the figures to this file")
    a = ap.parse_args()
    o = outputs.run_options(a.run, {"-domain_lx": None, "-domain_ly": None})
    lx, ly = o["-domain_lx"], o["-domain_ly"]
    lx, ly = a.lx or lx, a.ly or ly
    if not ly:
        sys.exit("profile_asymmetry.py: the domain height is not in %s/command.txt: give --ly" % a.run)
    times, rows = read_rows(a.run, a.height, a.start, ly)
    if len(times) < 2:
        sys.exit("profile_asymmetry.py: fewer than two snapshots at or after t = %g s in %s" % (a.start, a.run))
    nx = rows.shape[1]
    half = nx // 2
    diff = rows[:, :half].mean(axis=1) - rows[:, nx - half:].mean(axis=1)  # left minus right, per snapshot
    out = {"run": a.run, "height_m": a.height, "start_s": a.start, "snapshots": int(len(times)), "windows": []}
    print("voidage at %.1f mm, snapshots from t = %.3g s (%d, every %.3g s); left - right half means D" %
          (1e3 * a.height, times[0], len(times), np.median(np.diff(times))))
    print("%8s %9s %10s %12s %12s" % ("window_s", "samples", "asymmetry", "D", "D_std_err"))
    for w in [float(x) for x in a.windows.split(",")]:
        m = times <= a.start + w + 1e-9
        if m.sum() < 2 or times[m][-1] < a.start + w - 0.15 * w:
            continue  # the run does not reach this window
        prof = rows[m].mean(axis=0)
        asym = float(np.mean(np.abs(prof - prof[::-1])) / 2)
        d, se = float(diff[m].mean()), block_error(diff[m], times[m], a.block)
        out["windows"].append({"window_s": w, "samples": int(m.sum()), "mirror_asymmetry": asym, "left_minus_right": d,
                               "left_minus_right_std_err": se, "profile": prof.tolist()})
        print("%8.2f %9d %10.4f %12.4f %12.4f" % (w, m.sum(), asym, d, se))
    if lx:
        x = (np.arange(nx) + 0.5) * lx / nx
        out["x_m"] = x.tolist()
    if out["windows"]:
        last = out["windows"][-1]
        print("profile over the longest window:", " ".join("%.3f" % v for v in last["profile"]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
