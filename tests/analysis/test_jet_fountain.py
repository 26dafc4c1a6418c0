"""scripts/jet_fountain.py (fountain height and jet velocity of a time-averaged jetting bed) on inputs with known
answers, no runs:

- a column whose solid fraction falls linearly with height crosses each threshold where the line does (1e-12);
- a column that never reaches a threshold gives NaN; one whose top cell reaches it gives the top cell centre;
- x picks the particle-grid column holding it, clamped to the grid;
- the script on a hand-built analysis.h5 (3D, two cells deep, a fountain only in the jet column) reports the
  crossing of that column and its largest upward velocity, not those of the bed beside it;
- --since: two running means (1000 samples of a tall fountain, then 3000 samples in all) give back the window's own
  fountain and velocity exactly (to 1e-12); an earlier file with more samples is refused;
- --below leaves out a layer held against a closed top;
- --merge: a column between two jets that is packed low down and thins linearly above meets the jets' solid
  fraction where the line does (1e-12), scanning up; one denser than the jets everywhere gives NaN; jets that share
  a column with the midway one are refused;
- --snapshots with --blocks: the gas's void fraction of snapshots on a finer fluid grid, in the window only and in the
  jet's particle column only, gives the fountain of the mean profile and of each block exactly (1e-12), and the blocks'
  standard error; more blocks than snapshots, a window without any, or blocks without snapshots are refused."""
import json
import math
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


def write_analysis(path, sf, vel, samples, start, end):
    with h5py.File(path, "w") as f:
        f["grid/origin"] = np.zeros(3)
        f["grid/spacing"] = np.array([0.005, h, 0.002])
        f["grid/cells"] = np.array([nx, ny, nz])
        f["fields/solid_fraction"] = sf
        f["fields/velocity"] = vel
        f["fields/solid_flux"] = np.nan_to_num(vel) * sf[..., None]
        f["measures/window_start"] = [start]
        f["measures/window_end"] = [end]
        f["measures/samples"] = [samples]
        f["measures/expanded_bed_height_cutoff"] = [0.02]


def jet_fountain(run, *extra):
    p = subprocess.run([sys.executable, os.path.join(t.SRC, "scripts", "jet_fountain.py"), run, "--thresholds", "0.1,0.02",
                        "--json", run + "/jet.json"] + list(extra), capture_output=True, text=True, timeout=120)
    print(p.stdout, p.stderr)
    return p


os.makedirs("jet_fountain_run", exist_ok=True)
write_analysis("jet_fountain_run/analysis.h5", sf, vel, 1000, 1.0, 2.0)
p = jet_fountain("jet_fountain_run")
t.check(p.returncode == 0, "jet_fountain.py exits 0")
r = json.load(open("jet_fountain_run/jet.json"))
t.check(r["column"] == 4, "the jet column is the middle one (column %d)" % r["column"])
t.check(abs(r["fountain_height_m"]["0.1"] - 0.12) < 1e-12 and abs(r["fountain_height_m"]["0.02"] - 0.136) < 1e-12,
        "fountain heights %.4f and %.4f m at 0.1 and 0.02 (exact 0.12 and 0.136)" % (r["fountain_height_m"]["0.1"], r["fountain_height_m"]["0.02"]))
t.check(r["jet_max_velocity_y_m_s"] == 0.9 and abs(r["jet_max_velocity_y_height_m"] - y[k30]) < 1e-15,
        "largest upward velocity of the jet column 0.9 m/s at %.1f mm" % (1e3 * r["jet_max_velocity_y_height_m"]))
# cross-section mean: 0.6 in every layer below 20 mm; at the 22 mm layer only the jet column holds solid (0.59 / 9)
m22 = (0.6 - 5.0 * 0.002) / 9
exact = 0.018 + (0.6 - 0.1) / (0.6 - m22) * 0.004
t.check(abs(r["bed_height_cross_section_0.1_m"] - exact) < 1e-12,
        "bed height from the cross-section mean %.6f m (exact %.6f m)" % (r["bed_height_cross_section_0.1_m"], exact))

