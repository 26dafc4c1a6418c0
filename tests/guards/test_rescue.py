"""A run stopped by a guard is continued from its last good checkpoint with a safer time step and finishes; a restart
that would change the physics or the layout of the saved state is refused with the option named.

The scene: 3000 spheres colliding in a closed box (examples/dem/granular_gas.opts). At dt = 0.52 t_cr the contacts
are not resolved and the energy grows; the guard stops the run after its checkpoints at 1 and 2 ms. Continued at
dt = t_cr / 10 it runs to its end: the energy guard then sees no growth, every particle is still there, and the
monitor holds each step once."""
import os

import numpy as np

from fluidbed_tools import testing as t

gas = t.example("dem/granular_gas.opts")
common = ["-max_steps", "-1", "-t_final", "0.01", "-checkpoint_interval", "0.001"]

for n in (1, 2):
    out = "rescue_%d" % n
    _, p = t.run(gas, args=common + ["-dem_dt_factor", "0.52"], outdir=out, nprocs=n, expect_fail=True)
    s = t.summary(out)
    t.check(p.returncode != 0 and s["status"] == "stopped", "%d rank(s), dt = 0.52 t_cr: stopped by guard '%s' at t = %.4g s (exit %d)"
            % (n, s.get("guard"), s["time"], p.returncode))
    t.check(os.path.isfile(os.path.join(out, "checkpoint.h5")), "a checkpoint from before the failure exists")
    stop_step = s["steps"]

    _, p = t.run(gas, args=common + ["-dem_dt_factor", "0.1", "-restart", os.path.join(out, "checkpoint.h5")], outdir=out, nprocs=n, clean=False)
    s = t.summary(out)
    t.check("Restart with a new time step" in p.stdout, "the restart says it changes the time step")
    t.check(s["status"] == "ok" and abs(s["time"] - 0.01) < s["dt"], "continued at dt = t_cr / 10 to t = %.6g s: status %s" % (s["time"], s["status"]))
    t.check(s["guard_figures"]["energy_growth_max"] < 0.01, "energy growth after the rescue %.2e (limit 1e-2)" % s["guard_figures"]["energy_growth_max"])
    t.check(s["particles"] == s["particles_inserted"] == 3000 and s["particles_lost"] == 0,
            "particles: %d present, %d inserted, %d lost" % (s["particles"], s["particles_inserted"], s["particles_lost"]))
    m = t.table(os.path.join(out, "monitor.csv"))
    steps = m["step"]
    t.check(np.all(np.diff(steps) > 0), "monitor.csv: steps strictly increasing across the rescue (the failed run's rows after the checkpoint "
            "dropped; it had reached step %d)" % stop_step)
    t.check(np.all(np.diff(m["time"]) > 0), "monitor.csv: time strictly increasing, last %.6g s" % m["time"][-1])

# what a restart may not change: the physics and the layout of the saved state
ckpt = os.path.join("rescue_1", "checkpoint.h5")
for args, option in ((["-dem_kn", "900"], "-dem_kn"), (["-particle_density", "2600"], "-particle_density"), (["-dem_e", "0.8"], "-dem_e"),
                     (["-grid_nx", "7"], "-grid_nx"), (["-domain_lx", "0.021"], "-domain_lx")):
    _, p = t.run(gas, args=common + args + ["-restart", ckpt], outdir="refused", expect_fail=True)
    text = p.stdout + p.stderr
    t.check(p.returncode == 2 and option in text and "cannot change on a restart" in text and "Traceback" not in text,
            "restart with %s: exit %d, %s" % (" ".join(args), p.returncode, next((l for l in text.splitlines() if "error" in l), "")[:160]))

# A coupled run whose gas step is too long for its gas (-couple_substeps 2, Courant limit 1 for 20 gas steps): continued
# from its checkpoint with one DEM step per gas step, it runs on with the Courant number below 1.
jetted = t.example("jetted_bed_2d.opts")
coupled = ["-guard_courant", "1", "-guard_courant_steps", "20", "-checkpoint_interval", "0.0002", "-t_final", "0.004"]
_, p = t.run(jetted, args=coupled + ["-couple_substeps", "2"], outdir="rescue_coupled", expect_fail=True)
s = t.summary("rescue_coupled")
t.check(s["status"] == "stopped" and s["guard"] == "courant", "coupled, -couple_substeps 2: stopped by guard '%s' at t = %.4g s" % (s.get("guard"), s["time"]))
_, p = t.run(jetted, args=coupled + ["-couple_substeps", "1", "-restart", "rescue_coupled/checkpoint.h5"], outdir="rescue_coupled", clean=False)
s = t.summary("rescue_coupled")
t.check("Restart with -couple_substeps 1" in p.stdout and s["status"] == "ok" and s["guard_figures"]["courant_max"] < 1,
        "continued with -couple_substeps 1 to t = %.4g s: status %s, largest Courant number %.3f" % (s["time"], s["status"], s["guard_figures"]["courant_max"]))
t.check(s["particles"] == s["particles_inserted"] == 900, "coupled rescue: %d of %d particles" % (s["particles"], s["particles_inserted"]))
