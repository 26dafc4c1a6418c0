"""scripts/compare_runs.py on monitor series with known answers: a run whose pressure drop is 3% below the reference's
and whose particles' centre of mass is 2% higher is reported as -3% and +2% (within the noise, and the stated
uncertainty near the noise's), the largest overlap of the window (not of the whole run) is reported, the pressure
probes are taken lowest minus highest whatever their column order, and a run without monitor.csv or a window past
the shortest run ends with exit status 2 and a message. A reference stored by --json (its monitor gone) gives the
same differences as the reference run itself, and a window other than the stored one is refused."""
import json
import math
import os
import subprocess
import sys

import numpy as np

from fluidbed_tools import testing as t

SCRIPT = os.path.join(t.SRC, "scripts", "compare_runs.py")
D, RHO, N = 5.5e-4, 2500.0, 1000
MASS = RHO * math.pi / 6 * D ** 3


def write_run(path, dp, height, seed, overlap_late=0.01):
    """monitor.csv every 0.005 s over 0-0.5 s: pressure drop dp and centre height (m) with 1% noise; the largest overlap
    0.2 d before 0.1 s (outside the window compared), overlap_late after."""
    os.makedirs(path, exist_ok=True)
    with open(os.path.join(path, "command.txt"), "w") as f:
        f.write("fluidbed -particle_diameter %g -particle_density %g\n" % (D, RHO))
    rng = np.random.default_rng(seed)
    time = np.arange(0, 0.5 + 1e-9, 0.005)
    with open(os.path.join(path, "monitor.csv"), "w") as f:
        f.write("step,time,particles,contacts_per_particle,pe_grav,max_overlap_rel,p_y279_1mm_avg,p_y0_875mm_avg\n")
        for k, tk in enumerate(time):
            y = height * (1 + 0.01 * rng.standard_normal())
            p = dp * (1 + 0.01 * rng.standard_normal())
            f.write("%d,%.6f,%d,%.4f,%.9e,%.4f,%.6f,%.6f\n" % (k, tk, N, 4.5, N * MASS * 9.81 * y, 0.2 if tk < 0.1 else overlap_late, 10.0, 10.0 + p))


write_run("cmp_ref", 1000.0, 0.030, 1)
write_run("cmp_soft", 970.0, 0.0306, 2, overlap_late=0.04)
p = subprocess.run([sys.executable, SCRIPT, "cmp_ref", "cmp_soft", "--start", "0.1", "--json", "cmp.json", "--plot", "cmp.png"],
                   capture_output=True, text=True)
print(p.stdout, p.stderr)
t.check(p.returncode == 0 and os.path.getsize("cmp.png") > 0, "the comparison ran and drew its plot (exit %d)" % p.returncode)
res = json.load(open("cmp.json"))
ref, soft = res["runs"]
t.check(abs(ref["pressure_drop_Pa"]["mean"] - 1000.0) < 3 and abs(ref["centre_height_mm"]["mean"] - 30.0) < 0.1,
        "the reference: %.2f Pa (lowest probe minus highest), centre %.3f mm" % (ref["pressure_drop_Pa"]["mean"], ref["centre_height_mm"]["mean"]))
dp, dh = soft["relative_difference"]["pressure_drop_Pa"], soft["relative_difference"]["centre_height_mm"]
# 81 samples of 1% noise each side: the difference's standard error is about 0.01 sqrt(2 / 81) = 0.16%
t.check(abs(dp["value"] + 0.03) < 3 * dp["uncertainty"] and 0.0008 < dp["uncertainty"] < 0.004,
        "pressure drop %+.2f%% +- %.2f%% (made -3%%)" % (100 * dp["value"], 100 * dp["uncertainty"]))
t.check(abs(dh["value"] - 0.02) < 3 * dh["uncertainty"] and 0.0008 < dh["uncertainty"] < 0.004,
        "centre height %+.2f%% +- %.2f%% (made +2%%)" % (100 * dh["value"], 100 * dh["uncertainty"]))
t.check(abs(res["start"] - 0.1) < 1e-12 and abs(res["end"] - 0.5) < 1e-9 and ref["samples"] == 81, "window 0.1-0.5 s, 81 samples: %g-%g, %d" % (
    res["start"], res["end"], ref["samples"]))
t.check(ref["max_overlap_rel"] == 0.01 and soft["max_overlap_rel"] == 0.04, "the window's largest overlaps, not the start's 0.2 d: %g, %g" % (
    ref["max_overlap_rel"], soft["max_overlap_rel"]))

# The reference from the JSON just written, as for a run whose folder is gone: the same differences.
p = subprocess.run([sys.executable, SCRIPT, "cmp_soft", "--reference-json", "cmp.json", "--start", "0.1", "--json", "cmp_stored.json", "--plot",
                    "cmp_stored.png"], capture_output=True, text=True)
print(p.stdout, p.stderr)
t.check(p.returncode == 0 and os.path.getsize("cmp_stored.png") > 0, "the comparison with a stored reference ran and drew its plot (exit %d)" %
        p.returncode)
stored = json.load(open("cmp_stored.json"))
t.check(stored["runs"][0]["run"] == "cmp_ref (stored)" and stored["runs"][1]["relative_difference"] == soft["relative_difference"],
        "a stored reference gives the same differences as its run: %s" % stored["runs"][1]["relative_difference"])

for args, what in ((["cmp_ref", "missing_run"], "no monitor.csv"), (["cmp_ref", "cmp_soft", "--start", "0.6"], "windows that do not overlap"),
                   (["cmp_soft", "--reference-json", "cmp.json", "--start", "0.2"], "a window other than the stored reference's"),
                   (["cmp_soft", "--reference-json", "cmp_soft/monitor.csv"], "a stored reference that is not a comparison")):
    p = subprocess.run([sys.executable, SCRIPT] + args, capture_output=True, text=True)
    t.check(p.returncode == 2 and "compare_runs.py:" in p.stderr and "Traceback" not in p.stderr, "%s: exit %d, %s" % (what, p.returncode, p.stderr.strip()))
print("ok")
