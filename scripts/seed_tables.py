#!/usr/bin/env python3
"""The 550 um spouted beds' answers beside the seed's chapter-3 tables (and the nine-jet 2D bed's beside chapter 4's
figures: expanded bed height, bulk solid fraction, jet height): expanded bed height by the method the seed used
for each (Table 3.4: the cut-off solid fraction 0.1 at 1.6 U_mf, the expanded volume at 3 U_mf, where the fountain
defeats the cut-off; Table 3.5 double and triple jets, the cut-off), the inputs of the
counter-current circulation (Table 3.6: bulk solid fraction eq. 3.7, fraction of the bed moving down, mean downward
speed; the bulk fraction of eq. 3.7 with the height of the seed's method, as its Table 3.6 has it) and the circulation
rate of eq. 3.6 (ours and the seed's from the Table 3.6 inputs, with rho_p = 2500 kg/m^3 and the distributor's
56.4 x 4.95 mm).

Each run is a folder of scripts/validate.sh (its command.txt names examples/<scene>.opts; its analysis.h5 holds the
solver's time averages, -average_start). Prints a markdown table per run; --json writes the rows.

The seed's expanded volume is "the volume of all the fluid cells having particles in them", without saying whether of
each instant or of the time-averaged field. The solver's measure counts the cells of the time-averaged field, which
include every cell the fountain reached in the window; where the run's snapshots (-output_interval) fall in the
window, the table also gives the same count per snapshot (cells with void fraction below 1), averaged over them, and
the bulk solid fraction and circulation with that height.

    scripts/seed_tables.py bench/spouted550_kn150/spouted_550_jet1_u160 [more runs] [--json tables.json]

A run without analysis.h5, or of a scene the seed's tables do not hold, ends it with a message and exit status 2."""
import argparse
import glob
import json
import os
import re
import sys

import h5py
import numpy as np

from fluidbed_tools import outputs

RHO_P = 2500.0
DISTRIBUTOR_AREA = 0.0564 * 0.00495  # m^2, Fig. 3.1

# Tables 3.4-3.6 per scene: expanded bed height (mm) simulated and measured, the method the seed used for it, and the
# Table 3.6 inputs (bulk solid fraction, fraction moving down, mean downward speed in m/s). The seed's section 3.3: "The
# expanded bed height for 1.6 U_mf comes out to be about 60.3 mm" from the cut-off 0.1 of Fig. 3.6; "For 3 U_mf, the
# cut-off ... is not representative ... because of fountain formation", so 88.5 mm is the expanded volume.
SEED = {
    "spouted_550_jet1_u160": dict(h_sim=60.3, h_exp=55.4, method="cutoff", bulk=0.518, f_down=0.549, v_down=0.0328),
    "spouted_550_jet1_u301": dict(h_sim=88.5, h_exp=None, method="volume", bulk=0.353, f_down=0.451, v_down=0.117),
    "spouted_550_jet2_u160": dict(h_sim=58.22, h_exp=50.75, method="cutoff", bulk=0.536, f_down=0.558, v_down=0.0178),
    "spouted_550_jet2_u301": dict(h_sim=78.09, h_exp=None, method="cutoff", bulk=0.401, f_down=0.470, v_down=0.0623),
    "spouted_550_jet3_u160": dict(h_sim=63.35, h_exp=58.74, method="cutoff", bulk=0.493, f_down=0.461, v_down=0.0349),
    "spouted_550_jet3_u301": dict(h_sim=84.93, h_exp=None, method="cutoff", bulk=0.368, f_down=0.462, v_down=0.0671),
}
# Chapter 4, the nine-jet 2D bed (case A1 2D), time averages over the last 3.38 of 8.38 s: the expanded bed height
# "close to 150 mm in the 2D simulation ... close to 174 mm in the experiment" (Fig. 4.12, read off a plot: the
# cut-off is ours), the bulk solid fraction M_p / (rho_p A_c h_exp) 0.527 (2D) against 0.476, and the jet height,
# the mean over the nine jets of the height where the first bubble detaches, 22.1 mm against 21.32 +- 1.70 mm.
SEED_CH4 = {
    "ninejet_2d": dict(h_sim=150.0, h_exp=174.0, bulk_sim=0.527, bulk_exp=0.476, jet_sim=22.1, jet_exp=21.32),
}


