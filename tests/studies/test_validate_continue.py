"""scripts/validate.sh with FLUIDBED_CONTINUE=1 continues a run from its newest checkpoint with the same command: a
two-sphere head-on collision run to 1 ms (checkpoints every 0.5 ms), then continued to 2 ms, ends where the same
run made in one go ends (the tracked spheres' positions and velocities within 1e-12, relative: a restart repeats
the run bit for bit), with the restart in its appended command.txt; continuing a folder that has no
checkpoint stops with a message naming FLUIDBED_CONTINUE and a nonzero exit."""
import os
import subprocess

import numpy as np

from fluidbed_tools import outputs
from fluidbed_tools import testing as t

SCRIPT = os.path.join(t.SRC, "scripts", "validate.sh")


def validate(folder, extra, cont=False):
    env = dict(os.environ, FLUIDBED_EXE=t.EXE, FLUIDBED_VALIDATION_DIR=os.path.abspath(folder), FLUIDBED_CONTINUE="1" if cont else "0")
    p = subprocess.run(["bash", SCRIPT, "dem/head_on", "1", "-checkpoint_interval", "5e-4", "-monitor_dt", "1e-5"] + extra, env=env,
                       capture_output=True, text=True, timeout=600)
    print(p.stdout[-1500:], p.stderr[-1500:])
    return p


p = validate("whole", ["-t_final", "2e-3"])
t.check(p.returncode == 0, "the run in one go (exit %d)" % p.returncode)
p = validate("parts", ["-t_final", "1e-3"])
t.check(p.returncode == 0, "the first part, to 1 ms (exit %d)" % p.returncode)
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


a, b = final_particles("whole"), final_particles("parts")
cols = [n for n in a.dtype.names if n in ("x", "y", "z", "vx", "vy", "vz")]
t.check(len(cols) == 6 and len(a) == len(b) == 2, "both runs end with the two spheres' positions and velocities (%s)" % ", ".join(cols))
worst = max(float(np.max(np.abs(a[c] - b[c]) / np.maximum(np.abs(a[c]), 1e-30))) for c in cols)
t.check(worst < 1e-12, "the continued run ends as the run in one go (worst relative difference %.2g)" % worst)

p = validate("empty", ["-t_final", "1e-3"], cont=True)
t.check(p.returncode != 0 and "FLUIDBED_CONTINUE" in p.stderr, "continuing a folder with no checkpoint stops with a message (exit %d)" % p.returncode)
print("ok")
