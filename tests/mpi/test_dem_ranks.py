"""Verification 6: the same DEM scene on 1, 2 and 4 ranks (several process grids, 3D and 2D, periodic faces)
keeps every particle (count and id set) and gives the same positions after 200 steps. The contact sums are
ordered by particle id, so the agreement is expected bit for bit; the test allows 1e-10 relative."""
import os

import numpy as np

from fluidbed_tools import testing as t

scenes = {
    "3d": (["-max_steps", 200], [(1, None), (2, "2,1,1"), (2, "1,1,2"), (4, "2,1,2"), (4, "1,2,2")]),
    "2d": (["-domain_dim", 2, "-insert_count", 200, "-max_steps", 200], [(1, None), (2, "2,1"), (4, "2,2"), (4, "4,1")]),
}
for name, (args, runs) in scenes.items():
    ref = None
    for n, grid in runs:
        extra = list(args) + (["-pgrid_processors", grid] if grid else [])
        out, _ = t.run(t.example("dem/granular_gas.opts"), args=extra, nprocs=n, outdir="gas_%s_%d_%s" % (name, n, grid or "auto"))
        p = t.table(os.path.join(out, "particles.csv"))
        mon = t.table(os.path.join(out, "monitor.csv"))
        if ref is None:
            ref, ref_mon = p, mon
            t.check(mon["contacts_per_particle"].max() > 0.05, "%s: %.3f contacts per particle at the busiest row" % (name, mon["contacts_per_particle"].max()))
            continue
        label = "%s on %d ranks (process grid %s)" % (name, n, grid)
        t.check(len(p["id"]) == len(ref["id"]) and np.array_equal(p["id"], ref["id"]), "%s: same %d particle ids as on 1 rank" % (label, len(ref["id"])))
        worst = 0.0
        for c in ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"):
            scale = np.max(np.abs(ref[c])) or 1.0
            worst = max(worst, np.max(np.abs(p[c] - ref[c])) / scale)
        t.check(worst <= 1e-10, "%s: largest relative difference of positions and velocities from 1 rank %.1e (limit 1e-10)" % (label, worst))
