"""Verification 5 of the gas phase: the same gas-only scenes on 1, 2 and 4 ranks (several process grids, 2D and
3D, uniform and pressure outlets, models A and B, a periodic depth) give the same fields to 1e-10 relative.
The stencils are evaluated identically on every rank; only the pressure KSP's reductions and hypre's
partition-dependent coarsening differ, hence -fluid_p_ksp_rtol 1e-12 here."""
import os

import numpy as np

from fluidbed_tools import testing as t

jet = t.example("fluid/jet_empty_bed.opts")
slit = ["-inlet_jets", "0.0282,0.00161142857,45.3"]
scenes = {
    "2d_jet_B": (jet, ["-domain_dim", 2, "-grid_nx", 35, "-grid_ny", 50, "-t_final", 0.004] + slit, [(1, None), (2, "2,1"), (2, "1,2"), (4, "2,2"), (4, "4,1")]),
    "3d_bed_A_pressure": (jet, ["-grid_nx", 35, "-grid_ny", 50, "-grid_nz", 5, "-t_final", 0.002, "-fluid_model", "A", "-fluid_bc_yhi", "pressure",
                                "-fluid_eps_packed_bed", "0.06,0.4", "-fluid_eps_sphere", "0.02,0.1,0.0025,0.006,0.5"] + slit,
                          [(1, None), (2, "1,2,1"), (4, "2,1,2")]),
    "3d_periodic_depth_B": (t.example("fluid/cavity_re100.opts"), ["-domain_dim", 3, "-domain_periodic_z", "-grid_nx", 16, "-grid_ny", 16, "-grid_nz", 4,
                                                                   "-t_final", 0.05], [(1, None), (2, "2,1,1"), (4, "1,2,2")]),
}
velocity = ("u", "v", "w", "ufx", "ufy", "ufz")
for name, (opts, args, runs) in scenes.items():
    ref = None
    for n, grid in runs:
        extra = list(args) + ["-fluid_p_ksp_rtol", 1e-12] + (["-pgrid_processors", grid] if grid else [])
        out, _ = t.run(opts, args=extra, nprocs=n, outdir="gas_%s_%d_%s" % (name, n, grid or "auto"))
        c = t.table(os.path.join(out, "fluid_cells.csv"))
        s = t.summary(out)["fluid"]
        if ref is None:
            ref, ref_s = c, s
            print("%s: %d cells, %d gas steps, max speed %.3g m/s" % (name, len(c["i"]), s["steps"], s["max_speed"]))
            continue
        # velocities relative to the largest speed (a component that is zero everywhere has no scale of its own), pressure to its own
        speed = max(np.max(np.abs(ref[k])) for k in velocity)
        worst = max(max(np.max(np.abs(c[k] - ref[k])) for k in velocity) / speed, np.max(np.abs(c["p"] - ref["p"])) / np.max(np.abs(ref["p"])))
        t.check(s["steps"] == ref_s["steps"] and worst <= 1e-10,
                "%s on %d ranks (process grid %s): %d steps, largest relative difference from 1 rank %.1e (limit 1e-10)" % (name, n, grid, s["steps"], worst))
