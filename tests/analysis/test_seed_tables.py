"""scripts/seed_tables.py sets a run's averaged measures beside the seed's Tables 3.4-3.6: a run of the single jet at
1.6 U_mf whose analysis.h5 holds a bed 10% above the seed's 60.3 mm (the cut-off method the seed used at 1.6 U_mf,
Table 3.4) and the seed's own Table 3.6 inputs is reported as +10.0% and 0.0%, and its circulation of eq. 3.6 equals the
seed's inputs' rho_p eps_sb f_neg |v_neg| A_d (computed here by hand: 2500 x 0.518 x 0.549 x 0.0328 x 0.0564 x 0.00495
kg/s); the single jet at 3 U_mf takes its height from the expanded volume (the seed's 88.5 mm) and the double jet from
the cut-off (Table 3.5); the 3 U_mf single jet's snapshots in the averaging window (two of three) give the expanded
volume per snapshot, the share of cells with void fraction below 1 times the domain's height, 62.5 and 80 mm: 71.25 mm
on average, 8.75 mm apart, and eq. 3.7's bulk fraction with it (the same mass over that height); the nine-jet 2D bed is set beside chapter 4's height, bulk fraction and jet height; a run of another scene or one without analysis.h5 ends with exit status 2 and a message. scripts/plot_seed_550.py
draws the 550 um beds of that JSON at a glance and tables them in the seed's order, with the same differences."""
import json
import os
import re
import subprocess
import sys

import h5py
import numpy as np

from fluidbed_tools import testing as t

SCRIPT = os.path.join(t.SRC, "scripts", "seed_tables.py")


def fake_run(path, scene, measures):
    os.makedirs(path, exist_ok=True)
    with open(os.path.join(path, "command.txt"), "w") as f:
        f.write("mpiexec -n 2 fluidbed -options_file /src/examples/%s.opts -output_dir %s\n" % (scene, path))
    with h5py.File(os.path.join(path, "analysis.h5"), "w") as f:
        for k, v in measures.items():
            f.create_dataset("measures/" + k, data=[v])


base = {"samples": 3000, "window_start": 5.0, "window_end": 8.0, "bulk_solid_fraction": 0.40, "bulk_solid_fraction_cutoff": 0.518,
        "fraction_moving_down": 0.549,
        "mean_downward_speed": 0.0328, "pressure_drop": 470.0}
circ = 2500 * 0.518 * 0.549 * 0.0328 * 0.0564 * 0.00495
fake_run("jet1", "spouted_550_jet1_u160", dict(base, expanded_bed_height_volume=0.070, expanded_bed_height_cutoff=0.06633, solid_circulation=circ))
fake_run("jet1_u301", "spouted_550_jet1_u301", dict(base, expanded_bed_height_volume=0.0885, expanded_bed_height_cutoff=0.050, solid_circulation=circ,
                                                     bulk_solid_fraction=0.353))
# jet1_u301's snapshots on a grid of 4 x 10 x 1 cells, 100 mm high: at 6 s the lowest six rows and one cell of the
# seventh hold particles (25 of 40 cells: 62.5 mm), at 7 s the lowest eight rows (80 mm), at 4 s (before the window)
# all of them
with h5py.File(os.path.join("jet1_u301", "analysis.h5"), "a") as f:
    f["grid/cells"], f["grid/spacing"], f["grid/origin"] = [4, 10, 1], [0.01, 0.01, 0.005], [0.0, 0.0, 0.0]
for k, (time, full_rows, extra) in enumerate([(4.0, 10, 0), (6.0, 6, 1), (7.0, 8, 0)]):
    eps = np.ones((1, 10, 4))
    eps[0, :full_rows, :] = 0.5
    if extra:
        eps[0, full_rows, :extra] = 0.99
    with h5py.File(os.path.join("jet1_u301", "snapshot_%05d.h5" % k), "w") as f:
        f.attrs["time"] = time
        f["fluid/void_fraction"] = eps
fake_run("jet2", "spouted_550_jet2_u160", dict(base, expanded_bed_height_volume=0.070, expanded_bed_height_cutoff=0.05822, solid_circulation=circ))


def tables(*args):
    """Runs seed_tables.py and checks it printed its tables."""
    p = subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True)
    print(p.stdout, p.stderr)
    t.check(p.returncode == 0, "the tables of %s were printed (exit %d)" % (" ".join(args), p.returncode))
    return p


p = tables("jet1", "jet2", "jet1_u301", "--json", "tables.json")
t.check("| expanded bed height, cut-off method (mm) | 66.33 | 60.3 | 55.4 | +10.0% |" in p.stdout,
        "the single jet's height at 1.6 U_mf by the cut-off: 66.33 mm against the seed's 60.3 (simulation) and 55.4 (experiment), +10.0%")
t.check("| expanded bed height, expanded-volume method (mm) | 88.5 | 88.5 | - | +0.0% |" in p.stdout,
        "the single jet's height at 3 U_mf by the expanded volume")
t.check("| expanded bed height, cut-off method (mm) | 58.22 | 58.22 | 50.75 | +0.0% |" in p.stdout, "the double jet's height by the cut-off method")
t.check("| bulk solid fraction (eq. 3.7, with the height above) | 0.518 | 0.518 | - | +0.0% |" in p.stdout,
        "Table 3.6's bulk solid fraction beside ours, with the cut-off height at 1.6 U_mf (not the expanded volume's 0.40)")
t.check("| bulk solid fraction (eq. 3.7, with the height above) | 0.353 | 0.353 | - | +0.0% |" in p.stdout,
        "and with the expanded-volume height at 3 U_mf")
