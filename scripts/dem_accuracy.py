#!/usr/bin/env python3
"""Accuracy of the DEM time integration against the analytic linear spring-dashpot, as a function of dt / t_cr:
restitution and contact duration of a head-on collision (examples/dem/head_on.opts) and the apex error of a
bouncing particle (examples/dem/bounce_e100.opts, bounce_e090.opts). The worst case over 8 contact phases (the
instant a contact starts within a step) is reported. Prints markdown tables for docs/dem.md.

example:
  scripts/dem_accuracy.py                  # build/fluidbed
  scripts/dem_accuracy.py path/to/fluidbed"""
import argparse
import math
import os
import subprocess
import tempfile

import numpy as np

from fluidbed_tools import reference
from fluidbed_tools.run import EXE, ROOT, command

ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1],
                             formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("exe", nargs="?", default=EXE, help="the fluidbed executable (default $FLUIDBED_EXE, else build/fluidbed)")
EXE = os.path.abspath(ap.parse_args().exe)
FACTORS = (0.1, 0.05, 0.02, 0.01)
PHASES = 8
d, rho, kn = 1.2e-3, 1000.0, 800.0
m = rho * math.pi / 6 * d ** 3


def run(opts, args, tmp):
    out = os.path.join(tmp, "run")
    subprocess.run(command(["-options_file", os.path.join(ROOT, "examples", "dem", opts), "-output_dir", out, "-progress_interval", "0"]
                           + list(args), 1, EXE), check=True, capture_output=True)
    data = np.genfromtxt(os.path.join(out, "track.csv"), delimiter=",", names=True)
    return data


def head_on(e, f, phase, tmp):
    gap = 0.8e-3 + phase / PHASES * 0.5 * f * reference.contact_time(kn, e, m / 2)  # shifts where the contact starts
    args = ["-dem_e", e, "-dem_dt_factor", f, "-insert_positions", "%.12g,0.005,0.005,%.12g,0.005,0.005" % (0.005 - 0.6e-3 - gap / 2, 0.005 + 0.6e-3 + gap / 2)]
    tr = run("head_on.opts", args, tmp)
    a, b = tr["id"] == 0, tr["id"] == 1
    v0, v1 = tr["vx"][a], tr["vx"][b]
    ov = d - np.abs(tr["x"][b] - tr["x"][a])
    t = tr["time"][a]
    k_in = np.argmax(ov > 0)
    k_out = k_in + np.argmax(ov[k_in:] <= 0)
    t_in = t[k_in - 1] + (t[k_in] - t[k_in - 1]) * (-ov[k_in - 1]) / (ov[k_in] - ov[k_in - 1])
    t_out = t[k_out - 1] + (t[k_out] - t[k_out - 1]) * ov[k_out - 1] / (ov[k_out - 1] - ov[k_out])
    e_meas = (v1[-1] - v0[-1]) / (v0[0] - v1[0])
    return abs(e_meas / e - 1), abs((t_out - t_in) / reference.contact_time(kn, e, m / 2) - 1)


def bounce(e, f, phase, n, tmp):
    h0 = 0.01 * (1 + 2e-4 * phase)
    tfinal = 2.0 if e == 1.0 else 0.5
    tr = run("bounce_e100.opts", ["-dem_e", e, "-dem_dt_factor", f, "-t_final", tfinal, "-monitor_track_every", 1 if e < 1 else 10,
                                  "-insert_positions", "0.005,%.12g,0.005" % (h0 + d / 2)], tmp)
    gap = tr["y"] - d / 2
    vy = tr["vy"]
    apex = gap[1:][(vy[:-1] > 0) & (vy[1:] <= 0)][:n]
    ref = reference.bounce_apexes(h0, n, kn, e, m, 9.81)
    return max(abs(a / r - 1) for a, r in zip(apex, ref))


with tempfile.TemporaryDirectory() as tmp:
    print("| dt / t_cr | restitution error, e = 0.5 | e = 0.9 | contact duration error, e = 0.5 | e = 1 |")
    print("|---|---|---|---|---|")
    for f in FACTORS:
        r05 = [head_on(0.5, f, p, tmp) for p in range(PHASES)]
        r09 = [head_on(0.9, f, p, tmp) for p in range(PHASES)]
        r10 = [head_on(1.0, f, p, tmp) for p in range(PHASES)]
        print("| %g | %.3f%% | %.3f%% | %.3f%% | %.3f%% |" % (f, 100 * max(x[0] for x in r05), 100 * max(x[0] for x in r09),
                                                             100 * max(x[1] for x in r05), 100 * max(x[1] for x in r10)))
    print()
    print("| dt / t_cr | largest error of the first 5 apexes, e = 0.9 | of the first 20 apexes, e = 1 |")
    print("|---|---|---|")
    for f in FACTORS + (0.025,):
        b9 = [bounce(0.9, f, p, 5, tmp) for p in range(PHASES)]
        b1 = [bounce(1.0, f, p, 20, tmp) for p in range(PHASES)] if f >= 0.02 else [float("nan")]
        print("| %g | %.3f%% | %s |" % (f, 100 * max(b9), "%.3f%%" % (100 * max(b1)) if b1[0] == b1[0] else "not run"))
