"""Verification 4: a sphere launched without spin on a rough wall slides, spins up and rolls. Rigid-body
mechanics: the slip stops at t = 2 v0 / (7 mu g) and the sphere then rolls at 5/7 v0 (omega r = v). Both within 2%."""
import os

import numpy as np

from fluidbed_tools import testing as t

out, _ = t.run(t.example("dem/sliding_sphere.opts"), outdir="sliding_sphere")
tr = t.table(os.path.join(out, "track.csv"))
v0, mu, g, r = 0.5, 0.3, 9.81, 1e-3
time, vx, wz = tr["time"], tr["vx"], tr["wz"]
slip = vx + wz * r  # contact-point velocity on the floor (omega_z < 0 when rolling to +x)
t_roll = 2 * v0 / (7 * mu * g)
k = np.argmax(slip < 1e-3 * v0)
t.check(slip[k] < 1e-3 * v0, "the slip stopped")
t_meas = time[k - 1] + (time[k] - time[k - 1]) * (slip[k - 1] - 1e-3 * v0) / (slip[k - 1] - slip[k])
t.check(t.rel(t_meas, t_roll) < 0.02, "rolling from t = %.5f s, analytic %.5f s, error %.3f%% (limit 2%%)" % (t_meas, t_roll, 100 * t.rel(t_meas, t_roll)))
# during sliding the deceleration is mu g
early = (time > 0.1 * t_roll) & (time < 0.8 * t_roll)
decel = -np.polyfit(time[early], vx[early], 1)[0]
t.check(t.rel(decel, mu * g) < 0.02, "sliding deceleration %.4f m/s^2, mu g = %.4f m/s^2" % (decel, mu * g))
late = time > 1.5 * t_roll
v_final = vx[late].mean()
t.check(t.rel(v_final, 5 / 7 * v0) < 0.02, "rolling speed %.5f m/s, 5/7 v0 = %.5f m/s, error %.3f%% (limit 2%%)"
        % (v_final, 5 / 7 * v0, 100 * t.rel(v_final, 5 / 7 * v0)))
t.check(np.max(np.abs(slip[late])) < 0.01 * v0, "rolling without slip: |v + omega r| <= %.2e m/s" % np.max(np.abs(slip[late])))
