#!/usr/bin/env python3
"""Two or more runs of one scene, differing in a setting (a softer spring, a longer step, another solver), compared
over a common window of bed time: is the cheaper setting's answer the same?

From each run's monitor.csv, averaged over [--start, --end] (default: from --start to the end of the shortest run):
  pressure_drop_Pa    the lowest pressure probe minus the highest (the probes of -probe_heights, p_y..._avg);
  centre_height_mm    the particles' centre of mass above the floor, pe_grav / (N m g): the bed's expansion;
  contacts            contacts per particle;
and over the window its largest max_overlap_rel (the overlap the setting allows, in diameters). Each mean has its
standard error by batch means (10 batches; fluidbed_tools.stats), each run's difference from the first (REF) its
uncertainty from both. The cost (wall s per simulated s per core) comes from each run's summary.json, over the part
of the run its last start made (fluidbed_tools.outputs.run_cost).

--reference-json takes the reference from an earlier comparison's JSON (its first run) instead of a run directory,
for a reference whose monitor.csv is gone: its window statistics stand in, so the window must be the same (--start,
and --end or the stored end), and every run given must reach its end.

A run that lacks monitor.csv, or windows that do not overlap, end it with a message and exit status 2.

example:
  scripts/compare_runs.py bench/long/spouted_550_jet1_u160 bench/spouted550_kn100/spouted_550_jet1_u160 --start 0.05 \\
      --json docs/validation/spouted_550_kn100.json --plot docs/validation/spouted_550_kn100.png
"""
import argparse
import functools
import json
import math
import os
import re
import sys

import numpy as np

from fluidbed_tools import outputs
from fluidbed_tools.stats import batch_error

MEASURES = ("pressure_drop_Pa", "centre_height_mm", "contacts")


def die(message):
    print("compare_runs.py: " + message, file=sys.stderr)
    sys.exit(2)


def probes(columns):
    """The pressure probe columns (p_y<height>mm_avg) ordered from the lowest to the highest."""
    found = []
    for c in columns:
        m = re.fullmatch(r"p_y(\d+)_?(\d*)mm_avg", c)
        if m:
            found.append((float(m.group(1) + ("." + m.group(2) if m.group(2) else "")), c))
    return [c for _, c in sorted(found)]


@functools.lru_cache(maxsize=None)
def series(run):
    """The run's monitor series: time and each of MEASURES (nan where the run has no such column), and max_overlap_rel;
    read once per run (the comparison and the plot share it)."""
    path = os.path.join(run, "monitor.csv")
    if not os.path.exists(path):
        die("%s has no monitor.csv: not a fluidbed run directory, or the run has not started" % run)
    mon = outputs.table(path)
    opts = outputs.run_options(run, {"-particle_diameter": None, "-particle_density": None})
    out = {"time": mon["time"], "max_overlap_rel": mon.get("max_overlap_rel", np.full(len(mon["time"]), np.nan))}
    p = probes(mon)
    out["pressure_drop_Pa"] = mon[p[0]] - mon[p[-1]] if len(p) >= 2 else np.full(len(mon["time"]), np.nan)
    d, rho = opts["-particle_diameter"], opts["-particle_density"]
    if d and rho and "pe_grav" in mon:
        mass = rho * math.pi / 6 * d ** 3
        out["centre_height_mm"] = 1e3 * mon["pe_grav"] / (mon["particles"] * mass * 9.81)
    else:  # a scene of several diameters: no single mass per particle
        out["centre_height_mm"] = np.full(len(mon["time"]), np.nan)
    out["contacts"] = mon.get("contacts_per_particle", np.full(len(mon["time"]), np.nan))
    return out


def window_means(s, start, end):
    """Each measure's mean over [start, end] with its batch-means standard error, the largest overlap, the samples."""
    keep = (s["time"] >= start - 1e-12) & (s["time"] <= end + 1e-12)
    if keep.sum() < 20:
        return None
    res = {"samples": int(keep.sum())}
    for k in MEASURES:
        x = s[k][keep]
        res[k] = {"mean": float(x.mean()), "error": batch_error(x)} if np.all(np.isfinite(x)) else None
    res["max_overlap_rel"] = float(np.nanmax(s["max_overlap_rel"][keep]))
    return res


def cost(run):
    if not os.path.exists(os.path.join(run, "summary.json")):
        return float("nan"), float("nan")
    return outputs.run_cost(outputs.summary(run))