# --since: the first 1000 samples had a fountain twice as tall (solid fraction 0.6 up to 40 mm, then falling) and
# particles at 2 m/s; the run's file holds the running means over 3000 samples; the last 2000 are the bed above.
tall = np.where(y[None, :, None] < 0.04, 0.6, 0.0) * np.ones((nz, ny, nx))
vel_tall = np.zeros((nz, ny, nx, 3))
vel_tall[..., 1] = 2.0
flux_late = np.nan_to_num(vel) * sf[..., None]
sf_mean = (1000 * tall + 2000 * sf) / 3000
flux_mean = (1000 * vel_tall * tall[..., None] + 2000 * flux_late) / 3000
os.makedirs("jet_fountain_since", exist_ok=True)
write_analysis("jet_fountain_since/early.h5", tall, vel_tall, 1000, 1.0, 1.5)
with np.errstate(invalid="ignore", divide="ignore"):
    write_analysis("jet_fountain_since/analysis.h5", sf_mean, np.where(sf_mean[..., None] > 0, flux_mean / sf_mean[..., None], np.nan), 3000, 1.0, 2.5)
with h5py.File("jet_fountain_since/analysis.h5", "r+") as f:
    f["fields/solid_flux"][...] = flux_mean
p = jet_fountain("jet_fountain_since", "--since", "jet_fountain_since/early.h5")
r = json.load(open("jet_fountain_since/jet.json"))
t.check(p.returncode == 0 and r["samples"] == 2000 and abs(r["window_s"][0] - 1.5) < 1e-15, "--since: the window is 1.5-2.5 s, 2000 samples")
t.check(abs(r["fountain_height_m"]["0.1"] - 0.12) < 1e-12 and abs(r["fountain_height_m"]["0.02"] - 0.136) < 1e-12,
        "--since: the window's fountain heights %.6f and %.6f m (exact 0.12 and 0.136)" % (r["fountain_height_m"]["0.1"], r["fountain_height_m"]["0.02"]))
t.check(abs(r["jet_max_velocity_y_m_s"] - 0.9) < 1e-12, "--since: the window's largest upward velocity %.12f m/s (0.9)" % r["jet_max_velocity_y_m_s"])
# --below: a layer held against the top (every column full above 150 mm) hides the fountain unless left out
cake = sf.copy()
cake[:, y > 0.15, :] = 0.6
os.makedirs("jet_fountain_cake", exist_ok=True)
write_analysis("jet_fountain_cake/analysis.h5", cake, vel, 1000, 1.0, 2.0)
jet_fountain("jet_fountain_cake")
top = json.load(open("jet_fountain_cake/jet.json"))["fountain_height_m"]["0.1"]
jet_fountain("jet_fountain_cake", "--below", "0.15")
below = json.load(open("jet_fountain_cake/jet.json"))["fountain_height_m"]["0.1"]
t.check(top == y[-1] and abs(below - 0.12) < 1e-12, "--below 0.15 leaves the top layer out: %.4f m (without: %.4f m)" % (below, top))
p = jet_fountain("jet_fountain_run", "--since", "jet_fountain_since/analysis.h5")
t.check(p.returncode != 0 and "--since" in p.stderr, "--since with a later file is refused: %s" % p.stderr.strip()[:100])

# --merge: two jets in columns 2 and 6 (x = 12.5 and 32.5 mm) at solid fraction 0.1 from the bottom up; the column
# midway (4) packed at 0.6 up to 30 mm, then thinning by 0.01 per mm: it falls to the jets' 0.1 at 80 mm.
mid = np.clip(0.6 - 10.0 * (y - 0.03), 0.0, 0.6)
t.check(abs(jf.merge_height(y, mid, 0.1 * np.ones_like(y)) - 0.08) < 1e-12, "merge_height: the midway line meets 0.1 at 80 mm")
t.check(math.isnan(jf.merge_height(y, 0.6 * np.ones_like(y), 0.1 * np.ones_like(y))), "a midway column denser everywhere gives NaN")
t.check(jf.merge_height(y, 0.05 * np.ones_like(y), 0.1 * np.ones_like(y)) == y[0], "one already thinner at the bottom gives the bottom cell centre")
two = np.full((nz, ny, nx), 0.6)
two[:, :, 2] = two[:, :, 6] = 0.1
two[:, :, 4] = mid
vel2 = np.zeros((nz, ny, nx, 3))
vel2[:, :, 4, 1] = np.where(y > 0.08, 0.3, -0.05)
os.makedirs("jet_fountain_merge", exist_ok=True)
write_analysis("jet_fountain_merge/analysis.h5", two, vel2, 1000, 1.0, 2.0)
p = jet_fountain("jet_fountain_merge", "--merge", "0.0125,0.0325")
m = json.load(open("jet_fountain_merge/jet.json"))["merge"]
t.check(p.returncode == 0 and m["jet_columns"] == [2, 6] and m["mid_column"] == 4, "--merge: jet columns %s, midway %d" % (m["jet_columns"], m["mid_column"]))
t.check(abs(m["merge_height_m"] - 0.08) < 1e-12 and m["mid_solid_fraction_bottom"] == 0.6,
        "--merge: the jets merge at %.6f m (exact 0.08), the midway column packed (0.6) at the bottom" % m["merge_height_m"])
