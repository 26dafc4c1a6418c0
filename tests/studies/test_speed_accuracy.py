"""The speed-against-accuracy chart's short version (scripts/speed_accuracy.py --ci): the fifth apex of an e = 0.7
bounce against the analytic linear spring-dashpot at dt = 0.2, 0.1 and 0.05 t_cr. A smaller step is not less accurate
(the error falls) and costs more (the cost, wall seconds per simulated second, rises with the steps); at t_cr/10 the
apex is a few percent off (about 3%, the figure that motivates the chart). Run again with --keep-csv, the table keeps a
row of another point and does not repeat its own."""
import csv
import os
import subprocess
import sys

from fluidbed_tools import testing as t

out = os.path.abspath("speed_accuracy_ci")
table = os.path.join(out, "sa.csv")
p = subprocess.run([sys.executable, os.path.join(t.SRC, "scripts", "speed_accuracy.py"), "--ci", "--out", out, "--csv", table],
                   capture_output=True, text=True, env=dict(os.environ, FLUIDBED_EXE=t.EXE), timeout=900)
print(p.stdout[-2000:], p.stderr[-2000:])
t.check(p.returncode == 0, "speed_accuracy.py --ci ran (exit %d)" % p.returncode)
rows = sorted(csv.DictReader(open(table)), key=lambda r: -float(r["dt_factor"]))
f = [float(r["dt_factor"]) for r in rows]
err = [float(r["error"]) for r in rows]
cost = [float(r["cost"]) for r in rows]
steps = [int(r["steps"]) for r in rows]
t.check(f == [0.2, 0.1, 0.05], "three time steps: %s t_cr" % f)
t.check(err[0] > err[1] > err[2], "the error falls with the step: %s" % ", ".join("%.3g%%" % (100 * e) for e in err))
t.check(steps[0] < steps[1] < steps[2] and cost[0] < cost[2],
        "the cost rises with the steps: %s steps, %s wall s per simulated s" % (steps, ", ".join("%.3g" % c for c in cost)))
t.check(0.01 < err[1] < 0.05, "at t_cr/10 the fifth apex is %.2f%% off the analytic value (1-5%%)" % (100 * err[1]))

# a study continued on a fresh machine (--keep-csv): the table's rows of other points stay, its own are not repeated
with open(table) as f:
    header = f.readline().strip().split(",")
kept = dict(rows[0], id="bounce_from_an_earlier_session", error="0.5")
with open(table, "a", newline="") as f:
    csv.DictWriter(f, fieldnames=header).writerow(kept)
p = subprocess.run([sys.executable, os.path.join(t.SRC, "scripts", "speed_accuracy.py"), "--ci", "--out", out, "--csv", table, "--keep-csv"],
                   capture_output=True, text=True, env=dict(os.environ, FLUIDBED_EXE=t.EXE), timeout=900)
t.check(p.returncode == 0, "speed_accuracy.py --ci --keep-csv ran again (exit %d)" % p.returncode)
again = list(csv.DictReader(open(table)))
ids = sorted(r["id"] for r in again)
t.check(len(again) == 4 and ids.count("bounce_from_an_earlier_session") == 1 and len(set(ids)) == 4 and
        [r for r in again if r["id"] == "bounce_from_an_earlier_session"][0]["error"] == "0.5",
        "--keep-csv: the earlier row is kept as it was and the three points are not repeated (%s)" % ", ".join(ids))
