"""Restart continuity of coupled runs (particles + gas): a run continued from a checkpoint ends in the same state as
the uninterrupted run that wrote it, particles (sorted by id) and every gas cell compared to 1e-12 (found bit for
bit), on 1 and on 2 ranks, for a 3D bubbling bed with 20 DEM steps per gas step (the checkpoint falls between gas
steps; PFMG pressure solver) and the 2D jetted two-grid bed (BoomerAMG). Restarting on another number of ranks works:
same particles, and the drag action and reaction still balance.

Bit-for-bit continuation rests on three things: the checkpoint holds the whole state (particles with contact history
and linearised drag, gas face velocities, pressure, old void fraction, momentum source, coupling cell sums, the DEM
steps left to the next gas step); the coupling sums its particle contributions in an order fixed by cell and
particle id, not by the swarm's storage order; and a checkpoint makes the next pressure solve rebuild its
preconditioner in both runs (-fluid_pc_reuse)."""
import os
import shutil

import numpy as np

from fluidbed_tools import testing as t

scenes = {
    "bubbling_3d": (t.example("coupling/small_bed.opts"), ["-inlet_velocity", 0.5], 0.03),
    "jetted_2d": (t.example("jetted_bed_2d.opts"), [], 0.06),
}


def compare(a, b, label, limit=1e-12):
    pa, pb = t.table(os.path.join(a, "particles.csv")), t.table(os.path.join(b, "particles.csv"))
    t.check(np.array_equal(pa["id"], pb["id"]), "%s: same particle ids (%d)" % (label, len(pa["id"])))
    worst = max(np.max(np.abs(pa[c] - pb[c])) / (np.max(np.abs(pa[c])) or 1) for c in ("x", "y", "vx", "vy", "wz"))
    ga, gb = t.table(os.path.join(a, "fluid_cells.csv")), t.table(os.path.join(b, "fluid_cells.csv"))
    gworst = max(np.max(np.abs(ga[c] - gb[c])) / (np.max(np.abs(ga[c])) or 1) for c in ("u", "v", "p", "eps"))
    t.check(worst <= limit and gworst <= limit,
            "%s: largest relative difference from the uninterrupted run: particles %.1e, gas %.1e (limit %.0e)" % (label, worst, gworst, limit))


for name, (opts, args, t_end) in scenes.items():
    half = t_end / 2
    for n in (1, 2):
        ck_args = args + ["-checkpoint_interval", half]
        full, _ = t.run(opts, args=ck_args + ["-t_final", t_end], nprocs=n, outdir="cfull_%s_%d" % (name, n))
        first, _ = t.run(opts, args=ck_args + ["-t_final", half], nprocs=n, outdir="cpart_%s_%d" % (name, n))
        ck = os.path.join(first, "checkpoint.h5")
        for m in ((n, 3 - n) if n == 2 else (n,)):
            cont = "ccont_%s_%d_%d" % (name, n, m)
            if os.path.isdir(cont):
                shutil.rmtree(cont)
            shutil.copytree(first, cont)
            out, _ = t.run(opts, args=ck_args + ["-t_final", t_end, "-restart", ck], nprocs=m, outdir=cont, clean=False)
            label = "%s: checkpoint from %d rank(s), continued on %d" % (name, n, m)
            mon = t.table(os.path.join(out, "monitor.csv"))
            t.check(np.all(np.diff(mon["step"]) > 0), "%s: monitor.csv continues with increasing steps" % label)
            if m == n:
                compare(full, out, label)
            else:
                pa, pb = t.table(os.path.join(full, "particles.csv")), t.table(os.path.join(out, "particles.csv"))
                t.check(np.array_equal(pa["id"], pb["id"]), "%s: same particles (%d)" % (label, len(pb["id"])))
                bal = np.max(np.abs(mon["drag_particles_y"] + mon["drag_gas_y"])) / np.max(np.abs(mon["drag_particles_y"]))
                t.check(bal < 1e-10, "%s: drag action and reaction balance to %.1e" % (label, bal))