def die(message):
    print("seed_tables.py: " + message, file=sys.stderr)
    sys.exit(2)


def seed_circulation(s):
    """eq. 3.6 from Table 3.6's inputs, the seed's or ours (kg/s)."""
    return RHO_P * s["bulk"] * s["f_down"] * s["v_down"] * DISTRIBUTOR_AREA


def scene_name(run):
    """The scene of a run of scripts/validate.sh (examples/<scene>.opts in its command.txt), or None."""
    path = os.path.join(run, "command.txt")
    m = re.search(r"examples/([A-Za-z0-9_]+)\.opts", open(path).read()) if os.path.isfile(path) else None
    return m.group(1) if m else None


def scene_of(run):
    if not os.path.isfile(os.path.join(run, "command.txt")):
        die("%s has no command.txt: not a run of scripts/validate.sh" % run)
    scene = scene_name(run)
    if scene not in SEED and scene not in SEED_CH4:
        die("%s: scene %s is not one of the seed's tabled beds (%s)" % (run, scene or "unknown", ", ".join(list(SEED) + list(SEED_CH4))))
    return scene


def measures(run):
    path = os.path.join(run, "analysis.h5")
    if not os.path.isfile(path):
        die("%s has no analysis.h5: the run has not reached -average_start, or averages nothing" % run)
    data = outputs.read_h5(path)
    return {k[len("measures/"):]: float(v.ravel()[0]) for k, v in data.items() if k.startswith("measures/")}


def rows(run):
    """The table's rows for one run: (quantity, ours, seed's simulation, seed's experiment)."""
    scene = scene_of(run)
    if scene in SEED_CH4:
        return scene, *rows_chapter4(SEED_CH4[scene], measures(run))
    s, m = SEED[scene], measures(run)
    h_key = "expanded_bed_height_volume" if s["method"] == "volume" else "expanded_bed_height_cutoff"
    other = "expanded_bed_height_cutoff" if s["method"] == "volume" else "expanded_bed_height_volume"
    # eq. 3.7's bulk solid fraction with the height of the seed's method for this case (the seed's Table 3.6 values are
    # m_bed / (rho_p h A_d) with its Table 3.4-3.5 heights: 0.518 from 60.3 mm, 0.353 from 88.5 mm), and eq. 3.6 with it
    bulk = m["bulk_solid_fraction"] if s["method"] == "volume" else m["bulk_solid_fraction_cutoff"]
    ours = dict(bulk=bulk, f_down=m["fraction_moving_down"], v_down=m["mean_downward_speed"])
    out = [("expanded bed height, %s method (mm)" % ("expanded-volume" if s["method"] == "volume" else "cut-off"), 1e3 * m[h_key], s["h_sim"],
            s["h_exp"]),
           ("expanded bed height, the other method (mm)", 1e3 * m[other], None, None),
           ("bulk solid fraction (eq. 3.7, with the height above)", bulk, s["bulk"], None),
           ("fraction of the bed moving down", m["fraction_moving_down"], s["f_down"], None),
           ("mean downward speed (m/s)", m["mean_downward_speed"], s["v_down"], None),
           ("solid circulation, eq. 3.6 (g/s)", 1e3 * seed_circulation(ours), 1e3 * seed_circulation(s), None)]
    return scene, m, out + snapshot_rows(run, s, m) + pressure_drop_row(m)


def snapshot_heights(run, start, end):
    """The expanded-volume height of each snapshot of the run in [start, end] (s): the share of the gas cells holding
    particles (void fraction below 1) times the domain's height, which is their volume over the cross-section (the
    seed's expanded volume over the bed volume times the bed's height). Empty where no snapshot falls in the window."""
    paths = sorted(glob.glob(os.path.join(run, "snapshot_*.h5")))
    if not paths:
        return np.array([])
    with h5py.File(os.path.join(run, "analysis.h5"), "r") as f:
        height = float(f["grid/spacing"][1] * f["grid/cells"][1])
    heights = []
    for path in paths:
        with h5py.File(path, "r") as f:
            if "time" not in f.attrs or "fluid/void_fraction" not in f:
                continue
            t = float(np.ravel(f.attrs["time"])[0])
            if not (start - 1e-6 <= t <= end + 1e-6):
                continue
            eps = np.asarray(f["fluid/void_fraction"][()], float)
        heights.append(np.count_nonzero(eps < 1.0) / eps.size * height)
    return np.array(heights)


