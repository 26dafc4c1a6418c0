#!/usr/bin/env python3
"""Horizontal profiles of the time-averaged bed at heights above the distributor: solid fraction, vertical
particle velocity and granular temperature against x (seed Fig. 2.6-2.7, 3.8-3.16, 4.7). Uses the profiles of
analysis.h5 (-average_heights); --heights takes other heights from the averaged fields (the particle-grid layer
holding each, averaged over the depth); without either, a quarter, half and three quarters of the expanded bed.

    scripts/plot_profiles.py output/run profiles.png [--heights 0.01,0.03,0.06]"""

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = fp.parser(__doc__)
    ap.add_argument("--heights", help="comma-separated heights above the distributor in m (default: those of -average_heights)")
    args = ap.parse_args()

    a = fp.read_analysis(args.run)
    lo, h, n = a["grid/origin"], a["grid/spacing"], a["grid/cells"].astype(int)
    x = (lo[0] + (np.arange(n[0]) + 0.5) * h[0]) * fp.MM
    dim = a["fields/solid_fraction"].ndim
    if not args.heights and "profiles/heights" not in a:
        # no -average_heights in the run: a quarter, half and three quarters of the expanded bed (cut-off), or of the grid
        top = float(a["measures/expanded_bed_height_cutoff"][0]) or n[1] * h[1]
        args.heights = ",".join("%.6g" % (f * top) for f in (0.25, 0.5, 0.75))
        print("no -average_heights in the run: profiles at %s m" % args.heights)
    if args.heights:
        heights = [float(s) for s in args.heights.split(",")]
        for y in heights:
            if not 0 <= y <= n[1] * h[1]:
                fp.die("--heights: %g m is outside the bed's 0..%g m" % (y, n[1] * h[1]))
        rows = [min(int(np.floor(y / h[1])), n[1] - 1) for y in heights]
        layer = lambda name, c=None: np.array([(fp.depth_mean(a["fields/" + name], dim)[..., c] if c is not None
                                                else fp.depth_mean(a["fields/" + name], dim))[j] for j in rows])
        sf, vy, th = layer("solid_fraction"), layer("velocity", 1), layer("granular_temperature")
    else:
        heights = list(a["profiles/heights"])
        sf, vy, th = a["profiles/solid_fraction"], a["profiles/velocity_y"], a["profiles/granular_temperature"]

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for k, y in enumerate(heights):
        label = "y = %.4g mm" % (y * fp.MM)
        axes[0].plot(x, sf[k], "o-", label=label)
        axes[1].plot(x, vy[k], "o-", label=label)
        axes[2].plot(x, th[k], "o-", label=label)
    for ax, name in zip(axes, ("solid fraction", "vertical particle velocity (m/s)", "granular temperature (m$^2$/s$^2$)")):
        ax.set_xlabel("x (mm)")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[1].axhline(0, color="k", lw=0.5)
    axes[0].legend()
    fig.suptitle("time-averaged profiles (%d samples)" % int(a["measures/samples"][0]))
    fp.save(fig, args.output)


if __name__ == "__main__":
    main()
