"""A signal ends a run early and cleanly: a settling box (2000 spheres) sent SIGTERM on one rank, and SIGUSR1 through
mpiexec on two (mpiexec passes it on to the ranks), stops at a step all ranks agree on with exit status 4 (status.hpp,
EXIT_INTERRUPTED), summary.json status "interrupted" with the signal, before -t_final, and writes the state reached
as its checkpoint and final files. Continued from that checkpoint with -restart, it ends where the run made in one go
ends, bit for bit (positions and velocities of every sphere)."""
import os
import shutil
import signal
import subprocess
import time

import numpy as np

from fluidbed_tools import run as fr
from fluidbed_tools import testing as t

SCENE = t.example("dem/settle_box.opts")
OPTS = ["-insert_count", 2000, "-t_final", 0.12, "-checkpoint_interval", 1.0]


def particles(folder):
    p = np.genfromtxt(os.path.join(folder, "particles.csv"), delimiter=",", names=True)
    return p[np.argsort(p["id"])]


for ranks, sig in ((1, signal.SIGTERM), (2, signal.SIGUSR1)):
    whole, _ = t.run(SCENE, args=OPTS, nprocs=ranks, outdir="whole_np%d" % ranks)
    folder = "parts_np%d" % ranks
    shutil.rmtree(folder, ignore_errors=True)
    cmd = fr.command(["-options_file", SCENE] + OPTS + ["-output_dir", folder, "-progress_interval", 0], ranks)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=fr.ENV)
    for line in proc.stdout:  # the time loop has started
        if line.startswith("Running"):
            break
    time.sleep(1.0)
    proc.send_signal(sig)
    rest, _ = proc.communicate(timeout=600)
    print(rest[-2500:])
    s = t.summary(folder)
    w = t.summary(whole)
    t.check(proc.returncode == 4, "%d rank(s), signal %d: exit status %d, expected 4" % (ranks, sig, proc.returncode))
    t.check(s["status"] == "interrupted" and s.get("interrupt_signal") == int(sig) and s["exit_code"] == 4,
            "summary.json: status %s, signal %s, exit code %s" % (s["status"], s.get("interrupt_signal"), s["exit_code"]))
    t.check(0 < s["steps"] < w["steps"] and s["steps"] % 32 == 0, "stopped early at step %d of %d (a multiple of the 32-step agreement)" % (s["steps"], w["steps"]))
    t.check(os.path.exists(os.path.join(folder, "checkpoint.h5")) and "continue from it with -restart" in rest,
            "the state reached is the checkpoint, and the message says how to continue")
    shutil.copy(os.path.join(folder, "checkpoint.h5"), folder + "_restart.h5")
    t.run(SCENE, args=OPTS + ["-restart", folder + "_restart.h5"], nprocs=ranks, outdir=folder, clean=False)
    a, b = particles(whole), particles(folder)
    cols = ["x", "y", "z", "vx", "vy", "vz"]
    worst = max(float(np.max(np.abs(a[c] - b[c]))) for c in cols)
    t.check(len(a) == len(b) == 2000 and worst == 0.0, "continued to t_final on %d rank(s): the same %d spheres, largest difference %.3g" % (ranks, len(b), worst))
print("ok")
