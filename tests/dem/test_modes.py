"""Scene modes: pseudo-2D motion, 2D grids, polydisperse random fills, periodic wrapping, and the open top where
particles leave and are counted (none is lost silently)."""
import os

import numpy as np

from fluidbed_tools import testing as t

gas = t.example("dem/granular_gas.opts")

# pseudo-2D: a 3D bed whose particles keep their depth and spin only about z
out, _ = t.run(gas, args=["-dem_pseudo2d", "-insert_count", 1000, "-max_steps", 400, "-output_particles"], outdir="pseudo2d")
start, _ = t.run(gas, args=["-dem_pseudo2d", "-insert_count", 1000, "-max_steps", 0], outdir="pseudo2d_start")
a, b = t.table(os.path.join(start, "particles.csv")), t.table(os.path.join(out, "particles.csv"))
t.check(np.array_equal(a["z"], b["z"]), "pseudo-2D: every particle kept its z")
t.check(np.all(b["vz"] == 0) and np.all(b["wx"] == 0) and np.all(b["wy"] == 0), "pseudo-2D: v_z = 0 and spin only about z")
t.check(np.max(np.abs(b["x"] - a["x"])) > 1e-4, "pseudo-2D: particles moved in x-y (largest |dx| %.2e m)" % np.max(np.abs(b["x"] - a["x"])))

# 2D grids: a polydisperse random fill settles in a planar box
out, _ = t.run(None, args=["-domain_dim", 2, "-domain_lx", 0.03, "-domain_ly", 0.03, "-domain_lz", 1e-3, "-particle_diameter_min", 0.8e-3,
                           "-particle_diameter_max", 1.2e-3, "-insert_type", "random", "-insert_count", 300, "-t_final", 0.15], outdir="poly2d")
p = t.table(os.path.join(out, "particles.csv"))
mon = t.table(os.path.join(out, "monitor.csv"))
t.check(len(p["id"]) == 300 and np.all(p["z"] == 0), "2D: 300 particles in the plane z = 0")
t.check(p["d"].min() >= 0.8e-3 and p["d"].max() <= 1.2e-3 and p["d"].std() > 0.05e-3,
        "polydisperse diameters %.3f..%.3f mm (std %.3f mm)" % (1e3 * p["d"].min(), 1e3 * p["d"].max(), 1e3 * p["d"].std()))
t.check(mon["max_overlap_rel"][-1] < 0.01, "2D settled bed: largest overlap %.3f%% of d (during the pour %.3f%%, impacts of ~0.7 m/s)"
        % (100 * mon["max_overlap_rel"][-1], 100 * mon["max_overlap_rel"].max()))
t.check(np.all((p["x"] > 0) & (p["x"] < 0.03) & (p["y"] > 0) & (p["y"] < 0.03)), "2D: every particle in the box")

# periodic wrap: particles thrown sideways cross x = 0 / x = L many times and stay in [0, L)
out, _ = t.run(gas, args=["-insert_count", 400, "-insert_velocity", "3,0,0", "-max_steps", 2000], outdir="wrap")
p = t.table(os.path.join(out, "particles.csv"))
t.check(len(p["id"]) == 400 and p["x"].min() >= 0 and p["x"].max() < 0.02, "periodic x: 400 particles, x in [%.4f, %.4f) m" % (p["x"].min(), p["x"].max()))

# open top: particles launched upward leave, are removed and counted
out, _ = t.run(None, args=["-domain_top_outlet", "-gravity", "0,-9.81,0", "-insert_count", 200, "-insert_velocity", "0,2,0", "-t_final", 0.05], outdir="outlet")
s = t.summary(out)
mon = t.table(os.path.join(out, "monitor.csv"))
t.check(s["particles_outlet"] > 0 and s["particles"] + s["particles_outlet"] == 200,
        "open top: %d of 200 particles left through the outlet, %d remain, none lost" % (s["particles_outlet"], s["particles"]))
t.check(np.all(mon["particles"] + mon["outlet_removed"] == 200), "every monitor row: particles + removed = 200")
