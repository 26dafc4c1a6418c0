"""Coupling verification 5: the two-grid path with -pgrid_ratio 1 gives the same answer as the single-grid path
(-couple_grid single, void fraction and drag summed directly on the fluid cells) to 1e-12, here bit for bit."""
import os

import numpy as np

from fluidbed_tools import testing as t

args = ["-t_final", 0.03, "-inlet_velocity", 0.5, "-fluid_output_cells"]
two, _ = t.run(t.example("coupling/small_bed.opts"), args=args + ["-couple_grid", "two", "-pgrid_ratio", 1], outdir="ratio_one_two")
single, _ = t.run(t.example("coupling/small_bed.opts"), args=args + ["-couple_grid", "single"], outdir="ratio_one_single")
pa, pb = t.table(os.path.join(two, "particles.csv")), t.table(os.path.join(single, "particles.csv"))
ga, gb = t.table(os.path.join(two, "fluid_cells.csv")), t.table(os.path.join(single, "fluid_cells.csv"))
dp = max(np.max(np.abs(pa[c] - pb[c])) / (np.max(np.abs(pa[c])) or 1) for c in ("x", "y", "z", "vx", "vy", "vz"))
dg = max(np.max(np.abs(ga[c] - gb[c])) / (np.max(np.abs(ga[c])) or 1) for c in ("u", "v", "w", "p", "eps"))
moved = np.max(np.abs(pa["vy"]))
t.check(moved > 1e-3, "the particles moved (largest |v_y| %.3f m/s)" % moved)
t.check(dp <= 1e-12, "particles: largest relative difference %.1e (limit 1e-12)" % dp)
t.check(dg <= 1e-12, "gas: largest relative difference %.1e (limit 1e-12)" % dg)
