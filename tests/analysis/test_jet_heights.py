"""scripts/jet_heights.py (instantaneous jet heights of the snapshots at several void-fraction thresholds) against
known answers and against the run's own jet heights (kernels/jet_height.hpp):

- the inlet columns: those whose centres lie in the slit, or the one holding a narrow slit's centre;
- a hand-built field: a jet column of void fraction 0.9 two cells high over a bed at 0.4 reads the face between
  them (2 cells) at the halfway threshold 0.65; a cell at 0.9 touching the column only by a corner is not joined;
  an inlet cell under the threshold gives 0; a column reaching the top layer gives the grid height;
- a small 2D jetted bed (the coupling test's small bed, one particle deep, a jet at 8 m/s, 0.03 s, a snapshot and an
  averaging sample every 1 ms): at every snapshot the script's height at the run's threshold (0.8) equals the run's
  /series/jet_height of the same step (to 1 um, the snapshots' precision), and the heights rise as the jet enters
  the bed;
- the command line: the table's count is snapshots x jets, its mean at 0.8 the mean of the run's series over the
  snapshots after t = 0 (before the first gas step), --json holds the same; a threshold outside (0, 1) stops with a message."""
import json
import os
import subprocess
import sys

from fluidbed_tools import testing as t

try:
    import h5py
    import numpy as np
except ImportError as e:
    print("SKIP: %s (h5py and numpy are dependencies: apt-get install python3-h5py python3-numpy)" % e)
    sys.exit(0)
sys.path.insert(0, os.path.join(t.SRC, "scripts"))
import jet_heights as jh  # noqa: E402

# known answers: 5 x 4 cells of 1 mm, the jet in column 2
hy = 1e-3
v = np.full((4, 5), 0.4)
v[0:2, 2] = 0.9
v[2, 3] = 0.9  # touches the column's top cell by a corner only
r = jh.region(v, [2], 0.65)
t.check(r.sum() == 2 and not r[2, 3], "region: the two jet cells, not the corner cell (%d cells)" % r.sum())
got = jh.height(v, r, 0.65, hy)
t.check(abs(got - 2e-3) < 1e-15, "a 0.9 column two cells high over 0.4, threshold 0.65: %.6g mm (the face at 2 mm)" % (1e3 * got))
v0 = v.copy()
v0[0, 2] = 0.5
t.check(jh.height(v0, jh.region(v0, [2], 0.65), 0.65, hy) == 0, "an inlet cell under the threshold: height 0")
vt = v.copy()
vt[:, 2] = 0.9
t.check(jh.height(vt, jh.region(vt, [2], 0.65), 0.65, hy) == 4e-3, "a column to the top layer: the grid height")

# against the run's own jet heights
out, _ = t.run(t.example("coupling/small_bed.opts"),
               args=["-domain_dim", 2, "-domain_lz", 1.2e-3, "-grid_nz", 1, "-insert_count", 400, "-inlet_velocity", 0.1,
                     "-inlet_jets", "0.01,0.0066666667,8", "-couple_substeps", 5, "-t_final", 0.03, "-output_interval", 0.001,
                     "-average", "-average_interval", 1e-3], outdir="jet_heights")
with h5py.File(os.path.join(out, "analysis.h5"), "r") as f:
    st, sh = f["series/time"][()], f["series/jet_height"][()][:, 0]
    ny, nx = int(f["grid/cells"][1]), int(f["grid/cells"][0])
    ly, hx = ny * f["grid/spacing"][1], f["grid/spacing"][0]
    slot = f["jets/slots"][()][0]
inlets = jh.inlet_cells(slot, 0.0, hx, nx)
t.check(inlets == [2, 3], "the slit 6.7-13.3 mm holds the centres of columns 2 and 3 of 3.3 mm: %s" % inlets)
t.check(jh.inlet_cells((0.0095, 0.0105), 0.0, hx, nx) == [2], "a slit narrower than a cell: the column holding its centre")
compared, worst, mine = 0, 0.0, []
for k in range(1000):
    path = os.path.join(out, "snapshot_%05d.h5" % k)
    if not os.path.isfile(path):
        break
    with h5py.File(path, "r") as f:
        time, void = f.attrs["time"], f["fluid/void_fraction"][()]
    s = int(np.argmin(np.abs(st - time)))
    if abs(st[s] - time) > 1e-9 or np.isnan(sh[s]):
        continue
    h = jh.height(void, jh.region(void, inlets, 0.8), 0.8, ly / ny)
    worst = max(worst, abs(h - sh[s]))
    mine.append(h)
    compared += 1
t.check(compared >= 25 and worst < 1e-6, "%d snapshots: the script's height at 0.8 against the run's series, largest difference %.2e m" % (compared, worst))
t.check(mine[-1] > 5 * max(mine[5], 1e-3) and mine[-1] > 0.01, "the jet rises into the bed: %.1f mm at 5 ms, %.1f mm at 30 ms" % (1e3 * mine[5], 1e3 * mine[-1]))

# the command line
script = os.path.join(t.SRC, "scripts", "jet_heights.py")
p = subprocess.run([sys.executable, script, out, "--thresholds", "0.8,0.5", "--json", "jets.json"], capture_output=True, text=True, timeout=300)
t.check(p.returncode == 0 and "| 0.8 |" in p.stdout, "jet_heights.py prints its table (exit %d)" % p.returncode)
res = json.load(open("jets.json"))
row = res["thresholds"]["0.8"]
nsnap = res["snapshots"]
t.check(row["count"] == nsnap * 1, "count %d = %d snapshots x 1 jet" % (row["count"], nsnap))
t.check(nsnap == compared and abs(row["mean"] - np.mean(mine)) < 1e-6,
        "mean at 0.8 over %d snapshots (t = 0 left out) %.4f mm, the run's own series there %.4f mm" % (nsnap, 1e3 * row["mean"], 1e3 * np.mean(mine)))
t.check(res["thresholds"]["0.5"]["mean"] >= row["mean"], "a lower threshold reads a taller jet (%.2f >= %.2f mm)" % (1e3 * res["thresholds"]["0.5"]["mean"], 1e3 * row["mean"]))
p = subprocess.run([sys.executable, script, out, "--thresholds", "1.2"], capture_output=True, text=True, timeout=300)
t.check(p.returncode != 0 and "--thresholds" in p.stderr, "--thresholds 1.2 refused: %s" % p.stderr.strip()[:100])
