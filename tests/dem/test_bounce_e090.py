"""Verification 2 (seed fig. 2.4): with e = 0.9 the first five rebound apexes are within 1% of the analytic
sequence, which is e^(2n) h0 corrected for gravity acting during each contact (finite contact time, overlap)."""
import math
import os

from fluidbed_tools import reference
from fluidbed_tools import testing as t

out, _ = t.run(t.example("dem/bounce_e090.opts"), outdir="bounce_e090")
tr = t.table(os.path.join(out, "track.csv"))
d, rho, kn, e, h0, g = 1.2e-3, 1000.0, 800.0, 0.9, 0.01, 9.81
m = rho * math.pi / 6 * d ** 3
gap = tr["y"] - d / 2
vy = tr["vy"]
apex = gap[1:][(vy[:-1] > 0) & (vy[1:] <= 0)]
ref = reference.bounce_apexes(h0, 5, kn, e, m, g)
t.check(len(apex) >= 5, "%d rebounds recorded (need 5)" % len(apex))
for n in range(5):
    naive = e ** (2 * (n + 1)) * h0
    t.check(t.rel(apex[n], ref[n]) < 0.01,
            "apex %d: %.5f mm, analytic %.5f mm (e^2n h0 = %.5f mm), error %.3f%% (limit 1%%)"
            % (n + 1, apex[n] * 1e3, ref[n] * 1e3, naive * 1e3, 100 * t.rel(apex[n], ref[n])))
