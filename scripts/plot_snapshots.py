#!/usr/bin/env python3
"""Snapshots of particle motion (seed Fig. 2.10, 5.8-5.9): the particles of several snapshot_NNNNN.h5 files side by
side, seen along the depth (x against y), coloured by speed. By default six snapshots evenly spread over the run;
--snapshots picks them by number. The plot shows the bed and a margin above the highest particle of the chosen
snapshots (--ymax sets the top).

    scripts/plot_snapshots.py output/run snapshots.png [--snapshots 2,4,6,8] [--count 6] [--ymax 0.15]"""
import os

from fluidbed_tools import plot as fp
import h5py
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = fp.parser(__doc__)
    ap.add_argument("--snapshots", help="comma-separated snapshot numbers (NNNNN of snapshot_NNNNN.h5)")
    ap.add_argument("--count", type=int, default=6, help="how many snapshots, evenly spread, when --snapshots is not given")
    ap.add_argument("--ymax", type=float, default=None, help="top of the plotted region (m); default: 1.2 times the highest particle")
    args = ap.parse_args()

    files = fp.snapshots(args.run)
    if args.snapshots:
        names = {int(os.path.basename(f)[9:14]): f for f in files}
        wanted = [int(s) for s in args.snapshots.split(",")]
        missing = [n for n in wanted if n not in names]
        if missing:
            fp.die("--snapshots: %s has no snapshot %s (it has %d to %d)" % (args.run, ",".join(map(str, missing)), min(names), max(names)))
        files = [names[n] for n in wanted]
    else:
        if args.count < 1:
            fp.die("--count %d: give at least 1" % args.count)
        files = [files[int(round(k))] for k in np.linspace(0, len(files) - 1, min(args.count, len(files)))]

    lo, hi = fp.box(args.run)
    frames = []
    for path in files:
        with h5py.File(path, "r") as f:
            if "particles/position" not in f:
                fp.die("%s holds no particles (-output_particles 0?)" % path)
            x = np.atleast_2d(f["particles/position"][()])
            v = np.atleast_2d(f["particles/velocity"][()])
            d = np.atleast_1d(f["particles/diameter"][()])
            time = float(np.ravel(f.attrs["time"])[0]) if "time" in f.attrs else float("nan")
        frames.append((x, np.linalg.norm(v, axis=1), d, time))
    top_particle = max((float(np.max(x[:, 1] + 0.5 * d)) if len(d) else lo[1]) for x, _, d, _ in frames)
    top = min(hi[1], args.ymax if args.ymax is not None else lo[1] + 1.2 * (top_particle - lo[1]))
    vmax = max((float(np.percentile(s, 99)) if len(s) else 0.0) for _, s, _, _ in frames) or 1.0

    aspect = (hi[0] - lo[0]) / max(top - lo[1], 1e-12)  # each panel drawn to scale, 6 inches tall
    panel = min(max(6.0 * aspect, 1.2), 6.0) + 0.5
    fig, axes = plt.subplots(1, len(frames), figsize=(panel * len(frames) + 1.5, 7), squeeze=False, sharey=True)
    for ax, (x, speed, d, time) in zip(axes[0], frames):
        # the fastest drawn last, on top
        order = np.argsort(speed)
        sc = ax.scatter(x[order, 0] * fp.MM, x[order, 1] * fp.MM, c=speed[order], s=0.5, cmap="plasma", vmin=0, vmax=vmax, linewidths=0)
        ax.set_xlim(lo[0] * fp.MM, hi[0] * fp.MM)
        ax.set_ylim(lo[1] * fp.MM, top * fp.MM)
        ax.set_aspect("equal")
        ax.set_title("t = %.3f s" % time, fontsize=9)
        ax.set_xlabel("x (mm)")
    axes[0][0].set_ylabel("y (mm)")
    fig.colorbar(sc, ax=axes[0].tolist(), label="particle speed (m/s)", shrink=0.8)
    fig.savefig(args.output, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print("wrote %s" % args.output)


if __name__ == "__main__":
    main()
