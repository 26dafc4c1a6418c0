#!/usr/bin/env python3
"""The bed's pressure drop from a run's snapshots, distributor to top, as docs/validation.md reports it for the Muller
beds: the gas pressure of each snapshot at or after --start averaged over each cell layer (a cross-section), the
layer means continued linearly from the two outer layers to the distributor (y = 0) and to the top face (y = L),
and the gas column's weight rho_g g L taken off. Prints the mean and rms over the snapshots and the buoyant bed
weight per unit area it is compared with (from the particles of the last snapshot, their density and the gas's).
Domain, densities and gravity come from the run's options (command.txt) unless given."""
import argparse
import glob
import json
import os
import sys

import h5py
import numpy as np

from fluidbed_tools import outputs

DEFAULTS = {"-domain_lx": None, "-domain_ly": None, "-domain_lz": None, "-fluid_rho": 1.205, "-particle_density": 2500.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="run directory (fluidbed -output_dir) holding snapshot_*.h5")
    ap.add_argument("--start", type=float, default=1.0, help="first snapshot time in s (default 1.0)")
    ap.add_argument("--gravity", type=float, default=9.81, help="gravity in m/s^2 (default 9.81)")
    ap.add_argument("--json", help="write the figures to this file")
    a = ap.parse_args()
    o = outputs.run_options(a.run, DEFAULTS)
    if not o["-domain_ly"]:
        sys.exit("snapshot_pressure_drop.py: no -domain_ly in %s/command.txt" % a.run)
    L, rho_g = o["-domain_ly"], o["-fluid_rho"]
    times, drops, last = [], [], None
    for path in sorted(glob.glob(os.path.join(a.run, "snapshot_*.h5"))):
        with h5py.File(path, "r") as f:
            t = float(f.attrs["time"])
            if t < a.start - 1e-9 or "fluid/pressure" not in f:
                continue
            p = f["fluid/pressure"][...]
            last = (f["particles/diameter"][...], f["particles/position"][...]) if "particles/diameter" in f else last
        if p.ndim == 2:
            p = p[None]
        layers = p.mean(axis=(0, 2))  # per cell layer along y
        p_bottom = layers[0] - 0.5 * (layers[1] - layers[0])  # half a cell below the first centre
        p_top = layers[-1] + 0.5 * (layers[-1] - layers[-2])
        times.append(t)
        drops.append(p_bottom - p_top - rho_g * a.gravity * L)
    if not drops:
        sys.exit("snapshot_pressure_drop.py: no snapshot with gas pressure at or after t = %g s in %s" % (a.start, a.run))
    drops = np.array(drops)
    out = {"snapshots": len(drops), "from_s": times[0], "to_s": times[-1], "mean_Pa": float(drops.mean()),
           "rms_Pa": float(drops.std())}
    line = "pressure drop distributor -> top minus the gas column, %d snapshots %.3g-%.3g s: mean %.1f Pa, rms %.1f Pa" % (
        len(drops), times[0], times[-1], out["mean_Pa"], out["rms_Pa"])
    if last is not None and o["-domain_lx"] and o["-domain_lz"]:
        d = last[0]
        mass = o["-particle_density"] * np.pi / 6 * np.sum(d ** 3)
        w = mass * a.gravity * (1 - rho_g / o["-particle_density"]) / (o["-domain_lx"] * o["-domain_lz"])
        out.update(particles=int(len(d)), buoyant_weight_per_area_Pa=float(w), fraction_of_weight=float(drops.mean() / w))
        line += "; buoyant weight / area %.1f Pa (%d particles): %.1f%%" % (w, len(d), 100 * drops.mean() / w)
    print(line)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
