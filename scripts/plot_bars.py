#!/usr/bin/env python3
"""Bar charts across several runs (seed Fig. 3.20-3.22): solid circulation by the counter-current model (eq. 3.6),
convective power (eq. 3.8) and diffusive power (eq. 3.9), from each run's analysis.h5.

    scripts/plot_bars.py output/jet1 output/jet3 output/jet5 -o bars.png [--labels "1 jet,3 jets,5 jets"] [--seed]

--seed draws, beside each run of one of the seed's 550 um spouted beds, the seed's own circulation: eq. 3.6 from its
Table 3.6 inputs (scripts/seed_tables.py); the seed gives the powers only as figures, so they get no bar of the seed."""
import os

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = fp.parser(__doc__, single_run=False)
    ap.add_argument("runs", nargs="+", help="run directories (each holds analysis.h5)")
    ap.add_argument("-o", "--output", required=True, help="PNG file to write")
    ap.add_argument("--labels", help="comma-separated bar labels (default: the directory names)")
    ap.add_argument("--seed", action="store_true", help="the seed's circulation (eq. 3.6 from Table 3.6) beside each run of its spouted beds")
    args = ap.parse_args()

    labels = args.labels.split(",") if args.labels else [os.path.basename(os.path.normpath(r)) for r in args.runs]
    if len(labels) != len(args.runs):
        fp.die("--labels: %d labels for %d runs" % (len(labels), len(args.runs)))
    values = {"solid_circulation": [], "convective_power": [], "diffusive_power": []}
    seed = []  # the seed's circulation per run (kg/s), NaN where the run is not one of its tabled beds
    if args.seed:
        import seed_tables  # beside this script
    for run in args.runs:
        a = fp.read_analysis(run)
        for k in values:
            values[k].append(float(a["measures/" + k][0]))
        if args.seed:
            scene = seed_tables.scene_name(run)
            seed.append(seed_tables.seed_circulation(seed_tables.SEED[scene]) if scene in seed_tables.SEED else float("nan"))
    fig, axes = plt.subplots(1, 3, figsize=(4 + 2 * len(labels), 4.5))
    pos = np.arange(len(labels))
    for ax, (key, title, unit, scale) in zip(axes, (("solid_circulation", "solid circulation (eq. 3.6)", "g/s", 1e3),
                                                    ("convective_power", "convective power (eq. 3.8)", "mW", 1e3),
                                                    ("diffusive_power", "diffusive power (eq. 3.9)", "mW", 1e3))):
        if key == "solid_circulation" and seed:
            ax.bar(pos - 0.2, np.array(values[key]) * scale, width=0.4, color="tab:blue", label="fluidbed")
            ax.bar(pos + 0.2, np.array(seed) * scale, width=0.4, color="lightgrey", edgecolor="k", hatch="//",
                   label="seed (Table 3.6, eq. 3.6)")
            ax.set_ylim(0, 1.35 * np.nanmax(np.concatenate([values[key], seed])) * scale)  # room for the legend
            ax.legend(fontsize=7, loc="upper right")
        else:
            ax.bar(pos, np.array(values[key]) * scale, color="tab:blue")
        ax.set_xticks(pos)
        ax.set_xticklabels(labels, rotation=30, ha="right")
        ax.set_title(title)
        ax.set_ylabel(unit)
        ax.grid(axis="y", alpha=0.3)
    fp.save(fig, args.output)


if __name__ == "__main__":
    main()
