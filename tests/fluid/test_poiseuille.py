"""Verification 1: plane Poiseuille flow between no-slip walls, periodic along the flow, driven by a uniform
momentum source f (examples/fluid/poiseuille.opts). Steady profile v(x) = f x (W - x) / (2 mu) within 1% of its
maximum on 16, 32 and 64 cells across; the error falls as h^2 (fitted order 1.9..2.1). The same channel in 3D
with a periodic depth (the pseudo-2D option) gives the 2D profile."""
import numpy as np

from fluidbed_tools import reference
from fluidbed_tools import testing as t
import gas

W, mu, f = 1e-3, 1.8e-5, 14.4
vmax = reference.poiseuille_velocity(W / 2, W, mu, f)


def profile_error(out):
    c = gas.cells(out)
    x, v = c["x"], c["ufy"]  # v on the y-faces sits at the cell centres in x
    exact = reference.poiseuille_velocity(x, W, mu, f)
    return np.max(np.abs(v - exact)) / vmax, c


errs, hs = [], []
for n in (16, 32, 64):
    out, _ = t.run(t.example("fluid/poiseuille.opts"), args=["-grid_nx", n], outdir="poiseuille_%d" % n)
    err, c = profile_error(out)
    s = t.summary(out)["fluid"]
    t.check(err < 0.01, "%d cells: largest error of the steady profile %.3e of v_max = %.3g m/s (limit 1%%)" % (n, err, vmax))
    t.check(np.max(np.abs(c["ufx"])) < 1e-12 * vmax, "%d cells: no cross flow (max |u| %.1e m/s)" % (n, np.max(np.abs(c["ufx"]))))
    errs.append(err)
    hs.append(W / n)
order = np.polyfit(np.log(hs), np.log(errs), 1)[0]
t.check(1.9 < order < 2.1, "error falls as h^%.3f over 16, 32, 64 cells (expected 2)" % order)

out, _ = t.run(t.example("fluid/poiseuille.opts"), args=["-domain_dim", 3, "-domain_periodic_z", "-grid_nz", 4], outdir="poiseuille_3d")
err3, c3 = profile_error(out)
t.check(abs(err3 - errs[0]) < 1e-6 and err3 < 0.01,
        "3D, periodic depth, 16 x 4 x 4 cells: profile error %.3e (2D: %.3e); max |w| %.1e m/s" % (err3, errs[0], np.max(np.abs(c3["ufz"]))))
