"""Coupling verification 6: the jetted two-grid bed (the default scene, examples/jetted_bed_2d.opts) on 1, 2 and 4
ranks, 0.15 s of bed time.

The DEM is bitwise rank-independent; the gas is not (the pressure solve's reductions and preconditioner depend on
the partition, at the level of its tolerance, 1e-8), and a bubbling bed amplifies such differences exponentially.
So the runs must agree:
- exactly in the particle count at every monitor row (nothing lost, nothing through the outlet),
- closely while the differences are still round-off (the beads are still falling onto the distributor): the bed's
  potential energy at t = 0.005 s within 1e-9,
- statistically afterwards: the mean centre-of-mass height over 0.05-0.15 s (the bed bubbling) within twice the
  larger standard deviation of that height over the window, and within 5%,
and each run balances drag action and reaction to round-off."""
import os

import numpy as np

from fluidbed_tools import testing as t

runs = [(1, None), (2, "2,1"), (4, "2,2")]
res = {}
for n, grid in runs:
    args = ["-t_final", 0.15, "-output_particles", 0, "-fluid_output_cells", 0] + (["-pgrid_processors", grid] if grid else [])
    out, _ = t.run(t.example("jetted_bed_2d.opts"), args=args, nprocs=n, outdir="jetted_%d" % n)
    mon = t.table(os.path.join(out, "monitor.csv"))
    s = t.summary(out)
    res[n] = (mon, s)
    count = mon["particles"]
    t.check(np.all(count == count[0]) and count[0] == 900, "%d ranks: 900 particles at every row (min %d, max %d)" % (n, count.min(), count.max()))
    scale = np.max(np.abs(mon["drag_particles_y"]))
    bal = np.max(np.abs(mon["drag_particles_y"] + mon["drag_gas_y"]) + np.abs(mon["drag_particles_x"] + mon["drag_gas_x"])) / scale
    t.check(bal < 1e-10, "%d ranks: drag on particles + drag on gas = %.1e of the largest drag (limit 1e-10)" % (n, bal))

mon1 = res[1][0]
mass = 900 * 2500 * np.pi / 6 * 1e-9  # kg: 900 beads of 1 mm, 2500 kg/m^3
height = lambda mon: mon["pe_grav"] / (mass * 9.81)
win = (mon1["time"] >= 0.05) & (mon1["time"] <= 0.1500001)
h1 = height(mon1)[win]
early = np.argmin(np.abs(mon1["time"] - 0.005))
for n, grid in runs[1:]:
    mon = res[n][0]
    t.check(len(mon["time"]) == len(mon1["time"]) and np.allclose(mon["time"], mon1["time"], rtol=0, atol=1e-12), "%d ranks: same monitor times" % n)
    d = abs(mon["pe_grav"][early] / mon1["pe_grav"][early] - 1)
    t.check(d < 1e-9, "%d ranks: potential energy at t = %.3f s within %.1e of 1 rank (limit 1e-9)" % (n, mon1["time"][early], d))
    hn = height(mon)[win]
    diff, spread = abs(hn.mean() - h1.mean()), 2 * max(hn.std(), h1.std())
    t.check(diff <= spread and diff <= 0.05 * h1.mean(),
            "%d ranks: mean centre-of-mass height %.3f mm vs %.3f mm on 1 rank (difference %.3f mm, limits %.3f mm = 2 std and 5%%)"
            % (n, 1e3 * hn.mean(), 1e3 * h1.mean(), 1e3 * diff, 1e3 * spread))
