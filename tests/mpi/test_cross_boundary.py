"""Verification 6: a pair colliding across a rank boundary, and across a periodic boundary split between ranks,
gets the same force at every step as on one rank."""
import os

import numpy as np

from fluidbed_tools import testing as t

base = ["-domain_lx", 0.024, "-domain_ly", 0.012, "-domain_lz", 0.012, "-gravity", "0,0,0", "-dem_mu", 0.3, "-dem_e", 0.7,
        "-particle_diameter", 1.2e-3, "-insert_type", "list", "-t_final", 5e-4, "-monitor_track_ids", "0,1"]
cases = {
    # particle 0 left of x = 12 mm (rank 0), particle 1 right of it (rank 1), an oblique spinning collision
    "rank boundary": ["-insert_positions", "0.0113,0.006,0.006,0.0127,0.0062,0.0059", "-insert_velocities", "0.5,0,0.05,-0.5,0.02,0",
                      "-insert_omegas", "0,0,300,0,100,0"],
    # the same pair across the periodic face x = 0 = 24 mm
    "periodic boundary": ["-domain_periodic_x", "-insert_positions", "0.0233,0.006,0.006,0.0007,0.0062,0.0059",
                          "-insert_velocities", "0.5,0,0.05,-0.5,0.02,0", "-insert_omegas", "0,0,300,0,100,0"],
}
for name, args in cases.items():
    tracks = {}
    for n in (1, 2):
        out, _ = t.run(None, args=base + args + (["-pgrid_processors", "2,1,1"] if n == 2 else []), nprocs=n, outdir="cross_%s_%d" % (name.split()[0], n))
        tracks[n] = t.table(os.path.join(out, "track.csv"))
    one, two = tracks[1], tracks[2]
    fmag = np.hypot(one["fx"], one["fy"])
    t.check(fmag.max() > 1e-4, "%s: the pair collided (peak force %.3e N)" % (name, fmag.max()))
    same = all(np.array_equal(one[c], two[c]) for c in ("fx", "fy", "fz", "x", "vx", "wz"))
    diff = max(np.max(np.abs(one[c] - two[c])) for c in ("fx", "fy", "fz"))
    t.check(same, "%s: force at every step identical on 1 and 2 ranks (largest difference %.1e N)" % (name, diff))