t.check("| expanded bed height, expanded volume per snapshot, mean of 2 (mm) | 71.25 | 88.5 | - | -19.5% |" in p.stdout,
        "the 3 U_mf single jet's expanded volume per snapshot: the two snapshots in the window, 62.5 and 80 mm")
t.check("| the same, standard deviation over the snapshots (mm) | 8.75 | - | - | - |" in p.stdout, "and their spread")
bulk = 0.353 * 88.5 / 71.25
t.check("| bulk solid fraction (eq. 3.7) with the per-snapshot height | %.4g | 0.353 |" % bulk in p.stdout,
        "eq. 3.7 with the per-snapshot height: %.4g (the same mass over 71.25 instead of 88.5 mm)" % bulk)
t.check(p.stdout.count("per snapshot") == 1, "no per-snapshot rows for the runs without snapshots")
rows = {r["quantity"]: r for r in json.load(open("tables.json"))[0]["rows"]}
c = rows["solid circulation, eq. 3.6 (g/s)"]
t.check(abs(c["seed_simulation"] - 1e3 * circ) < 1e-9 and abs(c["ours"] - 1e3 * circ) < 1e-9,
        "eq. 3.6 from the seed's Table 3.6: %.4f g/s (by hand %.4f)" % (c["seed_simulation"], 1e3 * circ))

# scripts/plot_seed_550.py, the beds at a glance from that JSON: the seed's order (1.6 U_mf before 3 U_mf), each
# height by the seed's method with its difference, the downward flux f_down x v_down (0.549 x 32.8 mm/s = 18.0 mm/s
# for ours and the seed's alike), the per-snapshot height where the JSON has it; a figure is written; a JSON that is
# not seed_tables.py's ends with exit status 2
SUMMARY = os.path.join(t.SRC, "scripts", "plot_seed_550.py")
p = subprocess.run([sys.executable, SUMMARY, "tables.json", "-o", "summary.png", "--table", "summary.md"], capture_output=True, text=True)
print(p.stdout, p.stderr)
t.check(p.returncode == 0 and os.path.getsize("summary.png") > 10000, "the summary figure was drawn (exit %d)" % p.returncode)
lines = [line for line in open("summary.md") if line.startswith("| ") and "U_mf" in line]
t.check([line.split("|")[1].strip() for line in lines] == ["1 jet, 1.6 U_mf", "2 jets, 1.6 U_mf", "1 jet, 3 U_mf"],
        "the beds in the seed's order: %s" % [line.split("|")[1] for line in lines])
t.check("66.3 / 60.30 / 55.40 (+10%)" in lines[0] and "58.2 / 58.22 / 50.75 (+0%)" in lines[1],
        "the cut-off heights at 1.6 U_mf against the seed's simulation and experiment")
snap = re.search(r"per snapshot ([0-9.]+) \((-?[0-9]+)%\)", lines[2])
t.check("88.5 / 88.50 / - (+0%)" in lines[2] and snap and abs(float(snap.group(1)) - 71.25) <= 0.05 and snap.group(2) == "-19",
        "the 3 U_mf height by the expanded volume, and per snapshot 71.25 mm (-19.5%%): %s" % lines[2])
t.check("| 18.0 / 18.0 (+0%) |" in lines[0], "the downward flux 0.549 x 32.8 mm/s = 18.0 mm/s")
t.check("| %.1f / %.1f (+0%%) |" % (1e3 * circ, 1e3 * circ) in lines[0], "the circulation of eq. 3.6, %.1f g/s" % (1e3 * circ))
json.dump({"rows": []}, open("not_tables.json", "w"))
p = subprocess.run([sys.executable, SUMMARY, "not_tables.json"], capture_output=True, text=True)
t.check(p.returncode == 2 and "error: not_tables.json" in p.stderr and "Traceback" not in p.stderr,
        "a JSON that is not seed_tables.py's: exit %d, %s" % (p.returncode, p.stderr.strip()))

# the nine-jet 2D bed against chapter 4: a bed 10% above the seed's 150 mm, its bulk fraction, the jets' mean height
fake_run("ninejet", "ninejet_2d", dict(samples=3381, window_start=5.0, window_end=8.38, expanded_bed_height_cutoff=0.165,
                                        expanded_bed_height_volume=0.170, bulk_solid_fraction_cutoff=0.479, jet_penetration_height=0.02431,
                                        jet_penetration_height_std=0.004, jet_detachments=900, pressure_drop=1000.0))
p = tables("ninejet")
t.check("| expanded bed height, cut-off method (mm) | 165 | 150 | 174 | +10.0% |" in p.stdout,
        "the nine-jet bed's height against the seed's 150 mm (2D simulation) and 174 mm (experiment)")
t.check("| jet height, first bubble detachment, mean over the jets (mm) | 24.31 | 22.1 | 21.32 | +10.0% |" in p.stdout,
        "the jets' height against the seed's 22.1 mm and the experiment's 21.32 mm")
t.check("| bulk solid fraction (M_p / rho_p A h, the cut-off height) | 0.479 | 0.527 | 0.476 | -9.1% |" in p.stdout,
        "the bulk solid fraction against the seed's 0.527 (2D) and 0.476 (experiment)")

fake_run("muller", "muller_bed_u060", base)
os.makedirs("no_analysis", exist_ok=True)
open(os.path.join("no_analysis", "command.txt"), "w").write("fluidbed -options_file examples/spouted_550_jet1_u160.opts\n")
for run, what in (("muller", "a scene outside the tables"), ("no_analysis", "no analysis.h5")):
    p = subprocess.run([sys.executable, SCRIPT, run], capture_output=True, text=True)
    t.check(p.returncode == 2 and "seed_tables.py:" in p.stderr and "Traceback" not in p.stderr, "%s: exit %d, %s" % (what, p.returncode, p.stderr.strip()))
print("ok")
