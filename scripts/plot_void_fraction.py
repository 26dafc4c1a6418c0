#!/usr/bin/env python3
"""Void fraction contours of a run: the time-averaged void fraction 1 - <eps_s> on the particle grid (analysis.h5)
beside one snapshot's (the gas's void fraction when the gas is on, otherwise the snapshot's particles binned on the
particle grid). 3D fields are averaged over the depth. The plot shows the bed and a margin above it (--ymax sets the top).

    scripts/plot_void_fraction.py output/run void.png [--snapshot N] [--ymax 0.15]"""

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt


def main():
    ap = fp.parser(__doc__)
    ap.add_argument("--snapshot", type=int, default=-1, help="snapshot number (default: the last)")
    ap.add_argument("--vmin", type=float, default=0.3, help="lower end of the colour scale (default 0.3)")
    fp.add_ymax_option(ap)
    args = ap.parse_args()

    a = fp.read_analysis(args.run)
    lo, hi = fp.box(args.run)
    dim = a["fields/solid_fraction"].ndim
    avg = fp.depth_mean(a["fields/void_fraction"], dim)
    files = fp.snapshots(args.run)
    try:
        path = files[args.snapshot]
    except IndexError:
        fp.die("--snapshot %d: the run has %d snapshots (0..%d)" % (args.snapshot, len(files), len(files) - 1))
    snap, time, source = fp.snapshot_void_fraction(path, lo, hi, a["grid/cells"].astype(int))

    fig, axes = plt.subplots(1, 2, figsize=(10, 6))
    t0, t1 = float(a["measures/window_start"][0]), float(a["measures/window_end"][0])
    fp.field_image(axes[0], avg, lo, hi, "void fraction", vmin=args.vmin, vmax=1.0)
    axes[0].set_title("time average, %.4g-%.4g s (%d samples)" % (t0, t1, int(a["measures/samples"][0])))
    fp.field_image(axes[1], snap, lo, hi, "void fraction", vmin=args.vmin, vmax=1.0)
    axes[1].set_title("t = %.4g s (%s)" % (time, source))
    top = fp.plot_top(args.ymax, fp.depth_mean(a["fields/solid_fraction"], dim), lo, hi)
    for ax in axes:
        ax.set_ylim(lo[1] * fp.MM, top * fp.MM)
    fp.save(fig, args.output)


if __name__ == "__main__":
    main()
