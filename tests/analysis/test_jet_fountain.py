"""scripts/jet_fountain.py (fountain height and jet velocity of a time-averaged jetting bed) on inputs with known
answers, no runs:

- a column whose solid fraction falls linearly with height crosses each threshold where the line does (1e-12);
- a column that never reaches a threshold gives NaN; one whose top cell reaches it gives the top cell centre;
- x picks the particle-grid column holding it, clamped to the grid;
- the script on a hand-built analysis.h5 (3D, two cells deep, a fountain only in the jet column) reports the
  crossing of that column and its largest upward velocity, not those of the bed beside it."""
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fbtest as t

try:
    import h5py
    import numpy as np
except ImportError as e:
    print("SKIP: %s (h5py and numpy are dependencies: apt-get install python3-h5py python3-numpy)" % e)
    sys.exit(0)
sys.path.insert(0, os.path.join(t.SRC, "scripts"))
import jet_fountain as jf

h = 0.004
y = (np.arange(40) + 0.5) * h
line = np.clip(0.6 - 5.0 * (y - 0.02), 0.0, 0.6)  # 0.6 up to 20 mm, then falls by 0.02 per mm
for thr in (0.5, 0.1, 0.05, 0.02):
    exact = 0.02 + (0.6 - thr) / 5.0
    got = jf.fountain_height(y, line, thr)
    t.check(abs(got - exact) < 1e-12, "linear column: threshold %.2f crossed at %.6f m (exact %.6f m)" % (thr, got, exact))
t.check(math.isnan(jf.fountain_height(y, 0.01 * np.ones_like(y), 0.05)), "a column below the threshold everywhere gives NaN")
t.check(jf.fountain_height(y, 0.3 * np.ones_like(y), 0.05) == y[-1], "a column full to the top gives the top cell centre")
t.check(jf.column_index(0.0, 0.002, 10, 0.0105) == 5 and jf.column_index(0.0, 0.002, 10, -1.0) == 0
        and jf.column_index(0.0, 0.002, 10, 1.0) == 9, "x picks its column, clamped to the grid")

# A 3D analysis.h5: 9 columns, 40 layers, 2 cells deep; the bed is 20 mm high everywhere, the jet column (x of the
# middle, column 4) carries the linear fountain and particles rising at 0.2 m/s, 0.9 m/s in the layer at 30 mm;
# column 2 had no particle (NaN velocity) and must not disturb the jet column.
nx, ny, nz = 9, 40, 2
sf = np.where(y[None, :, None] < 0.02, 0.6, 0.0) * np.ones((nz, ny, nx))
sf[:, :, 4] = line
vel = np.zeros((nz, ny, nx, 3))
vel[:, :, 4, 1] = 0.2
k30 = int(np.argmin(np.abs(y - 0.030)))
vel[:, k30, 4, 1] = 0.9
vel[:, :, 2, 1] = np.nan  # column 2: no particle came (NaN), must not disturb the jet column
os.makedirs("jet_fountain_run", exist_ok=True)
with h5py.File("jet_fountain_run/analysis.h5", "w") as f:
    f["grid/origin"] = np.zeros(3)
    f["grid/spacing"] = np.array([0.005, h, 0.002])
    f["grid/cells"] = np.array([nx, ny, nz])
    f["fields/solid_fraction"] = sf
    f["fields/velocity"] = vel
    f["measures/window_start"] = [1.0]
    f["measures/window_end"] = [2.0]
    f["measures/samples"] = [1000]
    f["measures/expanded_bed_height_cutoff"] = [0.02]
p = subprocess.run([sys.executable, os.path.join(t.SRC, "scripts", "jet_fountain.py"), "jet_fountain_run", "--thresholds", "0.1,0.02",
                    "--json", "jet_fountain_run/jet.json"], capture_output=True, text=True, timeout=120)
print(p.stdout, p.stderr)
t.check(p.returncode == 0, "jet_fountain.py exits 0")
r = json.load(open("jet_fountain_run/jet.json"))
t.check(r["column"] == 4, "the jet column is the middle one (column %d)" % r["column"])
t.check(abs(r["fountain_height_m"]["0.1"] - 0.12) < 1e-12 and abs(r["fountain_height_m"]["0.02"] - 0.136) < 1e-12,
        "fountain heights %.4f and %.4f m at 0.1 and 0.02 (exact 0.12 and 0.136)" % (r["fountain_height_m"]["0.1"], r["fountain_height_m"]["0.02"]))
t.check(r["jet_max_velocity_y_m_s"] == 0.9 and abs(r["jet_max_velocity_y_height_m"] - y[k30]) < 1e-15,
        "largest upward velocity of the jet column 0.9 m/s at %.1f mm" % (1e3 * r["jet_max_velocity_y_height_m"]))
