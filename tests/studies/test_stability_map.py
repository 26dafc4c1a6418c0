"""The stability map's short version (scripts/stability_map.py --ci): one stable and one unstable point per method on
the 2D pseudo-bed of the seed's 750 um jet, 3 ms of bed from the lattice. The two grids on the seed's fine gas grid
(0.43 d wide cells) at dt = t_cr/10 finish; at dt = 1.5 t_cr a guard stops them. The single grid finishes on 3 d cells
and is stopped by the void-fraction guard on the 0.43 d cells, whose particle centres overfill them (seed chapter 5).
A second call reuses every finished point (the study resumes) and writes the same table."""
import csv
import os
import subprocess
import sys

from fluidbed_tools import testing as t

script = os.path.join(t.SRC, "scripts", "stability_map.py")
out = os.path.abspath("stability_ci")
table = os.path.join(out, "map.csv")
env = dict(os.environ, FLUIDBED_EXE=t.EXE)
cmd = [sys.executable, script, "--ci", "--out", out, "--csv", table, "--jobs", "2"]
p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
print(p.stdout[-3000:], p.stderr[-3000:])
t.check(p.returncode == 0, "stability_map.py --ci ran (exit %d)" % p.returncode)
rows = {(r["method"], float(r["cell_d"]), float(r["dt_factor"])): r for r in csv.DictReader(open(table))}
expect = {("two", 0.43, 0.1): ("stable", ""), ("two", 0.43, 1.5): ("unstable", None), ("single", 3.0, 0.1): ("stable", ""),
          ("single", 0.43, 0.1): ("unstable", "void_fraction")}
for key, (cls, guard) in expect.items():
    r = rows.get(key)
    t.check(r is not None, "point %s %g d dt %g in the table" % key)
    t.check(r["class"] == cls, "%s grid, %g d cells, dt %g t_cr: %s (%s) %s" % (key + (r["class"], r["status"], r["why"])))
    if cls == "unstable":
        t.check(r["exit_status"] not in ("0", "1") and r["guard"] and (guard is None or r["guard"] == guard),
                "  stopped by guard '%s' at t = %s s, exit status %s" % (r["guard"], r["guard_time"], r["exit_status"]))
    else:
        t.check(r["exit_status"] == "0" and abs(float(r["t_end"]) - 0.003) < 1e-5 and float(r["dp_over_weight"]) > 0,
                "  finished at t = %s s, pressure drop %s of the bed weight" % (r["t_end"], r["dp_over_weight"]))
first = open(table).read()
p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
t.check(p.returncode == 0 and p.stdout.count("(reused)") == 4, "a second call reuses the 4 finished points")
again = open(table).read()
t.check(first == again, "and writes the same table")
