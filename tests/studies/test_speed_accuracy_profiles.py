"""The Muller profile answer of scripts/speed_accuracy.py (profile_difference) on snapshots with a known answer: runs of
the same lopsided profile with independent noise (rms 0.02 per cell and snapshot) differ by no more than three times
the uncertainty it states, and that uncertainty is near the noise's own; the mirror image of the profile is the same
answer (the bed is symmetric, so the profiles are compared mirror-symmetrised); a profile 5% wetter everywhere is 5%
off, within the noise. With a long run as the reference (--muller-long), every point is compared with it, the
t_cr/20 one included; and the windows cut from a long run whose profile swells and shrinks by 5% with a 4 s period
leave about 3% after 1 s of averaging and next to nothing after two whole periods (8 s)."""
import json
import os
import sys

import h5py
import numpy as np

from fluidbed_tools import testing as t

sys.path.insert(0, os.path.join(t.SRC, "scripts"))
import speed_accuracy as sa  # noqa: E402

NX, NY, NZ = 12, 32, 2
BASE = 0.45 + 0.4 * np.linspace(0, 1, NX) ** 2  # lopsided: wet on the right


def write_run(path, profile, seed, count=101):
    """Snapshots every 0.05 s (by default 0-5 s; the comparison takes 1-5 s); profile: cells' voidage, or a function
    of time giving them."""
    os.makedirs(path, exist_ok=True)
    with open(os.path.join(path, "command.json"), "w") as f:  # the bed's height, as a study's run records it
        json.dump({"args": ["fluidbed", "-domain_ly", 0.16], "ranks": 1}, f)
    rng = np.random.default_rng(seed)
    for k in range(count):
        prof = profile(0.05 * k) if callable(profile) else profile
        eps = np.broadcast_to(prof, (NZ, NY, NX)) + 0.02 * rng.standard_normal((NZ, NY, NX))
        with h5py.File(os.path.join(path, "snapshot_%05d.h5" % k), "w") as f:
            f.attrs["time"] = 0.05 * k
            f["fluid/void_fraction"] = eps


write_run("prof_ref", BASE, 1)
write_run("prof_same", BASE, 2)
write_run("prof_mirror", BASE[::-1], 3)
write_run("prof_wet", 1.05 * BASE, 4)

m, e, n = sa.muller_profiles("prof_ref")
t.check(n == 81 and m.shape == (2 * NX,), "81 snapshots in 1-5 s, two rows of %d cells (%d, %s)" % (NX, n, m.shape))
t.check(np.allclose(m, m.reshape(2, NX)[:, ::-1].ravel()), "the averaged rows are mirror-symmetric")
# one cell's symmetrised series: the mean of two cells, two depth cells each, so noise 0.02 / 2 per snapshot; over
# 81 snapshots the standard error is about 0.01 / 9
t.check(np.all((0.3 * 0.01 / 9 < e) & (e < 3 * 0.01 / 9)), "each cell's standard error is near the noise's 0.0011 (%.5f-%.5f)" % (e.min(), e.max()))

err, unc = sa.profile_difference("prof_same", "prof_ref")
t.check(err < 3 * unc, "the same settings, other noise: %.4f%% apart, uncertainty %.4f%%" % (100 * err, 100 * unc))
err_m, unc_m = sa.profile_difference("prof_mirror", "prof_ref")
t.check(err_m < 3 * unc_m, "the mirrored profile is the same answer: %.4f%% apart, uncertainty %.4f%%" % (100 * err_m, 100 * unc_m))
err_w, unc_w = sa.profile_difference("prof_wet", "prof_ref")
t.check(abs(err_w - 0.05) < 3 * unc_w + 0.002, "5%% wetter everywhere: %.3f%% (uncertainty %.3f%%)" % (100 * err_w, 100 * unc_w))

rows = [{"problem": "muller", "knob": "dt_factor", "id": "muller_dt_factor0.05_substeps1", "status": "ok", "dt_factor": 0.05, "substeps": 1, "cost": 2.0},
        {"problem": "muller", "knob": "dt_factor", "id": "muller_dt_factor0.1_substeps1", "status": "ok", "dt_factor": 0.1, "substeps": 1, "cost": 1.0}]
os.makedirs("prof_runs", exist_ok=True)
for name, src in (("muller_dt_factor0.05_substeps1", "prof_ref"), ("muller_dt_factor0.1_substeps1", "prof_wet")):
    if not os.path.exists(os.path.join("prof_runs", name)):
        os.symlink(os.path.abspath(src), os.path.join("prof_runs", name))
got = sa.muller_profile_rows(rows, "prof_runs")
t.check(len(got) == 1 and got[0]["id"] == "muller_profile_dt_factor0.1_substeps1" and abs(got[0]["error"] - err_w) < 1e-12 and got[0]["cost"] == 1.0,
        "one derived row, the t_cr/10 point against the t_cr/20 reference: %s" % got)
t.check(sa.muller_profile_rows(rows[1:], "prof_runs") == [], "no rows before the reference has run")

# a long reference, 0-13 s, whose profile swells and shrinks by 5% every 4 s: its 1-13 s mean is BASE
write_run("prof_long", lambda time: BASE * (1 + 0.05 * np.sin(2 * np.pi * (time - 1.0) / 4.0)), 5, count=261)
got = sa.muller_profile_rows(rows, "prof_runs", long_run="prof_long")
t.check(sorted(r["id"] for r in got) == ["muller_profile_dt_factor0.05_substeps1", "muller_profile_dt_factor0.1_substeps1"],
        "with a long reference both points are compared: %s" % [r["id"] for r in got])
near = [r for r in got if r["dt_factor"] == 0.05][0]
t.check(near["error"] < 0.03, "the t_cr/20 stand-in (BASE over 1-5 s, one whole period) is near the long mean: %.3f%%" % (100 * near["error"]))
win = {r["window"]: r for r in sa.muller_profile_window_rows("prof_long", 1.0)}
t.check(sorted(win) == [0.25, 0.5, 1.0, 2.0, 4.0, 8.0], "windows up to 8 s of the 12 s run: %s" % sorted(win))
# over 1 to 2 s the swell averages (4 / 2 pi) x 0.05 = 3.2%
t.check(0.02 < win[1.0]["error"] < 0.045, "1 s of averaging leaves %.2f%% (expected about 3.2%%)" % (100 * win[1.0]["error"]))
t.check(win[8.0]["error"] < 0.005, "two whole periods leave %.3f%%" % (100 * win[8.0]["error"]))
t.check(win[8.0]["cost"] == 9.0, "a window's cost is 1 s of settling plus the window: %g" % win[8.0]["cost"])
print("ok")
