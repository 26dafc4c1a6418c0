"""Verification 1 (seed fig. 2.3): a particle dropped from 10 mm with e = 1 rebounds to 10 mm; the apex after
20 bounces is within 0.5% of 10 mm."""
import os

from fluidbed_tools import testing as t

out, _ = t.run(t.example("dem/bounce_e100.opts"), outdir="bounce_e100")
tr = t.table(os.path.join(out, "track.csv"))
r = 0.6e-3
gap = tr["y"] - r
vy = tr["vy"]
apex = gap[1:][(vy[:-1] > 0) & (vy[1:] <= 0)]
t.check(len(apex) >= 20, "%d rebounds recorded (need 20)" % len(apex))
err = [(a / 0.01 - 1) * 100 for a in apex[:20]]
print("apex error after each bounce (%):", " ".join("%.3f" % e for e in err))
t.check(abs(err[19]) < 0.5, "apex after 20 bounces %.5f mm, %.3f%% from 10 mm (limit 0.5%%)" % (apex[19] * 1e3, err[19]))
t.check(max(abs(e) for e in err) < 0.5, "every apex within 0.5%% (largest %.3f%%)" % max(abs(e) for e in err))
