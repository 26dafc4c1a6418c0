"""The Muller profile answer of scripts/speed_accuracy.py (profile_difference) on snapshots with a known answer: runs of
the same lopsided profile with independent noise (rms 0.02 per cell and snapshot) differ by no more than three times
the uncertainty it states, and that uncertainty is near the noise's own; the mirror image of the profile is the same
answer (the bed is symmetric, so the profiles are compared mirror-symmetrised); a profile 5% wetter everywhere is 5%
off, within the noise. With a long run as the reference (--muller-long), every point is compared with it, the
t_cr/20 one included; and the windows cut from a long run whose profile swells and shrinks by 5% with a 4 s period
leave about 3% after 1 s of averaging and next to nothing after two whole periods (8 s). An ensemble of long runs
(--muller-long A,B) is their mean, with the runs' spread as its uncertainty where it exceeds their block errors, and each
run is compared with the others (leave one out)."""
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


def write_run(path, profile, seed, count=101, args=()):
    """Snapshots every 0.05 s (by default 0-5 s; the comparison takes 1-5 s); profile: cells' voidage, or a function
    of time giving them; args: more options recorded as the run's."""
    os.makedirs(path, exist_ok=True)
    with open(os.path.join(path, "command.json"), "w") as f:  # the bed's height, as a study's run records it
        json.dump({"args": ["fluidbed", "-domain_ly", 0.16] + list(args), "ranks": 1}, f)
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

# an ensemble of two long runs (--muller-long A,B): 2% wetter and, mirrored, 2% drier than BASE; made mirror-symmetric
# their mean is SYM, with an uncertainty from their spread (2% of SYM), far above their block errors
SYM = 0.5 * (BASE + BASE[::-1])
write_run("prof_long_a", 1.02 * BASE, 6, count=261, args=["-insert_seed", 1])
write_run("prof_long_b", 0.98 * BASE[::-1], 7, count=261, args=["-insert_seed", 3])
ens, ens_err = sa.reference_profiles(("prof_long_a", "prof_long_b"), sa.MULLER_LONG_BLOCK)
sym2 = np.concatenate([SYM, SYM])
t.check(np.sqrt(np.mean((ens / sym2 - 1) ** 2)) < 0.002, "the ensemble's mean is the symmetric profile: %.4f%% rms" % (100 * np.sqrt(np.mean((ens / sym2 - 1) ** 2))))
t.check(np.all((0.015 < ens_err / sym2) & (ens_err / sym2 < 0.025)), "its uncertainty is the runs' spread, 2%%: %.2f-%.2f%%" % (
    100 * (ens_err / sym2).min(), 100 * (ens_err / sym2).max()))
single, single_err = sa.reference_profiles(("prof_long_a",), sa.MULLER_LONG_BLOCK)
# six 2 s blocks of 40 snapshots, noise 0.01 per symmetrised snapshot: about 0.15% of SYM (estimated with 5 degrees of freedom)
single_rms = np.sqrt(np.mean((single_err / sym2) ** 2))
t.check(single_rms < 0.005, "one run alone states only its block error: %.3f%% rms" % (100 * single_rms))
err_e, unc_e = sa.profile_difference("prof_ref", ("prof_long_a", "prof_long_b"), sa.MULLER_LONG_BLOCK)
t.check(err_e < 3 * unc_e and 0.015 < unc_e < 0.025, "a point of BASE against the ensemble: %.3f%% apart, uncertainty %.3f%%" % (100 * err_e, 100 * unc_e))
pair = {r["id"]: r for r in sa.muller_long_rows(["prof_long_a", "prof_long_b"], 1.0)}
t.check(sorted(pair) == ["muller_profile_run_seed1", "muller_profile_run_seed3"], "one row per long run, named by its seed: %s" % sorted(pair))
# each against the other: 1.02 / 0.98 - 1 = 4.1%, 0.98 / 1.02 - 1 = -3.9%
t.check(abs(pair["muller_profile_run_seed1"]["error"] - 0.0408) < 0.003 and abs(pair["muller_profile_run_seed3"]["error"] - 0.0392) < 0.003,
        "each run against the other: %.2f%% and %.2f%%" % (100 * pair["muller_profile_run_seed1"]["error"], 100 * pair["muller_profile_run_seed3"]["error"]))
t.check(pair["muller_profile_run_seed1"]["window"] == 12.0 and pair["muller_profile_run_seed1"]["cost"] == 13.0,
        "the window is the run's 1-13 s, its cost 13 s of bed: %s" % pair["muller_profile_run_seed1"])
print("ok")
