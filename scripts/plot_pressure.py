#!/usr/bin/env python3
"""Gas pressure time series of a run: the monitor.csv probe columns (p_y<height>mm_avg, cross-section averages at
-probe_heights; p_probe<n>, point probes at -probe_points) and the sampled pressure drop of analysis.h5 (between
-average_pressure_heights), each where present.

    scripts/plot_pressure.py output/run pressure.png"""
import os

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = fp.parser(__doc__)
    args = ap.parse_args()

    series = []  # (label, t, p)
    mon = os.path.join(args.run, "monitor.csv")
    if os.path.isfile(mon):
        data = np.genfromtxt(mon, delimiter=",", names=True)
        for name in data.dtype.names:
            if name.startswith("p_y") or name.startswith("p_probe"):
                series.append((name, np.atleast_1d(data["time"]), np.atleast_1d(data[name])))
    if os.path.isfile(os.path.join(args.run, "analysis.h5")):
        a = fp.read_analysis(args.run)
        if "series/pressure_drop" in a:
            series.append(("pressure drop (analysis.h5)", a["series/time"], a["series/pressure_drop"]))
    if not series:
        fp.die("%s has no pressure columns in monitor.csv (-probe_heights, -probe_points) and no pressure drop in analysis.h5 "
               "(gas on, -average)" % args.run)
    fig, ax = plt.subplots(figsize=(9, 5))
    for label, t, p in series:
        ax.plot(t, p, label=label)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("pressure (Pa)")
    ax.grid(alpha=0.3)
    ax.legend()
    fp.save(fig, args.output)


if __name__ == "__main__":
    main()
