#!/usr/bin/env python3
"""Horizontal profiles of the time-averaged bed at heights above the distributor: solid fraction, vertical
particle velocity and granular temperature against x (seed Fig. 2.6-2.7, 3.8-3.16, 4.7). Uses the profiles of
analysis.h5 (-average_heights); --heights takes other heights from the averaged fields (the particle-grid layer
holding each, averaged over the depth); without either, a quarter, half and three quarters of the expanded bed.
--inlet-velocity V draws the seed's chapter-4 panels instead: the particle speed |V_av| / V (eq. 4.3, Fig. 4.8-4.9),
the horizontal particle flux eps_s u_x / V (eq. 4.4, Fig. 4.10) and the cross-section solid fraction against height
(Fig. 4.11), beside the solid fraction (Fig. 4.7).

    scripts/plot_profiles.py output/run profiles.png [--heights 0.01,0.03,0.06] [--inlet-velocity 4.37]"""

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = fp.parser(__doc__)
    ap.add_argument("--heights", help="comma-separated heights above the distributor in m (default: those of -average_heights)")
    ap.add_argument("--inlet-velocity", type=float, help="orifice velocity in m/s: normalised speed and horizontal flux (seed ch. 4)")
    args = ap.parse_args()
    if args.inlet_velocity is not None and not args.inlet_velocity > 0:
        fp.die("--inlet-velocity: %g m/s, it must be above 0" % args.inlet_velocity)

    a = fp.read_analysis(args.run)
    lo, h, n = a["grid/origin"], a["grid/spacing"], a["grid/cells"].astype(int)
    x = (lo[0] + (np.arange(n[0]) + 0.5) * h[0]) * fp.MM
    dim = a["fields/solid_fraction"].ndim
    if not args.heights and "profiles/heights" not in a:
        # no -average_heights in the run: a quarter, half and three quarters of the expanded bed (cut-off), or of the grid
        top = float(a["measures/expanded_bed_height_cutoff"][0]) or n[1] * h[1]
        args.heights = ",".join("%.6g" % (f * top) for f in (0.25, 0.5, 0.75))
        print("no -average_heights in the run: profiles at %s m" % args.heights)
    if not args.heights and args.inlet_velocity is not None:
        args.heights = ",".join("%.6g" % y for y in a["profiles/heights"])  # the chapter-4 panels need the fields' layers
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

    panels = [("solid fraction", sf)]
    if args.inlet_velocity is None:
        panels += [("vertical particle velocity (m/s)", vy), ("granular temperature (m$^2$/s$^2$)", th)]
    else:
        v = args.inlet_velocity
        speed = np.linalg.norm(layer("velocity"), axis=-1)  # eq. 4.3: the mean velocity of the particles in the cell
        panels += [("particle speed / inlet velocity (eq. 4.3)", speed / v),
                   ("horizontal particle flux $\\varepsilon_s u_x$ / inlet velocity (eq. 4.4)", sf * layer("velocity", 0) / v)]
    fig, axes = plt.subplots(1, len(panels) + (args.inlet_velocity is not None), figsize=(5 * (len(panels) + 1), 4.5))
    for k, y in enumerate(heights):
        label = "y = %.4g mm" % (y * fp.MM)
        for ax, (name, values) in zip(axes, panels):
            ax.plot(x, values[k], "o-", ms=3, label=label)
    for ax, (name, values) in zip(axes, panels):
        ax.set_xlabel("x (mm)")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[1].axhline(0, color="k", lw=0.5)
    axes[0].legend()
    if args.inlet_velocity is not None:  # Fig. 4.11: the cross-section solid fraction against height
        ax = axes[-1]
        ax.plot(a["cross_section/solid_fraction"], a["cross_section/height"] * fp.MM, "-")
        ax.set_xlabel("cross-section solid fraction")
        ax.set_ylabel("height above the distributor (mm)")
        top = float(a["measures/expanded_bed_height_cutoff"][0])
        ax.axhline(top * fp.MM, color="k", ls="--", lw=0.8, label="expanded bed (cut-off) %.1f mm" % (top * fp.MM))
        ax.set_ylim(0, 1.5 * top * fp.MM)
        ax.legend()
        ax.grid(alpha=0.3)
    fig.suptitle("time-averaged profiles (%d samples)" % int(a["measures/samples"][0]))
    fig.tight_layout()
    fp.save(fig, args.output)


if __name__ == "__main__":
    main()
