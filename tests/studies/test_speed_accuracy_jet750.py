"""The 750 um jet problem of scripts/speed_accuracy.py (jet750) on made-up runs with known answers: a run whose jet
column has the reference's solid-fraction profile (linear from 0.5 at 60 mm to 0 at 120 mm, so the fountain top at
solid fraction 0.05 lies at 114 mm, exactly, since the interpolation between cell centres is exact on a line), a
pressure drop 6% above the reference's and a jet velocity 10% below is 10% off (the largest of the three), each part
in the table (the beads held against the closed top are not the fountain); the two mirrored twins, whose pressure drops differ by 2%, give the uncertainty 2%; a run without its
averages yet has no error. The mirrored start (fluidbed_tools.outputs.mirror_particles) reflects x about the bed's
centre, negates the x components of velocity and force and the spin's y and z (an axial vector), and twice is the
identity."""
import csv
import json
import os
import shutil
import sys

import h5py
import numpy as np

from fluidbed_tools import outputs
from fluidbed_tools import testing as t

sys.path.insert(0, os.path.join(t.SRC, "scripts"))
import speed_accuracy as sa  # noqa: E402

NX, NY = 21, 75
H = (0.0564 / NX, 0.28 / NY)


def write_run(path, dp, v_jet, profile_shift=0.0):
    """analysis.h5 of a 2D particle grid whose jet column (x = 28.2 mm) has the linear profile, the rest of the bed
    solid fraction 0.3, and summary.json with the pressure drop."""
    os.makedirs(path, exist_ok=True)
    y = (np.arange(NY) + 0.5) * H[1]
    col = np.clip(0.5 * (1 - (y - 0.060 - profile_shift) / 0.060), 0, 0.5)
    sf = np.full((NY, NX), 0.3)
    i = int(0.0282 / H[0])
    sf[:, i] = col
    sf[-1, i] = 0.6  # beads held against the closed top: not the fountain
    vel = np.zeros((NY, NX, 2))
    vel[:, i, 1] = v_jet * np.exp(-((y - 0.02) / 0.01) ** 2)  # peak v_jet at 20 mm
    with h5py.File(os.path.join(path, "analysis.h5"), "w") as f:
        f["grid/origin"] = [0.0, 0.0, 0.0]
        f["grid/spacing"] = [H[0], H[1], 0.00075]
        f["grid/cells"] = [NX, NY, 1]
        f["fields/solid_fraction"] = sf
        f["fields/velocity"] = vel
        f["measures/samples"] = [500]
        f["measures/window_start"] = [0.5]
        f["measures/window_end"] = [1.0]
    with open(os.path.join(path, "summary.json"), "w") as f:
        json.dump({"averages": {"pressure_drop_mean_Pa": dp}}, f)


here = os.path.abspath("jet750_study")
shutil.rmtree(here, ignore_errors=True)  # a study folder of an earlier run of this test would hold the twins already
pid = lambda k: os.path.join(here, sa.point_id("jet750", k))  # noqa: E731
write_run(pid(sa.JET750_REFERENCE), 500.0, 1.0)
m = sa.jet750_measures(pid(sa.JET750_REFERENCE))
t.check(abs(m["fountain"] - 0.114) < 1e-12 and m["dp"] == 500.0 and abs(m["v_jet"] - 1.0) < 0.01,
        "the reference's measures: fountain %.4f mm (114), pressure drop %g Pa, jet velocity %.3f m/s" % (1e3 * m["fountain"], m["dp"], m["v_jet"]))

point = {"cells_x": 105, "dt_factor": 0.25, "mirror": 0}
write_run(pid(point), 530.0, 0.9)
err, unc, more = sa.jet750_error(pid(point), point)
t.check(unc != unc, "without the twins the uncertainty is not known (NaN): %s" % unc)
t.check(abs(err - 0.1) < 0.01 and abs(more["err_dp"] - 0.06) < 1e-12 and more["err_fountain"] < 1e-12 and abs(more["err_v_jet"] - 0.1) < 0.01,
        "a run 6%% high in pressure drop and 10%% low in jet velocity is %.4f off (dp %.4f, fountain %.2g, velocity %.4f)"
        % (err, more["err_dp"], more["err_fountain"], more["err_v_jet"]))

write_run(pid(sa.JET750_TWINS[0]), 500.0, 1.0)
write_run(pid(sa.JET750_TWINS[1]), 510.0, 1.0)
err2, unc, _ = sa.jet750_error(pid(point), point)
t.check(abs(unc - 0.02) < 1e-12 and err2 == err, "the twins' 2%% difference in pressure drop is the uncertainty: %.4f" % unc)

late = {"cells_x": 105, "dt_factor": 0.05, "mirror": 0}
os.makedirs(pid(late), exist_ok=True)
err3, unc3, _ = sa.jet750_error(pid(late), late)
t.check(err3 != err3, "a run without its averages has no error yet (NaN)")

# the mirrored start
src, dst, back = "bed.csv", "bed_mirrored.csv", "bed_back.csv"
cols = ["id", "d", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "fx", "fy", "fz"]
rows = [[1, 7.5e-4, 0.010, 0.002, 0.0, 0.1, 0.2, 0.0, 1.0, 2.0, 3.0, 0.01, 0.02, 0.03], [2, 7.5e-4, 0.0300, 0.004, 0.0, -0.3, 0.0, 0.0, 0, 0, -5.0, 0, 0, 0]]
with open(src, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(cols)
    w.writerows(rows)
outputs.mirror_particles(src, dst, 0.0564)
mir = list(csv.DictReader(open(dst)))
t.check(abs(float(mir[0]["x"]) - 0.0464) < 1e-15 and float(mir[0]["vx"]) == -0.1 and float(mir[0]["vy"]) == 0.2 and float(mir[0]["wx"]) == 1.0
        and float(mir[0]["wy"]) == -2.0 and float(mir[0]["wz"]) == -3.0 and float(mir[0]["fx"]) == -0.01 and float(mir[0]["fy"]) == 0.02,
        "mirrored: x -> 0.0564 - x, vx and fx negated, spin's y and z negated, the rest kept: %s" % dict(mir[0]))
outputs.mirror_particles(dst, back, 0.0564)
again = list(csv.DictReader(open(back)))
t.check(all(abs(float(a[c]) - float(r[k])) < 1e-15 for a, r in zip(again, rows) for k, c in enumerate(cols)), "mirrored twice: the bed itself")
print("ok")
