"""The particle-grid ratio as a knob of its own (scripts/stability_map.py --maps ratio; scripts/speed_accuracy.py,
knob pgrid_ratio): each ratio point is the reference's run (two grids on the seed's 0.43 d gas cells, t_cr/20, the
seed's jet) with only -pgrid_ratio changed; the coarsest, 25 x 4 gas cells per particle cell, runs 1 ms of bed from
the lattice and reports those particle cells in its summary; a ratio table turns into chart rows of knob pgrid_ratio (their own panel, jet2d_ratio),
each error the larger of the pressure drop's and the bed height's relative differences from that table's own
reference row."""
import csv
import os
import sys

from fluidbed_tools import testing as t

sys.path.insert(0, os.path.join(t.SRC, "scripts"))
import speed_accuracy as sa  # noqa: E402
import stability_map as sm  # noqa: E402

pts = sm.points(["ratio"], False)
t.check([tuple(p["ratio"]) for p in pts] == sm.RATIOS and (7, 2) not in sm.RATIOS, "one point per ratio, not the reference's 7 x 2: %s" % sm.RATIOS)


class Args:
    t_final = 0.001


for p in pts:
    o = sm.options(p, Args, None)
    ref = sm.options(sm.REFERENCE, Args, None)
    diff = [(a, b) for a, b in zip(o, ref) if a != b]
    t.check(len(o) == len(ref) and diff == [("%d,%d" % tuple(p["ratio"]), "7,2")], "%s: only -pgrid_ratio differs from the reference (%s)" % (sm.point_id(p), diff))

coarse = [p for p in pts if tuple(p["ratio"]) == (25, 4)][0]
o = [str(a) for a in sm.options(coarse, Args, None)]
out, _ = t.run(o[1], args=o[2:], outdir="ratio_25x4")  # -options_file first, so that -output_dir is the test's
s = t.summary(out)
t.check(s["model"]["fluid_cells_per_particle_cell"][:2] == [25, 4] and abs(s["time"] - 0.001) <= s["dt"],
        "the 25 x 4 point ran to %g s on particle cells of %s gas cells" % (s["time"], s["model"]["fluid_cells_per_particle_cell"]))

# a ratio table with its reference and two points
keys = ["id", "map", "method", "cell_d", "dt_factor", "jet", "substeps", "cells_per_particle_cell", "class", "status", "exit_status",
        "dp_over_weight", "bed_height_mm", "cost_s_per_s_core"]
rows = [dict(id=sm.point_id(sm.REFERENCE), map="cell_dt", method="two", cell_d=0.43, dt_factor=0.05, jet=45.3, substeps=1,
             cells_per_particle_cell="7x2", status="ok", exit_status=0, dp_over_weight=1.0, bed_height_mm=80.0, cost_s_per_s_core=100),
        dict(id=sm.point_id(pts[0]), map="ratio", method="two", cell_d=0.43, dt_factor=0.05, jet=45.3, substeps=1, cells_per_particle_cell="5x1",
             status="ok", exit_status=0, dp_over_weight=1.03, bed_height_mm=79.2, cost_s_per_s_core=110),
        dict(id=sm.point_id(pts[3]), map="ratio", method="two", cell_d=0.43, dt_factor=0.05, jet=45.3, substeps=1, cells_per_particle_cell="25x4",
             status="ok", exit_status=0, dp_over_weight=0.98, bed_height_mm=88.0, cost_s_per_s_core=90)]
with open("ratio_table.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
    w.writeheader()
    for r in rows:
        w.writerow(dict(r, **{"class": "stable"}))
got = {r["cell"].split(", ")[-1]: r for r in sa.jet2d_rows("ratio_table.csv")}
t.check(sorted(got) == ["particle cells 25x4", "particle cells 5x1"] and all(r["knob"] == "pgrid_ratio" and r["problem"] == "jet2d_ratio" for r in got.values()),
        "two chart rows of knob pgrid_ratio on their own panel (jet2d_ratio), the reference not among them: %s" % sorted(got))
t.check(abs(got["particle cells 5x1"]["error"] - 0.03) < 1e-12 and abs(got["particle cells 25x4"]["error"] - 0.10) < 1e-12,
        "errors against the table's reference: 5x1 %.4f (dp +3%%), 25x4 %.4f (bed height +10%%)" %
        (got["particle cells 5x1"]["error"], got["particle cells 25x4"]["error"]))