def snapshot_rows(run, s, m):
    """Rows of the per-snapshot expanded volume (snapshot_heights over the averaging window), with eq. 3.7 and 3.6 from
    it and the same fraction moving down and mean downward speed."""
    h = snapshot_heights(run, m["window_start"], m["window_end"])
    if h.size == 0:
        return []
    bulk = m["bulk_solid_fraction"] * m["expanded_bed_height_volume"] / h.mean()  # eq. 3.7: the same mass over this height
    ours = dict(bulk=bulk, f_down=m["fraction_moving_down"], v_down=m["mean_downward_speed"])
    seed_h = s["h_sim"] if s["method"] == "volume" else None
    return [("expanded bed height, expanded volume per snapshot, mean of %d (mm)" % h.size, 1e3 * h.mean(), seed_h, None),
            ("the same, standard deviation over the snapshots (mm)", 1e3 * h.std(), None, None),
            ("bulk solid fraction (eq. 3.7) with the per-snapshot height", bulk, s["bulk"] if seed_h else None, None),
            ("solid circulation, eq. 3.6, with it (g/s)", 1e3 * seed_circulation(ours), 1e3 * seed_circulation(s) if seed_h else None, None)]


def rows_chapter4(s, m):
    """The nine-jet bed's rows: the cut-off height, eq. 3.7's bulk fraction with it (the seed's M_p / (rho_p A_c h_exp)),
    the jets' mean height before a bubble detaches (the mean over the jets that shed bubbles) and the pressure drop."""
    out = [("expanded bed height, cut-off method (mm)", 1e3 * m["expanded_bed_height_cutoff"], s["h_sim"], s["h_exp"]),
           ("expanded bed height, expanded-volume method (mm)", 1e3 * m["expanded_bed_height_volume"], None, None),
           ("bulk solid fraction (M_p / rho_p A h, the cut-off height)", m["bulk_solid_fraction_cutoff"], s["bulk_sim"], s["bulk_exp"])]
    if "jet_penetration_height" in m:
        out += [("jet height, first bubble detachment, mean over the jets (mm)", 1e3 * m["jet_penetration_height"], s["jet_sim"], s["jet_exp"]),
                ("jet height's standard deviation (mm)", 1e3 * m["jet_penetration_height_std"], None, 1.70),
                ("bubble detachments, all jets", m["jet_detachments"], None, None)]
    return m, out + pressure_drop_row(m)


def pressure_drop_row(m):
    """The pressure drop's row where the run measured one (the seed gives it as a figure only)."""
    return [("pressure drop (Pa)", m["pressure_drop"], None, None)] if "pressure_drop" in m else []


def fmt(x):
    return "-" if x is None else "%.4g" % x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="run folders of scripts/validate.sh")
    ap.add_argument("--json", help="write the rows here")
    args = ap.parse_args()
    report = []
    for run in args.runs:
        scene, m, table = rows(run)
        print("%s (%s), averaged over %.3g-%.3g s, %d samples\n" % (run, scene, m["window_start"], m["window_end"], m["samples"]))
        print("| quantity | ours | seed, simulation | seed, experiment | ours against the seed's simulation |")
        print("|---|---|---|---|---|")
        entries = []
        for name, ours, sim, exp in table:
            diff = "%+.1f%%" % (100 * (ours / sim - 1)) if sim else "-"
            print("| %s | %s | %s | %s | %s |" % (name, fmt(ours), fmt(sim), fmt(exp), diff))
            entries.append({"quantity": name, "ours": ours, "seed_simulation": sim, "seed_experiment": exp})
        print()
        report.append({"run": run, "scene": scene, "window": [m["window_start"], m["window_end"]], "rows": entries})
    if args.json:
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1)


if __name__ == "__main__":
    main()
