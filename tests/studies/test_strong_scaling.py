"""scripts/strong_scaling.py straight through mpiexec on 1 and 2 ranks: the 2D jetted bed (900 particles, 33 x 60 gas
cells), 60 steps. The table has its columns; two ranks split x (the bed is shared, not stacked), so particles and gas
cells are balanced (imbalance max / mean below 1.25 and 1.15), each rank has ghosts and halo cells, the 1-rank run sends
no messages and the 2-rank run sends some (between 1 and 300 kB per step: the halos, and the fast Poisson pressure PC's
transposes, which move half the 1980-cell grid four times per application, about 32 kB, at 4-6 applications per step); the counts add up to the scene's particles
and cells. A second call reuses both runs and writes the same particle and cell columns."""
import csv
import os
import subprocess
import sys

from fluidbed_tools import testing as t

script = os.path.join(t.SRC, "scripts", "strong_scaling.py")
out = os.path.abspath("strong_scaling_direct")
cmd = [sys.executable, script, "--scene", t.example("jetted_bed_2d.opts"), "--ranks", "1,2", "--steps", "60", "--out", out, "--exe", t.EXE,
       "--model"]
p = subprocess.run(cmd + ["--fresh"], capture_output=True, text=True, timeout=120)
print(p.stdout[-4000:], p.stderr[-2000:])
t.check(p.returncode == 0, "strong_scaling.py ran on 1 and 2 ranks (exit %d)" % p.returncode)
rows = list(csv.DictReader(open(os.path.join(out, "scaling.csv"))))
need = ["ranks", "process_grid", "step_s", "speedup", "efficiency", "contact_s", "fluid_s", "pressure_s", "ghosts_s", "particles_max",
        "particles_imbalance", "fluid_cells_imbalance", "ghosts_max", "halo_cells_max", "msg_per_step", "msg_bytes_per_step",
        "reductions_per_step", "load_before"]
t.check(all(c in rows[0] for c in need), "the table has the columns " + ", ".join(need))
t.check([r["ranks"] for r in rows] == ["1", "2"], "rows of 1 and 2 ranks")
one, two = rows
f = {k: float(two[k]) for k in need if k not in ("process_grid",)}
t.check(float(one["step_s"]) > 0 and f["step_s"] > 0 and float(one["efficiency"]) == 1.0 and f["efficiency"] > 0,
        "times per step %s and %s s, efficiency on 2 ranks %s" % (one["step_s"], two["step_s"], two["efficiency"]))
t.check(two["process_grid"] == "2x1x1", "two ranks split x: process grid %s" % two["process_grid"])
t.check(1.0 <= f["particles_imbalance"] < 1.25 and 1.0 <= f["fluid_cells_imbalance"] < 1.15,
        "imbalance particles %.3f, cells %.3f" % (f["particles_imbalance"], f["fluid_cells_imbalance"]))
t.check(float(one["ghosts_max"]) == 0 and float(one["halo_cells_max"]) == 0 and f["ghosts_max"] > 0 and f["halo_cells_max"] == 60,
        "ghosts per rank 1: %s, 2: %s; halo cells 2: %s (one column of 60 gas cells)" % (one["ghosts_max"], two["ghosts_max"],
                                                                                          two["halo_cells_max"]))
t.check(float(one["msg_bytes_per_step"]) == 0 and 1e3 < f["msg_bytes_per_step"] < 3e5 and f["msg_per_step"] >= 2,
        "messages per step: 1 rank %s B, 2 ranks %.0f messages, %.0f B" % (one["msg_bytes_per_step"], f["msg_per_step"],
                                                                            f["msg_bytes_per_step"]))
t.check(abs(2 * float(two["particles_mean"]) - float(one["particles_max"])) < 1e-6 and float(one["particles_max"]) == 900 and
        2 * float(two["fluid_cells_mean"]) == float(one["fluid_cells_max"]) == 1980, "the per-rank counts add up to 900 particles, 1980 cells")
t.check(f["reductions_per_step"] > 0, "reductions per step %.1f" % f["reductions_per_step"])
t.check(os.path.isfile(os.path.join(out, "scaling.png")) and os.path.isfile(os.path.join(out, "model.md")), "plot and model written")
first = [(r["particles_max"], r["fluid_cells_max"], r["ghosts_max"]) for r in rows]
p = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
t.check(p.returncode == 0 and p.stdout.count("(reused)") == 2, "a second call reuses both runs")
again = [(r["particles_max"], r["fluid_cells_max"], r["ghosts_max"]) for r in csv.DictReader(open(os.path.join(out, "scaling.csv")))]
t.check(first == again, "and tabulates the same counts")
