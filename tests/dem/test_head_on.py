"""Verification 3 (seed fig. 2.5): two particles collide head on without gravity.

e = 1: kinetic energy after the collision equals that before to 1e-6 (velocity Verlet's error here is
O((dt/t_cr)^3), so this runs at dt = t_cr/200); during contact the error of kinetic + spring energy is bounded and
falls as dt^2 (order fitted over t_cr/10 ... t_cr/80). e = 0.5 and 0.9: measured restitution within 1% (dt = t_cr/50).
Contact duration within 2% of the linear-spring value t_cr (eq. 3.2), at the default dt = t_cr/10."""
import math
import os

import numpy as np

from fluidbed_tools import reference
from fluidbed_tools import testing as t

d, rho, kn = 1.2e-3, 1000.0, 800.0
m = rho * math.pi / 6 * d ** 3


def collide(name, args):
    out, _ = t.run(t.example("dem/head_on.opts"), args=args, outdir=name)
    tr = t.table(os.path.join(out, "track.csv"))
    a, b = tr["id"] == 0, tr["id"] == 1
    time = tr["time"][a]
    x0, x1 = tr["x"][a], tr["x"][b]
    v0, v1 = tr["vx"][a], tr["vx"][b]
    overlap = d - np.abs(x1 - x0)
    ke = 0.5 * m * (v0 ** 2 + v1 ** 2)
    spring = 0.5 * kn * np.maximum(overlap, 0.0) ** 2
    return time, overlap, ke, spring, v0, v1


# energy after the collision, e = 1
_, ov, ke, sp, _, _ = collide("head_on_e100_fine", ["-dem_dt_factor", "0.005"])
t.check(ov[-1] < 0 and ov.max() > 0, "the particles collided and separated")
err_after = abs(ke[-1] - ke[0]) / ke[0]
t.check(err_after < 1e-6, "e = 1, dt = t_cr/200: kinetic energy after / before - 1 = %.2e (limit 1e-6)" % err_after)

# energy during contact falls as dt^2: the largest error depends on where the contact starts within a step, so
# fit the order over four time steps
errs = []
factors = (0.1, 0.05, 0.025, 0.0125)
for f in factors:
    _, ov, ke, sp, _, _ = collide("head_on_e100_%g" % f, ["-dem_dt_factor", f])
    errs.append(np.max(np.abs(ke + sp - ke[0])) / ke[0])
order = np.polyfit(np.log(factors), np.log(errs), 1)[0]
print("largest error of kinetic + spring energy during contact at dt = t_cr x", factors, ":", " ".join("%.3e" % e for e in errs))
t.check(errs[0] < 0.05, "error bounded: %.3e at t_cr/10" % errs[0])
t.check(1.6 < order < 2.4, "it falls as dt^%.2f (expected 2)" % order)

# restitution
for e in (0.5, 0.9):
    _, ov, _, _, v0, v1 = collide("head_on_e%03d" % int(100 * e), ["-dem_e", e, "-dem_dt_factor", "0.02"])
    e_meas = (v1[-1] - v0[-1]) / (v0[0] - v1[0])
    t.check(t.rel(e_meas, e) < 0.01, "e = %.1f at dt = t_cr/50: measured restitution %.5f, error %.3f%% (limit 1%%)" % (e, e_meas, 100 * t.rel(e_meas, e)))

# contact duration at the default time step (crossings of zero overlap interpolated between steps)
for e in (1.0, 0.5):
    time, ov, _, _, _, _ = collide("head_on_duration_e%03d" % int(100 * e), ["-dem_e", e])
    k_in = np.argmax(ov > 0)
    k_out = k_in + np.argmax(ov[k_in:] <= 0)
    t_in = time[k_in - 1] + (time[k_in] - time[k_in - 1]) * (-ov[k_in - 1]) / (ov[k_in] - ov[k_in - 1])
    t_out = time[k_out - 1] + (time[k_out] - time[k_out - 1]) * ov[k_out - 1] / (ov[k_out - 1] - ov[k_out])
    tc = reference.contact_time(kn, e, m / 2)
    t.check(t.rel(t_out - t_in, tc) < 0.02, "e = %.1f, dt = t_cr/10: contact lasted %.4e s, analytic %.4e s, error %.3f%% (limit 2%%)"
            % (e, t_out - t_in, tc, 100 * t.rel(t_out - t_in, tc)))
