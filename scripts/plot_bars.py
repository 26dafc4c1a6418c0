#!/usr/bin/env python3
"""Bar charts across several runs (seed Fig. 3.20-3.22): solid circulation by the counter-current model (eq. 3.6),
convective power (eq. 3.8) and diffusive power (eq. 3.9), from each run's analysis.h5.

    scripts/plot_bars.py output/jet1 output/jet3 output/jet5 -o bars.png [--labels "1 jet,3 jets,5 jets"]"""
import os

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = fp.parser(__doc__, single_run=False)
    ap.add_argument("runs", nargs="+", help="run directories (each holds analysis.h5)")
    ap.add_argument("-o", "--output", required=True, help="PNG file to write")
    ap.add_argument("--labels", help="comma-separated bar labels (default: the directory names)")
    args = ap.parse_args()

    labels = args.labels.split(",") if args.labels else [os.path.basename(os.path.normpath(r)) for r in args.runs]
    if len(labels) != len(args.runs):
        fp.die("--labels: %d labels for %d runs" % (len(labels), len(args.runs)))
    values = {"solid_circulation": [], "convective_power": [], "diffusive_power": []}
    for run in args.runs:
        a = fp.read_analysis(run)
        for k in values:
            values[k].append(float(a["measures/" + k][0]))
    fig, axes = plt.subplots(1, 3, figsize=(4 + 2 * len(labels), 4.5))
    pos = np.arange(len(labels))
    for ax, (key, title, unit, scale) in zip(axes, (("solid_circulation", "solid circulation (eq. 3.6)", "g/s", 1e3),
                                                    ("convective_power", "convective power (eq. 3.8)", "mW", 1e3),
                                                    ("diffusive_power", "diffusive power (eq. 3.9)", "mW", 1e3))):
        ax.bar(pos, np.array(values[key]) * scale, color="tab:blue")
        ax.set_xticks(pos)
        ax.set_xticklabels(labels, rotation=30, ha="right")
        ax.set_title(title)
        ax.set_ylabel(unit)
        ax.grid(axis="y", alpha=0.3)
    fp.save(fig, args.output)


if __name__ == "__main__":
    main()
