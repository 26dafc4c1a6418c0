"""The spring stiffness as a knob (scripts/stability_map.py --maps kn; scripts/speed_accuracy.py, knob kn on the jetted
2D bed, the packed bed and the Muller bed): each kn point of the map is the map's cell_dt point at the same gas cells and
-dem_dt_factor with only -dem_kn added; the step follows the spring's own t_cr, so a quarter of the stiffness runs twice
the step (1 ms of bed from the lattice at 800 and 200 N/m; t_cr goes as 1 / sqrt(k_n), eq. 3.2); a kn table turns into
chart rows of knob kn on their own panel (jet2d_kn) with errors against the table's reference row; the packed and
Muller points at the seed's 800 N/m keep the commands they had before the knob (no -dem_kn), the others name it."""
import csv
import os
import sys

from fluidbed_tools import testing as t

sys.path.insert(0, os.path.join(t.SRC, "scripts"))
import speed_accuracy as sa  # noqa: E402
import stability_map as sm  # noqa: E402

pts = sm.points(["kn"], False)
t.check([(p["dt_factor"], p["kn"], p["gas_substeps"]) for p in pts] == sm.KNS and (0.25, 800, 1) in sm.KNS, "one point per (step, k_n, gas substeps) of KNS: %s" % sm.KNS)


class Args:
    t_final = 0.001


for p in pts:
    plain = {k: v for k, v in p.items() if k not in ("kn", "gas_substeps")}
    plain["map"] = "cell_dt"
    o, base = sm.options(p, Args, None), sm.options(plain, Args, None)
    extra = ["-dem_kn", p["kn"]] + (["-couple_gas_substeps", p["gas_substeps"]] if p["gas_substeps"] > 1 else [])
    t.check(o == base + extra, "%s: the cell_dt point's options with %s added" % (sm.point_id(p), extra))
t.check(len({sm.point_id(p) for p in pts}) == len(pts) and all("_kn%g" % p["kn"] in sm.point_id(p) for p in pts), "each point its own run directory")

dts = {}
for p in pts:
    if p["dt_factor"] == 0.25 and p["kn"] in (800, 200) and p["gas_substeps"] == 1:
        o = [str(a) for a in sm.options(p, Args, None)]
        out, _ = t.run(o[1], args=o[2:], outdir="kn_%g" % p["kn"])  # -options_file first, so that -output_dir is the test's
        s = t.summary(out)
        t.check(abs(s["time"] - 0.001) <= s["dt"], "k_n %g N/m ran to %g s" % (p["kn"], s["time"]))
        dts[p["kn"]] = s["dt"]
t.check(abs(dts[200] / dts[800] - 2.0) < 1e-6, "a quarter of the stiffness, twice the step: %.6g / %.6g s" % (dts[200], dts[800]))

# a kn table with its reference and two points
keys = ["id", "map", "method", "cell_d", "dt_factor", "kn", "jet", "substeps", "cells_per_particle_cell", "class", "status", "exit_status",
        "dp_over_weight", "bed_height_mm", "cost_s_per_s_core", "overlap_max"]
p800 = [p for p in pts if p["kn"] == 800][0]
p100 = [p for p in pts if p["kn"] == 100 and p["gas_substeps"] == 1][0]
rows = [dict(id=sm.point_id(sm.REFERENCE), map="cell_dt", method="two", cell_d=0.43, dt_factor=0.05, kn="", jet=45.3, substeps=1,
             cells_per_particle_cell="7x2", status="ok", exit_status=0, dp_over_weight=1.0, bed_height_mm=80.0, cost_s_per_s_core=1000),
        dict(id=sm.point_id(p800), map="kn", method="two", cell_d=3, dt_factor=0.25, kn=800, jet=45.3, substeps=1, cells_per_particle_cell="1x2",
             status="ok", exit_status=0, dp_over_weight=1.01, bed_height_mm=80.4, cost_s_per_s_core=100, overlap_max=0.03),
        dict(id=sm.point_id(p100), map="kn", method="two", cell_d=3, dt_factor=0.25, kn=100, jet=45.3, substeps=1, cells_per_particle_cell="1x2",
             status="ok", exit_status=0, dp_over_weight=0.95, bed_height_mm=84.0, cost_s_per_s_core=40, overlap_max=0.09)]
with open("kn_table.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
    w.writeheader()
    for r in rows:
        w.writerow(dict(r, **{"class": "stable"}))
got = {r["kn"]: r for r in sa.jet2d_rows("kn_table.csv")}
t.check(sorted(got) == [100.0, 800.0] and all(r["knob"] == "kn" and r["problem"] == "jet2d_kn" for r in got.values()),
        "two chart rows of knob kn on their own panel (jet2d_kn), the reference not among them: %s" % sorted(got))
t.check(abs(got[800.0]["error"] - 0.01) < 1e-12 and abs(got[100.0]["error"] - 0.05) < 1e-12 and got[100.0]["cost"] == 40.0,
        "errors against the table's reference: 800 N/m %.4f (dp +1%%), 100 N/m %.4f (dp -5%%, bed height +5%%)" % (got[800.0]["error"], got[100.0]["error"]))

# the packed and Muller beds' stiffness points
for name in ("packed", "muller"):
    pr = sa.PROBLEMS[name]
    default = pr["options"](pr["defaults"])
    t.check("-dem_kn" not in default, "%s: the default point (the seed's 800 N/m) keeps its command, no -dem_kn" % name)
    soft = [k for (n, knob, k) in sa.points([name], False) if knob == "kn"]
    t.check(sorted(k["kn"] for k in soft) == sorted(pr["knobs"]["kn"]) and 800 not in pr["knobs"]["kn"],
            "%s: the kn points %s, besides the default" % (name, [k["kn"] for k in soft]))
    for k in soft:
        o = pr["options"](k)
        t.check(o == default + ["-dem_kn", k["kn"]], "%s k_n %g: the default's options with -dem_kn added" % (name, k["kn"]))
print("ok")
