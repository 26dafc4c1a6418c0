"""scripts/bench_pc_coupled.py on the 2D jetted bed, 40 steps, 1 rank, one repetition, PCs fastpoisson, hypre and pfmg:
PFMG is skipped on the 2D bed (PETSc 3.18's structured matrix is 3D only); each other PC's run converged (iterations
per solve above zero; fastpoisson at most 10), its pressure phase is a share of the step in (0, 1), its particle-steps
per second are 900 particles times the steps over the wall time; the table and the CSV are written; a 750 bed without
--settled is refused with a message naming it."""
import csv
import os
import subprocess
import sys

from fluidbed_tools import testing as t

script = os.path.join(t.SRC, "scripts", "bench_pc_coupled.py")
out = os.path.abspath("bench_pc_coupled")
env = dict(os.environ, FLUIDBED_EXE=t.EXE)
p = subprocess.run([sys.executable, script, "--beds", "jet2d", "--pcs", "fastpoisson,hypre,pfmg", "--ranks", "1", "--repeat", "1",
                    "--steps", "40", "--out", out], capture_output=True, text=True, timeout=300, env=env)
print(p.stdout[-3000:], p.stderr[-2000:])
t.check(p.returncode == 0, "bench_pc_coupled.py ran (exit %d)" % p.returncode)
rows = list(csv.DictReader(open(os.path.join(out, "pc_coupled.csv"))))
t.check([r["pc"] for r in rows] == ["fastpoisson", "hypre"], "rows for fastpoisson and hypre, pfmg skipped in 2D: %s" % [r["pc"] for r in rows])
for r in rows:
    its, share = float(r["its_per_solve"]), float(r["pressure_share"])
    t.check(its > 0 and (r["pc"] != "fastpoisson" or its <= 10) and 0 < share < 1 and int(r["steps"]) == 40 and int(r["particles"]) == 900,
            "%s: %.2f iterations per solve, pressure %.0f%% of the step, 40 steps of 900 particles" % (r["pc"], its, 100 * share))
    step_s = float(r["step_ms"]) / 1e3
    t.check(t.rel(float(r["psteps_per_s_per_core"]), 900 / step_s) < 0.02,
            "%s: %.3g particle-steps/s/core = 900 / %.3g s per step" % (r["pc"], float(r["psteps_per_s_per_core"]), step_s))
table = open(os.path.join(out, "pc_coupled.md")).read()
t.check("| jet2d | 1 | fastpoisson |" in table and "| jet2d | 1 | hypre |" in table, "the markdown table has both rows")
p = subprocess.run([sys.executable, script, "--beds", "coarse750", "--out", out], capture_output=True, text=True, timeout=60, env=env)
t.check(p.returncode != 0 and "--settled" in p.stderr, "a 750 bed without --settled is refused: %s" % p.stderr.strip()[:120])
