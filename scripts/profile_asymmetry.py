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
the run's options file (command.txt) unless --lx / --ly are given. --json writes the figures.

A bed that keeps one roll for seconds correlates D over seconds, and blocks shorter than that understate its error.
So the error of D over the whole window is also given for growing blocks (--error-blocks; a blocking analysis: the
error grows with the block until the blocks are longer than the correlation, then levels off), and the roll's
history: the sign of D's means over --roll-block s, how often it changes and the share of the window with the left
half wetter (D > 0). --plot draws D's block means and its running mean against time."""
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


def roll_history(diff, times, block):
    """The means of D over consecutive blocks of block s (start times, means), the number of sign changes between
    consecutive blocks, and the share of blocks with D > 0."""
    starts, means = [], []
    for a in np.arange(times[0], times[-1] + 1e-9, block):
        m = (times >= a - 1e-9) & (times < a + block - 1e-9)
        if m.sum() and (times[m][-1] - a) >= 0.5 * block:  # a block the run covers for at least half its length
            starts.append(float(a))
            means.append(float(diff[m].mean()))
    signs = np.sign(means)
    changes = int(np.sum(signs[1:] != signs[:-1])) if len(means) > 1 else 0
    share = float(np.mean(np.array(means) > 0)) if means else float("nan")
    return starts, means, changes, share


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="run directory (fluidbed -output_dir) holding snapshot_*.h5")
    ap.add_argument("--height", type=float, default=0.0312, help="height of the profile in m (default 0.0312, the seed's 31.2 mm)")
    ap.add_argument("--start", type=float, default=1.0, help="first snapshot time of the average in s (default 1.0)")
    ap.add_argument("--windows", default="0.5,1,2,3,4", help="window lengths in s, comma-separated")
    ap.add_argument("--block", type=float, default=0.5, help="block length in s for the standard error (default 0.5)")
    ap.add_argument("--lx", type=float, help="bed width in m (default: from the run's options)")
    ap.add_argument("--ly", type=float, help="bed height in m (default: from the run's options)")
    ap.add_argument("--error-blocks", default="0.25,0.5,1,2,4", help="block lengths in s for the blocking analysis of D's error")
    ap.add_argument("--roll-block", type=float, default=1.0, help="block length in s of the roll history (default 1)")
    ap.add_argument("--plot", help="draw D's block means and running mean against time into this PNG")
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
    whole = diff.mean()
    out["error_blocks"] = []
    print("D over the whole window (%.3g-%.3g s): %.4f; its standard error by block length:" % (times[0], times[-1], whole))
    for b in [float(x) for x in a.error_blocks.split(",")]:
        nb = int((times[-1] - times[0]) / b + 1e-9)
        if nb < 4:
            continue  # too few blocks for an error
        se = block_error(diff, times, b)
        out["error_blocks"].append({"block_s": b, "blocks": nb, "left_minus_right_std_err": se})
        print("  %6.2f s blocks (%3d): %.4f" % (b, nb, se))
    starts, means, changes, share = roll_history(diff, times, a.roll_block)
    out["roll"] = {"block_s": a.roll_block, "block_start_s": starts, "left_minus_right": means, "sign_changes": changes,
                   "share_left_wetter": share}
    print("roll history (%.3g s blocks): %d blocks, %d sign changes of D, left half wetter in %.0f%% of them" %
          (a.roll_block, len(means), changes, 100 * share))
    print("  D per block:", " ".join("%+.3f" % v for v in means))
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 3.2))
        ax.step(np.array(starts), means, where="post", color="C0", label="D, %.3g s block means" % a.roll_block)
        run_mean = np.cumsum(diff) / np.arange(1, len(diff) + 1)
        ax.plot(times, run_mean, color="C1", label="running mean from %.3g s" % times[0])
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("left - right voidage")
        ax.set_title("voidage at %.1f mm: left-right difference of the half-bed means" % (1e3 * a.height), fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=110)
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
