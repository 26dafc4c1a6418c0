#!/usr/bin/env python3
"""Particle velocity vectors of the time-averaged field (eq. 4.3 over the window, analysis.h5) over the
time-averaged solid fraction; cells whose mean solid fraction is below --min-solid-fraction get no arrow. 3D
fields are averaged over the depth. The plot shows the bed and a margin above it (--ymax sets the top).

    scripts/plot_velocity.py output/run velocity.png [--ymax 0.15]"""

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = fp.parser(__doc__)
    ap.add_argument("--min-solid-fraction", type=float, default=0.01, help="no arrow below this mean solid fraction (default 0.01)")
    fp.add_ymax_option(ap)
    args = ap.parse_args()

    a = fp.read_analysis(args.run)
    lo, hi = fp.box(args.run)
    dim = a["fields/solid_fraction"].ndim
    sf = fp.depth_mean(a["fields/solid_fraction"], dim)
    v = fp.depth_mean(a["fields/velocity"], dim)
    ny, nx = sf.shape
    x = (lo[0] + (np.arange(nx) + 0.5) * (hi[0] - lo[0]) / nx) * fp.MM
    y = (lo[1] + (np.arange(ny) + 0.5) * (hi[1] - lo[1]) / ny) * fp.MM
    X, Y = np.meshgrid(x, y)
    keep = sf > args.min_solid_fraction
    fig, ax = plt.subplots(figsize=(6, 8))
    fp.field_image(ax, sf, lo, hi, "solid fraction", cmap="Greys", vmin=0.0)
    speed = np.hypot(v[..., 0], v[..., 1])
    q = ax.quiver(X[keep], Y[keep], v[..., 0][keep], v[..., 1][keep], speed[keep], cmap="plasma", angles="xy")
    plt.colorbar(q, ax=ax, label="particle speed (m/s)")
    ax.set_ylim(lo[1] * fp.MM, fp.plot_top(args.ymax, sf, lo, hi) * fp.MM)
    ax.set_title("time-averaged particle velocity (%d samples)" % int(a["measures/samples"][0]))
    fp.save(fig, args.output)


if __name__ == "__main__":
    main()
