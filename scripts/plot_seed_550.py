#!/usr/bin/env python3
"""The seed's chapter-3 spouted beds at a glance: for each 550 um bed compared (one, two, three jets at 1.6 and 3 U_mf),
our time averages beside the seed's Tables 3.4-3.6, from the JSON files of scripts/seed_tables.py --json.

Four panels: the expanded bed height by the seed's method for that bed (Table 3.4 / 3.5; where the JSON holds the
per-snapshot expanded volume too, it is drawn as a diamond), the bulk solid fraction (eq. 3.7), the downward solid
flux per unit bed, fraction moving down x mean downward speed (Table 3.6's two inputs whose product eq. 3.6 uses:
the fraction alone depends on how creeping cells count, the product does not), and the circulation rate (eq. 3.6).
Bars: ours; hatched: the seed's simulation; a black bar: its experiment (heights at 1.6 U_mf only). --table writes
the same numbers as a markdown table with our difference from the seed's simulation.

    scripts/plot_seed_550.py docs/validation/spouted_550_*_tables.json -o docs/validation/spouted_550_summary.png \\
        --table docs/validation/spouted_550_summary.md

A file that is not a seed_tables.py JSON of a 550 um bed ends it with a message and exit status 2."""
import json

from fluidbed_tools import plot as fp
import matplotlib.pyplot as plt
import numpy as np

import seed_tables  # beside this script: the seed's values

# the cases in the seed's order: jets, then superficial velocity
ORDER = ["spouted_550_jet1_u160", "spouted_550_jet2_u160", "spouted_550_jet3_u160",
         "spouted_550_jet1_u301", "spouted_550_jet2_u301", "spouted_550_jet3_u301"]


def label(scene):
    jets = int(scene.split("_jet")[1][0])
    u = "1.6" if scene.endswith("u160") else "3"
    return "%d jet%s\n%s U_mf" % (jets, "" if jets == 1 else "s", u)


def row(rows, start, path):
    """The first row whose quantity begins with `start`."""
    for r in rows:
        if r["quantity"].startswith(start):
            return r
    fp.die("%s has no row '%s...': not a seed_tables.py JSON of a 550 um bed" % (path, start))


def case(entry, path):
    """One bed's values: ours and the seed's, from one run's entry of a seed_tables.py JSON."""
    scene = entry.get("scene")
    if scene not in seed_tables.SEED:
        fp.die("%s: scene %s is not one of the seed's 550 um beds (%s)" % (path, scene, ", ".join(seed_tables.SEED)))
    s = seed_tables.SEED[scene]
    rows = entry["rows"]
    method = "expanded bed height, %s" % ("cut-off method" if s["method"] == "cutoff" else "expanded-volume method")
    height = row(rows, method, path)
    snap = [r for r in rows if r["quantity"].startswith("expanded bed height, expanded volume per snapshot")]
    f_down = row(rows, "fraction of the bed moving down", path)["ours"]
    v_down = row(rows, "mean downward speed", path)["ours"]
    return dict(
        scene=scene, window=entry.get("window"),
        height=height["ours"], height_seed=s["h_sim"], height_exp=s["h_exp"],
        height_snap=snap[0]["ours"] if snap else None,
        bulk=row(rows, "bulk solid fraction (eq. 3.7, with the height above)", path)["ours"], bulk_seed=s["bulk"],
        flux=1e3 * f_down * v_down, flux_seed=1e3 * s["f_down"] * s["v_down"],
        circ=row(rows, "solid circulation, eq. 3.6 (g/s)", path)["ours"], circ_seed=1e3 * seed_tables.seed_circulation(s),
        pressure=row(rows, "pressure drop", path)["ours"])


def read(paths):
    cases = {}
    for path in paths:
        try:
            data = json.load(open(path))
        except (OSError, ValueError) as e:
            fp.die("%s: %s" % (path, e))
        if not isinstance(data, list):
            fp.die("%s: not a seed_tables.py JSON (a list of runs)" % path)
        for entry in data:
            c = case(entry, path)
            if c["scene"] in cases:
                fp.die("%s: %s given twice (also in an earlier file)" % (path, c["scene"]))
            cases[c["scene"]] = c
    return [cases[s] for s in ORDER if s in cases]


