"""scripts/validate.sh with FLUIDBED_CONTINUE=1 continues a run from its newest checkpoint with the same command: a
two-sphere head-on collision run to 1 ms (checkpoints every 0.5 ms), then continued to 2 ms, ends where the same
run made in one go ends (the tracked spheres' positions and velocities within 1e-12, relative: a restart repeats
the run bit for bit), with the restart in its appended command.txt; continuing a folder that has no
checkpoint stops with a message naming FLUIDBED_CONTINUE and a nonzero exit.

scripts/campaign.sh carries a run to another machine: the first part saved (packed checkpoint and records), restored
into a new folder and continued there ends as the run in one go too; a restore over an existing checkpoint and a
restore of a damaged pack stop with a message and a nonzero exit."""
import os
import re
import shutil
import subprocess

import numpy as np

from fluidbed_tools import outputs
from fluidbed_tools import testing as t

SCRIPT = os.path.join(t.SRC, "scripts", "validate.sh")
CAMPAIGN = os.path.join(t.SRC, "scripts", "campaign.sh")
STORE = os.path.abspath("store")


def campaign(*args):
    p = subprocess.run(["bash", CAMPAIGN] + list(args), env=dict(os.environ, FLUIDBED_CAMPAIGN_DIR=STORE), capture_output=True, text=True,
                       timeout=300)
    print(p.stdout[-800:], p.stderr[-800:])
    return p


def validate(folder, extra, cont=False):
    env = dict(os.environ, FLUIDBED_EXE=t.EXE, FLUIDBED_VALIDATION_DIR=os.path.abspath(folder), FLUIDBED_CONTINUE="1" if cont else "0")
    p = subprocess.run(["bash", SCRIPT, "dem/head_on", "1", "-checkpoint_interval", "5e-4", "-monitor_dt", "1e-5"] + extra, env=env,
                       capture_output=True, text=True, timeout=600)
    print(p.stdout[-1500:], p.stderr[-1500:])
    return p


for leftover in ("moved", "damaged", STORE):  # from an earlier run of this test in the same build folder
    shutil.rmtree(leftover, ignore_errors=True)
p = validate("whole", ["-t_final", "2e-3"])
t.check(p.returncode == 0, "the run in one go (exit %d)" % p.returncode)
p = validate("parts", ["-t_final", "1e-3"])
t.check(p.returncode == 0, "the first part, to 1 ms (exit %d)" % p.returncode)
# The first part carried to a new folder, as to a fresh machine: saved, restored, continued there.
# A finished run's averages (analysis.h5) travel with its records; a stand-in here, taken away again after the save.
stand_in = os.path.join("parts", "dem", "head_on", "analysis.h5")
open(stand_in, "wb").write(b"averages of a finished run\x00\x01\x02")
p = campaign("save", os.path.join("parts", "dem", "head_on"), "head_on")
os.remove(stand_in)
t.check(p.returncode == 0 and os.path.isfile(os.path.join(STORE, "head_on", "checkpoint.h5.xz")), "campaign.sh save packs the first part (exit %d)" %
        p.returncode)
m = re.search(r"checkpoint: t = ([0-9.e+-]+) s, step (\d+)", open(os.path.join(STORE, "head_on", "state.txt")).read())
t.check(m is not None and abs(float(m.group(1)) - 1e-3) < 1e-5, "state.txt gives the checkpoint's bed time, 1 ms (%s)" %
        (m.group(0) if m else "no time"))
p = campaign("restore", "head_on", os.path.join("moved", "dem", "head_on"))
t.check(p.returncode == 0, "campaign.sh restore unpacks it into a new folder (exit %d)" % p.returncode)
moved_analysis = os.path.join("moved", "dem", "head_on", "analysis.h5")
t.check(os.path.isfile(moved_analysis) and open(moved_analysis, "rb").read() == b"averages of a finished run\x00\x01\x02",
        "analysis.h5 is saved and restored with the run")
os.remove(moved_analysis)
p = campaign("restore", "head_on", os.path.join("moved", "dem", "head_on"))
t.check(p.returncode != 0 and "already has a checkpoint" in p.stderr, "a restore over a run's checkpoint stops (exit %d)" % p.returncode)
p = validate("moved", ["-t_final", "2e-3"], cont=True)
t.check(p.returncode == 0, "the restored run continued to 2 ms (exit %d)" % p.returncode)
p = validate("parts", ["-t_final", "2e-3"], cont=True)
t.check(p.returncode == 0, "the second part, continued to 2 ms (exit %d)" % p.returncode)
lines = open(os.path.join("parts", "dem", "head_on", "command.txt")).read().splitlines()
t.check(len(lines) == 2 and "-restart" in lines[1] and "-restart" not in lines[0], "command.txt holds both commands, the second a restart")
s = outputs.summary(os.path.join("parts", "dem", "head_on"))
w = outputs.summary(os.path.join("whole", "dem", "head_on"))
t.check(s["time"] == w["time"] and s["steps"] == w["steps"] and s["time"] >= 2e-3,
        "the continued run reached t = %.6g s in %d steps, as the run in one go (%.6g s, %d)" % (s["time"], s["steps"], w["time"], w["steps"]))


def final_particles(folder):
    return np.genfromtxt(os.path.join(folder, "dem", "head_on", "particles.csv"), delimiter=",", names=True)


a = final_particles("whole")
for folder in ("parts", "moved"):
    b = final_particles(folder)
    cols = [n for n in a.dtype.names if n in ("x", "y", "z", "vx", "vy", "vz")]
    t.check(len(cols) == 6 and len(a) == len(b) == 2, "both runs end with the two spheres' positions and velocities (%s)" % ", ".join(cols))
    worst = max(float(np.max(np.abs(a[c] - b[c]) / np.maximum(np.abs(a[c]), 1e-30))) for c in cols)
    t.check(worst < 1e-12, "the run continued in %s ends as the run in one go (worst relative difference %.2g)" % (folder, worst))

# A damaged pack (one byte changed) must not become a checkpoint.
pack = os.path.join(STORE, "head_on", "checkpoint.h5.xz")
data = bytearray(open(pack, "rb").read())
data[len(data) // 2] ^= 0xFF
open(pack, "wb").write(bytes(data))
p = campaign("restore", "head_on", "damaged")
t.check(p.returncode != 0 and "damaged" in p.stderr and os.listdir("damaged") in ([], ["plots"]), "a damaged pack is not restored, nothing left of it (exit %d)" %
        p.returncode)

p = validate("empty", ["-t_final", "1e-3"], cont=True)
t.check(p.returncode != 0 and "FLUIDBED_CONTINUE" in p.stderr, "continuing a folder with no checkpoint stops with a message (exit %d)" % p.returncode)
print("ok")
