"""scripts/snapshot_pressure_drop.py on snapshots with a known answer: a gas pressure falling linearly with height,
p = p0 - G y, in 3D cells, gives a drop of G L over the bed's height L less the gas column rho_g g L, exactly (the
linear continuation to the distributor and the top is exact for a linear profile), with no rms over snapshots that
all hold it; the buoyant weight per area is that of the snapshot's particles."""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

from fluidbed_tools import testing as t

run = os.path.abspath("pdrop_run")
os.makedirs(run, exist_ok=True)
lx, ly, lz, rho_g, rho_p, G = 0.044, 0.16, 0.01, 1.205, 1000.0, 1200.0
with open(os.path.join(run, "command.txt"), "w") as f:
    f.write("fluidbed -domain_lx %g -domain_ly %g -domain_lz %g -fluid_rho %g -particle_density %g\n" % (lx, ly, lz, rho_g, rho_p))
ny = 32
y = (np.arange(ny) + 0.5) * ly / ny
d = np.full(500, 1.2e-3)
for k in range(6):
    p = np.empty((2, ny, 12))
    p[:] = (2000.0 - G * y)[None, :, None]
    with h5py.File(os.path.join(run, "snapshot_%05d.h5" % k), "w") as f:
        f.attrs["time"] = 0.5 + 0.2 * k
        f["fluid/pressure"] = p
        f["particles/diameter"] = d
        f["particles/position"] = np.zeros((len(d), 3))
out = run + ".json"
p = subprocess.run([sys.executable, os.path.join(t.SRC, "scripts", "snapshot_pressure_drop.py"), run, "--start", "1.0", "--json", out],
                   capture_output=True, text=True, timeout=120)
print(p.stdout, p.stderr)
t.check(p.returncode == 0, "snapshot_pressure_drop.py ran (exit %d)" % p.returncode)
r = json.load(open(out))
expect = G * ly - rho_g * 9.81 * ly
t.check(r["snapshots"] == 3, "the snapshots at or after 1.0 s: %d (of 6)" % r["snapshots"])
t.check(abs(r["mean_Pa"] - expect) < 1e-9 * expect and r["rms_Pa"] < 1e-9 * expect,
        "drop %.6f Pa (rms %.2g), expected G L - rho_g g L = %.6f Pa" % (r["mean_Pa"], r["rms_Pa"], expect))
w = rho_p * np.pi / 6 * np.sum(d ** 3) * 9.81 * (1 - rho_g / rho_p) / (lx * lz)
t.check(abs(r["buoyant_weight_per_area_Pa"] - w) < 1e-9 * w, "buoyant weight / area %.4f Pa, expected %.4f" % (r["buoyant_weight_per_area_Pa"], w))