def diff(ours, seed):
    return "%+.0f%%" % (100.0 * (ours / seed - 1.0)) if seed else "-"


def table(cases):
    lines = ["| bed | bed height, seed's method (mm): ours / seed / experiment | bulk solid fraction | "
             "downward flux f_down v_down (mm/s) | circulation, eq. 3.6 (g/s) | pressure drop (Pa) |",
             "|---|---|---|---|---|---|"]
    for c in cases:
        h = "%.1f / %.2f / %s (%s)" % (c["height"], c["height_seed"], "%.2f" % c["height_exp"] if c["height_exp"] else "-",
                                       diff(c["height"], c["height_seed"]))
        if c["height_snap"] is not None:
            h += "; per snapshot %.1f (%s)" % (c["height_snap"], diff(c["height_snap"], c["height_seed"]))
        lines.append("| %s | %s | %.3f / %.3f (%s) | %.1f / %.1f (%s) | %.1f / %.1f (%s) | %.0f |" % (
            label(c["scene"]).replace("\n", ", "), h, c["bulk"], c["bulk_seed"], diff(c["bulk"], c["bulk_seed"]),
            c["flux"], c["flux_seed"], diff(c["flux"], c["flux_seed"]), c["circ"], c["circ_seed"],
            diff(c["circ"], c["circ_seed"]), c["pressure"]))
    return "\n".join(lines) + "\n"


def plot(cases, out):
    pos = np.arange(len(cases))
    fig, axes = plt.subplots(1, 4, figsize=(4.2 * 4, 4.6))
    panels = (("height", "expanded bed height (mm)\nseed's method: cut-off 0.1, or expanded volume"),
              ("bulk", "bulk solid fraction (eq. 3.7)"),
              ("flux", "downward flux, fraction down x speed (mm/s)"),
              ("circ", "solid circulation, eq. 3.6 (g/s)"))
    for ax, (key, title) in zip(axes, panels):
        # bars side by side: ours, the seed's simulation and (heights only) its experiment
        w = 0.27 if key == "height" else 0.38
        x_ours, x_seed = (pos - w, pos) if key == "height" else (pos - w / 2, pos + w / 2)
        ours = np.array([c[key] for c in cases])
        seed = np.array([c[key + "_seed"] for c in cases])
        ax.bar(x_ours, ours, width=w, color="tab:blue", label="fluidbed")
        ax.bar(x_seed, seed, width=w, color="lightgrey", edgecolor="k", hatch="//", label="seed, simulation")
        if key == "height":
            exp = np.array([c["height_exp"] if c["height_exp"] else np.nan for c in cases])
            ax.bar(pos + w, exp, width=w, color="k", label="seed, experiment")
            snap = [(x, c["height_snap"]) for x, c in zip(x_ours, cases) if c["height_snap"] is not None]
            if snap:
                ax.plot([x for x, _ in snap], [h for _, h in snap], "D", color="tab:orange", markeredgecolor="k",
                        label="fluidbed, expanded volume per snapshot")
        ax.set_title(title, fontsize=9)
        ax.set_xticks(pos)
        ax.set_xticklabels([label(c["scene"]) for c in cases], fontsize=7)
        ax.set_ylim(0, 1.3 * np.nanmax(np.concatenate([ours, seed])))
        ax.grid(axis="y", alpha=0.3)
        ax.legend(fontsize=6.5, loc="upper left")
    fig.suptitle("550 um spouted beds (seed ch. 3, Tables 3.4-3.6): time averages over %s" % windows(cases), fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def windows(cases):
    ws = sorted({"%.1f-%.1f s" % tuple(c["window"]) for c in cases if c["window"]})
    return ", ".join(ws) if ws else "the runs' windows"


def main():
    ap = fp.parser(__doc__, single_run=False)
    ap.add_argument("tables", nargs="+", help="JSON files of scripts/seed_tables.py --json")
    ap.add_argument("-o", "--output", help="PNG file to write")
    ap.add_argument("--table", help="markdown file to write (printed too)")
    args = ap.parse_args()
    cases = read(args.tables)
    if not cases:
        fp.die("no 550 um bed in the files given")
    text = table(cases)
    print(text, end="")
    if args.table:
        open(args.table, "w").write(text)
    if args.output:
        plot(cases, args.output)


if __name__ == "__main__":
    main()
