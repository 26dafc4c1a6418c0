"""Verification 5: 5000 particles poured into a box settle. The largest overlap stays below 1% of d, every
particle stays in the box (same ids at the end), and the kinetic energy decays to rest: at the end it is below
1e-4 of its peak during the pour."""
import os

import numpy as np

from fluidbed_tools import testing as t

out, _ = t.run(t.example("dem/settle_box.opts"), outdir="settle_box")
mon = t.table(os.path.join(out, "monitor.csv"))
parts = t.table(os.path.join(out, "particles.csv"))
d, L = 1e-3, (0.02, 0.04, 0.02)

t.check(np.all(mon["particles"] == 5000), "5000 particles in every monitor row")
ids = np.sort(parts["id"].astype(int))
t.check(len(ids) == 5000 and np.array_equal(ids, np.arange(5000)), "the final table holds ids 0..4999 exactly once")
inside = all(np.all((parts[c] >= 0.5 * d * 0.99) & (parts[c] <= L[k] - 0.5 * d * 0.99)) for k, c in enumerate(("x", "y", "z")))
t.check(inside, "every particle inside the box")
t.check(mon["max_overlap_rel"].max() < 0.01, "largest overlap during the run %.3f%% of d (limit 1%%)" % (100 * mon["max_overlap_rel"].max()))
ke = mon["ke_trans"] + mon["ke_rot"]
t.check(ke[-1] < 1e-4 * ke.max(), "kinetic energy at the end %.3e J, %.2e of its peak %.3e J (limit 1e-4)" % (ke[-1], ke[-1] / ke.max(), ke.max()))
height = parts["y"].max() + 0.5 * d
print("settled: bed top %.2f mm, %.2f contacts per particle, solid fraction below the top %.3f"
      % (1e3 * height, mon["contacts_per_particle"][-1], 5000 * np.pi / 6 * d ** 3 / (L[0] * L[2] * height)))
