"""Restart continuity: a run continued from a checkpoint ends in the same state as the uninterrupted run
(compared to 1e-12, found bit for bit) on 1 and on 2 ranks, and restarting on a different number of ranks works
(1 -> 2, 2 -> 1, again bit for bit). A checkpoint whose write fails leaves the previous one intact."""
import os
import shutil

import numpy as np

from fluidbed_tools import testing as t

scene = ["-insert_type", "random", "-insert_count", 2000, "-insert_velocity_random", 0.3, "-insert_seed", 5]


def compare(a, b, label):
    pa, pb = t.table(os.path.join(a, "particles.csv")), t.table(os.path.join(b, "particles.csv"))
    t.check(np.array_equal(pa["id"], pb["id"]), "%s: same particle ids" % label)
    worst = max(np.max(np.abs(pa[c] - pb[c])) / (np.max(np.abs(pa[c])) or 1) for c in ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"))
    t.check(worst <= 1e-12, "%s: largest relative difference from the uninterrupted run %.1e (limit 1e-12)" % (label, worst))


for n in (1, 2):
    full, _ = t.run(None, args=scene + ["-t_final", 0.04], nprocs=n, outdir="full_%d" % n)
    first, _ = t.run(None, args=scene + ["-t_final", 0.02, "-checkpoint_interval", 0.01], nprocs=n, outdir="part_%d" % n)
    t.check(os.path.isfile(os.path.join(first, "checkpoint.h5")) and not os.path.exists(os.path.join(first, "checkpoint.h5.tmp")),
            "%d rank(s): checkpoint.h5 written, no temporary file left" % n)
    ck = os.path.join(first, "checkpoint.h5")
    for m in (n, 3 - n):
        cont = "cont_%d_%d" % (n, m)
        if os.path.isdir(cont):
            shutil.rmtree(cont)
        shutil.copytree(first, cont)  # continue in a copy of the first run's directory (monitor.csv is appended)
        out, _ = t.run(None, args=scene + ["-t_final", 0.04, "-restart", ck], nprocs=m, outdir=cont, clean=False)
        compare(full, out, "checkpoint from %d rank(s), continued on %d" % (n, m))
        mon = t.table(os.path.join(out, "monitor.csv"))
        t.check(np.all(np.diff(mon["step"]) > 0), "the continued monitor.csv has increasing steps (%d rows)" % len(mon["step"]))

# a failing checkpoint write (the temporary path is unusable) stops the run and keeps the previous checkpoint
first = "part_1"
before = open(os.path.join(first, "checkpoint.h5"), "rb").read()
os.makedirs(os.path.join(first, "checkpoint.h5.tmp"), exist_ok=True)  # a directory where the file should go
_, p = t.run(None, args=scene + ["-t_final", 0.03, "-restart", os.path.join(first, "checkpoint.h5"), "-checkpoint_interval", 0.005],
             outdir=first, expect_fail=True, clean=False)
t.check(p.returncode != 0, "a checkpoint that cannot be written stops the run (exit %d)" % p.returncode)
t.check(open(os.path.join(first, "checkpoint.h5"), "rb").read() == before, "the previous checkpoint is unchanged")