t.check(m["mid_max_velocity_y_m_s"] == 0.3, "--merge: the midway column rises at 0.3 m/s above the merge")
p = jet_fountain("jet_fountain_merge", "--merge", "0.021,0.022")
t.check(p.returncode != 0 and "--merge" in p.stderr, "--merge with both jets in one column is refused: %s" % p.stderr.strip()[:120])
p = jet_fountain("jet_fountain_merge", "--merge", "0.01")
t.check(p.returncode != 0 and "--merge" in p.stderr, "--merge with one x is refused: %s" % p.stderr.strip()[:120])

# --snapshots: the gas's void fraction of snapshots on a fluid grid twice as fine as the particle grid (18 x 80 x 2);
# in the jet's particle column (x 20-25 mm: fluid columns 8 and 9) each snapshot's solid fraction falls linearly from
# 0.6 above a_k, a_k = 20, 22, 24, 26 mm at t = 1.0 .. 1.3 s (the last written a step early), and a snapshot at
# 0.9 s outside the window stands far higher. The fluid columns beside the jet are packed to the top, so a column
# taken too wide shows. The mean of lines that are not clipped at a height is the line of the mean a: the threshold
# s is crossed at mean(a) + (0.6 - s) / 5, exactly between cell centres; two blocks give mean(a) of each half.
os.makedirs("jet_fountain_snap", exist_ok=True)
write_analysis("jet_fountain_snap/analysis.h5", sf, vel, 1000, 1.0, 2.0)
fy = (np.arange(80) + 0.5) * 0.002
for k, (time, a) in enumerate(((0.9, 0.08), (1.0, 0.020), (1.1, 0.022), (1.2, 0.024), (1.3 - 3e-6, 0.026))):
    solid = np.full((2, 80, 18), 0.6)
    solid[:, :, 8] = solid[:, :, 9] = np.clip(0.6 - 5.0 * (fy - a), 0.0, 0.6)[None, :]
    with h5py.File("jet_fountain_snap/snapshot_%05d.h5" % k, "w") as f:
        f.attrs["time"] = time
        f["fluid/void_fraction"] = 1.0 - solid
p = jet_fountain("jet_fountain_snap", "--snapshots", "1.0,1.3", "--blocks", "2")
sn = json.load(open("jet_fountain_snap/jet.json"))["from_snapshots"]
t.check(p.returncode == 0 and sn["snapshots"] == 4, "--snapshots 1.0,1.3: the four snapshots in the window (%d)" % sn["snapshots"])
for thr in ("0.1", "0.02"):
    exact = 0.023 + (0.6 - float(thr)) / 5.0
    t.check(abs(sn["fountain_height_m"][thr] - exact) < 1e-12,
            "--snapshots: fountain at %s %.6f m (exact %.6f m)" % (thr, sn["fountain_height_m"][thr], exact))
b = sn["blocks"]["0.1"]
t.check(abs(b["heights_m"][0] - 0.121) < 1e-12 and abs(b["heights_m"][1] - 0.125) < 1e-12 and abs(b["mean_m"] - 0.123) < 1e-12
        and abs(b["standard_error_m"] - 0.002) < 1e-12, "--blocks 2: %s m, mean %.6f, standard error %.6f (exact 0.121, 0.125, 0.123, 0.002)"
        % (b["heights_m"], b["mean_m"], b["standard_error_m"]))
p = jet_fountain("jet_fountain_snap", "--snapshots", "1.0,1.3", "--blocks", "5")
t.check(p.returncode != 0 and "--blocks" in p.stderr, "--blocks beyond the snapshots is refused: %s" % p.stderr.strip()[:100])
p = jet_fountain("jet_fountain_snap", "--snapshots", "3,4")
t.check(p.returncode != 0 and "--snapshots" in p.stderr, "a window without snapshots is refused: %s" % p.stderr.strip()[:100])
p = jet_fountain("jet_fountain_snap", "--blocks", "2")
t.check(p.returncode != 0 and "--blocks" in p.stderr, "--blocks without --snapshots is refused: %s" % p.stderr.strip()[:100])