def stored_reference(path, start, end):
    """The reference entry of an earlier comparison's JSON, and its window's end; its window must be [start, end]."""
    try:
        stored = json.load(open(path))
        ref, s0, s1 = stored["runs"][0], stored["start"], stored["end"]
    except (OSError, ValueError, KeyError, IndexError, TypeError) as e:
        die("--reference-json %s: not a comparison written by --json (%s)" % (path, e))
    if abs(s0 - start) > 1e-9 or (end is not None and abs(s1 - end) > 1e-9):
        die("--reference-json %s holds the window %g-%g s; --start/--end ask for %g-%s s" % (path, s0, s1, start, "%g" % end if end is not None else "its end"))
    name = ref["run"] if ref["run"].endswith(" (stored)") else ref["run"] + " (stored)"  # a comparison of a stored one, stored again
    return dict(ref, run=name), s1


def compare(runs, start, end=None, reference=None):
    """The comparison of runs[1:] with runs[0] (see the module's text) as a dict; with reference (a stored entry, see
    stored_reference), of every run with it, over its window [start, end]."""
    data = [series(r) for r in runs]
    common = min(s["time"][-1] for s in data)
    if reference is not None and common < end - 1e-9:
        die("the stored reference's window ends at %g s; the shortest run ends at %g s" % (end, common))
    end = common if end is None else min(end, common)
    if end <= start:
        die("the runs' windows do not overlap after --start %g s (the shortest ends at %g s)" % (start, common))
    out = {"start": start, "end": end, "runs": []}
    ref = reference
    if ref is not None:
        out["runs"].append(ref)
    for run, s in zip(runs, data):
        w = window_means(s, start, end)
        if w is None:
            die("%s has fewer than 20 monitor samples in %g-%g s" % (run, start, end))
        c, share = cost(run)
        entry = {"run": run, "cost": c, "cpu_share": share, **w}
        if ref is None:
            ref = entry
        else:
            entry["relative_difference"] = {}
            for k in MEASURES:
                a, b = ref[k], w[k]
                if a and b and a["mean"] != 0:
                    entry["relative_difference"][k] = {"value": b["mean"] / a["mean"] - 1,
                                                       "uncertainty": math.hypot(a["error"], b["error"]) / abs(a["mean"])}
        out["runs"].append(entry)
    return out


def report(res):
    print("window %.4g-%.4g s" % (res["start"], res["end"]))
    ref = res["runs"][0]
    for e in res["runs"]:
        line = "%-60s cost %8.4g s/s (share %.2f)  overlap max %.4f d" % (e["run"][-60:], e["cost"], e["cpu_share"], e["max_overlap_rel"])
        print(line)
        for k in MEASURES:
            if e[k] is None:
                continue
            diff = e.get("relative_difference", {}).get(k)
            print("    %-18s %10.5g +- %-9.3g%s" % (k, e[k]["mean"], e[k]["error"],
                                                   "  %+.2f%% +- %.2f%%" % (100 * diff["value"], 100 * diff["uncertainty"]) if diff else
                                                   ("  (reference)" if e is ref else "")))


def plot(runs, res, path, labels):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = MEASURES + ("max_overlap_rel",)
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.2 * len(names)), sharex=True)
    for run, label in zip(runs, labels):
        s = series(run)
        for ax, k in zip(axes, names):
            ax.plot(s["time"], s[k], lw=0.8, label=label)
    stored = [e for e in res["runs"] if e["run"].endswith("(stored)")]
    for e in stored:  # a reference without its series: its window mean +- standard error
        for ax, k in zip(axes, MEASURES):
            if e.get(k):
                m, err = e[k]["mean"], e[k]["error"]
                ax.fill_between([res["start"], res["end"]], m - err, m + err, color="black", alpha=0.25, label=e["run"])
    for ax, k in zip(axes, names):
        ax.axvspan(res["start"], res["end"], color="grey", alpha=0.12)
        ax.set_ylabel(k.replace("_", " "), fontsize=8)
    axes[0].legend(fontsize=7)
    axes[-1].set_xlabel("t (s); shaded: the window compared")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="run directories; the first is the reference")
    ap.add_argument("--start", type=float, default=0.0, help="start of the window (s of bed time)")
    ap.add_argument("--end", type=float, default=None, help="end of the window (s; default the end of the shortest run)")
    ap.add_argument("--labels", default="", help="comma-separated legend labels (default the directories)")
    ap.add_argument("--json", help="write the comparison here")
    ap.add_argument("--plot", help="draw the runs' series here (png)")
    ap.add_argument("--reference-json", help="the reference from an earlier comparison's --json (its first run), not a run directory")
    args = ap.parse_args()
    reference, end = None, args.end
    if args.reference_json:
        reference, end = stored_reference(args.reference_json, args.start, args.end)
    elif len(args.runs) < 2:
        die("give a reference run and at least one run to compare with it")
    res = compare(args.runs, args.start, end, reference)
    report(res)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(res, f, indent=1)
    if args.plot:
        labels = args.labels.split(",") if args.labels else args.runs
        plot(args.runs, res, args.plot, labels)


if __name__ == "__main__":
    main()
