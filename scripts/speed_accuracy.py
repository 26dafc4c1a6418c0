#!/usr/bin/env python3
"""Speed against accuracy: error against cost for each knob on reference problems with a known answer.

Problems (each point is one fluidbed run, resumable and parallel like the stability map: fluidbed_tools/study.py):
  bounce     a 1.2 mm sphere dropped 10 mm onto the floor, e = 0.7: the fifth apex against the analytic linear
             spring-dashpot of the seed's k_n = 800 N/m (fluidbed_tools/reference.py); knobs -dem_dt_factor and -dem_kn (the
             soft-spring trade: a softer spring allows a longer step and a larger overlap, both in the table);
  head_on    two spheres colliding at 1 m/s, e = 0.9: the measured restitution against e; knob -dem_dt_factor;
  packed     the small bed (examples/coupling/small_bed.opts) below U_mf at 0.15 m/s: the pressure drop against Ergun
             for the measured voidage, layer by layer; knobs -dem_dt_factor, -couple_substeps, -fluid_p_ksp_rtol,
             -fluid_pc_reuse, -dem_kn (the default point is the seed's 800 N/m; the softer springs at the same fraction of
             their own t_cr);
  muller     the Muller bubbling bed at 0.6 m/s (examples/muller_bed_u060.opts, from its own settled start): the
             time-averaged pressure drop against the bed weight per area, over a window; knobs -dem_dt_factor,
             -couple_substeps and -dem_kn (as packed; hours per point). The averaging window is not run again: the windows 0.25-4 s are cut
             from the longest run's pressure series and compared with its full average (their own panel, --png).
             Its second answer, muller_profile (derived rows, their own panel): the voidage profiles across the bed
             at the seed's 16.4 and 31.2 mm (Fig. 2.6), time-averaged over the same window and made mirror-
             symmetric (the bed is; a 4 s average is not, docs/validation.md), against the converged reference
             run at t_cr/20 (MULLER_REFERENCE): the rms relative difference over the cells of both rows, with the
             rms the two runs' standard errors (block means of 0.5 s) alone would give as its uncertainty.
             --muller-long DIR[,DIR...]: long runs of the scene (scripts/validate.sh muller_bed_u060 1 -t_final T
             -output_interval 0.05, each with its own -insert_seed) are the profiles' reference instead: their mean,
             each averaged over 1-T s with the standard errors of 2 s blocks (a roll keeps its side for seconds,
             MULLER_LONG_BLOCK), the uncertainty the larger of those and the runs' spread; the first run's series
             give the windows (pressure drop, muller_window, and profiles, muller_profile_window: 1 to 1 + w s
             against 1-T s), and each run is compared with the others' mean (muller_profile_runs: how far one run
             of that length is from the answer);
  jet2d      the 750 um jetted 2D pseudo-bed of the stability map (scripts/stability_map.py; its runs, read from its
             table --stability-csv, are not run again here): the time-averaged pressure drop and expanded bed height
             against the map's reference (two grids on the seed's 0.43 d cells at t_cr/20), the larger of the two
             relative errors; knobs the gas cell width with single or two grids, -dem_dt_factor, -couple_substeps, and
             the particle grid's cells on the reference's gas grid (-pgrid_ratio, the map's ratio table --ratio-csv),
             and the spring stiffness -dem_kn on the two grids' 3 d cells (the map's kn table --kn-csv);
             uncertainty: the reference against its mirrored-start twin.
  jet750     the seed's 750 um single jet at 3 U_mf (examples/twogrid_750_jet1_u301_wallmu050_coarse.opts: one 1.611 mm
             slit at 45.3 m/s, wall friction 0.5, closed top) as a 2D pseudo-bed one particle deep (6,894 particles,
             settled without gas first, JET750_SETTLE), spouting, averaged over 0.5-1 s: the fountain height in the jet
             column (solid fraction 0.05, scripts/jet_fountain.py), the pressure drop and the largest upward particle
             velocity in the jet column, each against the finest affordable reference (the seed's fine 175 x 200 gas
             grid, particle cells of 7 x 2 of its cells, t_cr/20); the error is the largest of the three (each in the
             table); knobs the gas grid (the fine one and the seed's coarse 105 x 150 of its grid-sensitivity study,
             particle cells of 5 x 2) with the step; uncertainty: the coarse grid at t_cr/10 against its mirrored-start
             twin (what two realizations of one setting differ by).
Cost: wall seconds per simulated second per core (summary.json), with cpu_share, the processor time the run had over its
wall time x ranks (below 1 where it waited for its core on a loaded machine, or for its writes). Each problem's Pareto front (no other point both
cheaper and more accurate) is marked in --png; the table goes to --csv. docs/speed_accuracy.md has the results.

example:
  scripts/speed_accuracy.py --jobs 2                      # bounce, head_on, packed
  scripts/speed_accuracy.py --problems muller --jobs 2    # the long problem
  scripts/speed_accuracy.py --ci --out build/sa_ci        # the three-point bounce test
"""
import argparse
import csv
import functools
import math
import os

import numpy as np

from fluidbed_tools import outputs, reference, run, study
from fluidbed_tools.stats import batch_error
import profile_asymmetry  # the voidage rows of a run's snapshots and their block-means errors
import umf_sweep  # the small bed's particles, geometry and pressure probes

ROOT = run.ROOT
EX = os.path.join(ROOT, "examples")
D, RHO = 1.2e-3, 1000.0  # the bounce and head-on particles (seed Table 2.1)
M = RHO * math.pi / 6 * D ** 3


def read_table(path):
    return np.genfromtxt(path, delimiter=",", names=True)


# Each problem: the options of a point (knob -> value over the problem's defaults), the error of a finished run
# (relative, against the known answer), and the knobs swept (each with the others at the defaults).
def bounce_options(k):
    return ["-options_file", os.path.join(EX, "dem", "bounce_e090.opts"), "-dem_e", 0.7, "-dem_dt_factor", k["dt_factor"], "-dem_kn", k["kn"],
            "-t_final", 0.4, "-monitor_track_every", 1, "-insert_positions", "0.005,%.12g,0.005" % (0.01 + D / 2)]


def bounce_error(out, k):
    tr = read_table(os.path.join(out, "track.csv"))
    gap, vy = tr["y"] - D / 2, tr["vy"]
    apex = gap[1:][(vy[:-1] > 0) & (vy[1:] <= 0)]
    # against the seed's spring (k_n = 800 N/m): a softer spring is the cheaper model whose error this measures
    ref = reference.bounce_apexes(0.01, 5, 800.0, 0.7, M, 9.81)
    if len(apex) < 5:
        return float("nan"), 0.0
    return abs(apex[4] / ref[4] - 1), 0.0


def head_on_options(k):
    return ["-options_file", os.path.join(EX, "dem", "head_on.opts"), "-dem_e", 0.9, "-dem_dt_factor", k["dt_factor"], "-dem_kn", k["kn"]]


def head_on_error(out, k):
    tr = read_table(os.path.join(out, "track.csv"))
    a, b = tr["id"] == 0, tr["id"] == 1
    v0, v1 = tr["vx"][a], tr["vx"][b]
    return abs((v1[-1] - v0[-1]) / (v0[0] - v1[0]) / 0.9 - 1), 0.0


def packed_options(k):
    return ["-options_file", os.path.join(EX, "coupling", "small_bed.opts"), "-t_final", 0.25, "-dem_dt_factor", k["dt_factor"],
            "-couple_substeps", k["substeps"], "-fluid_p_ksp_rtol", k["rtol"], "-fluid_pc_reuse", k["pc_reuse"], "-output_particles", 1] + kn_options(k)


def kn_options(k):
    """-dem_kn for the stiffness knob's points (walls follow it, the step follows its t_cr); none at the seed's 800 N/m,
    so that the points run before the knob existed keep their commands and are not run again."""
    return ["-dem_kn", k["kn"]] if "kn" in k else []


def packed_error(out, k):
    mon = read_table(os.path.join(out, "monitor.csv"))
    p = read_table(os.path.join(out, "particles.csv"))
    h = umf_sweep.LAYER
    vp = math.pi / 6 * umf_sweep.D ** 3
    area = umf_sweep.LX * umf_sweep.LZ
    # between the probes at the centres of layers 1 and 5 (as tests/coupling/test_small_bed.py)
    # time-averaged over the last 0.1 s (the bed settles under the gas in the first 0.15 s), with its batch-means error
    late = mon["time"] >= mon["time"][-1] - 0.1
    series = mon["p_y5mm_avg"][late] - mon["p_y18_33mm_avg"][late] - umf_sweep.RHO_G * umf_sweep.G * 4 * h
    dp = series.mean()
    ergun = reference.ergun_layers(p["y"], h, 1, 5, vp, area, lambda eps: umf_sweep.ergun_gradient(eps, 0.15))
    return abs(dp / ergun - 1), batch_error(series) / ergun


def muller_options(k):
    return ["-options_file", os.path.join(EX, "muller_bed_u060.opts"), "-t_final", MULLER_WINDOW + 1.0, "-dem_dt_factor", k["dt_factor"],
            "-couple_substeps", k["substeps"], "-average_start", 1.0, "-output_particles", 0, "-checkpoint_interval", 0, "-output_interval",
            MULLER_SNAPSHOT_DT] + kn_options(k)


def muller_error(out, k):
    """The time-averaged pressure drop (summary.json averages, from the distributor) against the buoyant bed weight per
    area, and its uncertainty: the standard error of the probes' pressure difference over the window by batch means (10
    batches, each longer than the bubble period)."""
    s = outputs.summary(out)
    weight = s["particles_inserted"] * math.pi / 6 * 1.2e-3 ** 3 * (1000.0 - 1.205) * 9.81 / (0.044 * 0.01)
    dp = s["averages"]["pressure_drop_mean_Pa"]
    mon = read_table(os.path.join(out, "monitor.csv"))
    series = (mon["p_y2_5mm_avg"] - mon["p_y157_5mm_avg"])[mon["time"] >= 1.0]
    return abs(dp / weight - 1), batch_error(series) / weight


MULLER_WINDOW = 4.0  # s: every Muller point averages over 1-5 s; the window rows are cut from the default point's run
MULLER_WINDOWS = [0.25, 0.5, 1.0, 2.0]
MULLER_SNAPSHOT_DT = 0.05  # s: the gas snapshots the profiles are averaged from (80 in the window)
MULLER_HEIGHTS = (0.0164, 0.0312)  # m: the seed's profiles (Fig. 2.6)
MULLER_REFERENCE = {"dt_factor": 0.05, "substeps": 1}  # the profiles' converged reference: t_cr/20, a gas step per DEM step
MULLER_BLOCK = 0.5  # s: block length of the profiles' standard errors (longer than the bubble period)
MULLER_LONG_BLOCK = 2.0  # s: the long reference's blocks (docs/validation.md: a roll keeps its side for seconds)
MULLER_LONG_WINDOWS = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0]  # s: windows cut from the long reference, where it reaches 1 + w


def muller_height(out):
    """The bed's height (-domain_ly) as the run was given it (its options file and command line)."""
    ly = outputs.run_options(out, {"-domain_ly": None})["-domain_ly"]
    if not ly:
        raise SystemExit("speed_accuracy.py: no -domain_ly in the options recorded in %s (command.txt or command.json)" % out)
    return ly


@functools.lru_cache(maxsize=None)
def muller_rows(out, height):
    """Times and mirror-symmetric voidage rows at height of every snapshot of a run, read once per run and height:
    the reference's rows serve every point, and a long run's every window (a run's snapshots do not change once it
    has finished)."""
    times, rows = profile_asymmetry.read_rows(out, height, 0.0, muller_height(out))
    return times, 0.5 * (rows + rows[:, ::-1])


@functools.lru_cache(maxsize=None)
def muller_profiles(out, start=1.0, end=float("inf"), block=MULLER_BLOCK):
    """The mirror-symmetric time-averaged voidage rows at MULLER_HEIGHTS from a run's snapshots in [start, end],
    concatenated, with each cell's standard error by block means (of block s), and the snapshots used."""
    means, errs, count = [], [], 0
    for h in MULLER_HEIGHTS:
        times, sym = muller_rows(out, h)
        keep = (times >= start - 1e-9) & (times <= end + 1e-9)
        times, sym = times[keep], sym[keep]
        if len(times) < 2:
            return None, None, 0
        means.append(sym.mean(axis=0))
        errs.append([profile_asymmetry.block_error(sym[:, i], times, block) for i in range(sym.shape[1])])
        count = len(times)
    return np.concatenate(means), np.concatenate(errs), count


def reference_profiles(refs, block):
    """The profiles' reference from one run or an ensemble of runs (refs: a tuple of run directories), each averaged
    over all its snapshots from 1 s: the mean of the runs' mirror-symmetric rows and each cell's standard error. With
    one run that is its block-means error (blocks of block s); with several, the larger of the runs' block errors
    combined and their spread (standard deviation over sqrt K): a roll that keeps its side for a whole run makes two
    runs differ by more than their blocks say (docs/validation.md)."""
    means, errs = [], []
    for ref in refs:
        m, e, n = muller_profiles(ref, 1.0, float("inf"), block)
        if not n:
            return None, None
        means.append(m)
        errs.append(e)
    means, errs = np.array(means), np.array(errs)
    within = np.sqrt((errs ** 2).sum(axis=0)) / len(refs)
    if len(refs) == 1:
        return means[0], within
    return means.mean(axis=0), np.maximum(within, means.std(axis=0, ddof=1) / math.sqrt(len(refs)))


def profile_difference(out, ref_out, ref_block=MULLER_BLOCK, block=MULLER_BLOCK):
    """The rms relative difference of run out's profiles (over its snapshots from 1 s, standard errors from blocks of
    block s) from the reference's (reference_profiles of ref_out, one run directory or a sequence of them, over all
    their snapshots from 1 s, blocks of ref_block s) over all cells, and the rms the standard errors of both sides
    alone give (what two runs of the same settings would differ by)."""
    refs = (ref_out,) if isinstance(ref_out, str) else tuple(ref_out)
    m, e = reference_profiles((out,), block)
    r, re = reference_profiles(refs, ref_block)
    if m is None or r is None or m.shape != r.shape:
        return float("nan"), float("nan")
    return float(np.sqrt(np.mean(((m - r) / r) ** 2))), float(np.sqrt(np.mean((e ** 2 + re ** 2) / r ** 2)))


def muller_profile_rows(rows, out_dir, long_run=None):
    """The muller_profile rows: every finished Muller point's profiles against the reference: the long run, or the
    ensemble of long runs (a sequence of directories), if given (every point then compared with it), else the t_cr/20
    point's (none until that has run)."""
    ref_id = point_id("muller", dict(PROBLEMS["muller"]["defaults"], **MULLER_REFERENCE))
    if long_run:
        ref, block = long_run, MULLER_LONG_BLOCK  # one directory or several: profile_difference takes either
    elif any(r["id"] == ref_id and r["status"] == "ok" for r in rows):
        ref, block = os.path.join(out_dir, ref_id), MULLER_BLOCK
    else:
        return []
    out = []
    for r in rows:
        if r["problem"] != "muller" or r["status"] != "ok" or (r["id"] == ref_id and not long_run):
            continue
        err, unc = profile_difference(os.path.join(out_dir, r["id"]), ref, block)
        out.append({"problem": "muller_profile", "knob": r["knob"], "id": "muller_profile" + r["id"][len("muller"):], "dt_factor": r["dt_factor"],
                    "substeps": r["substeps"], "status": "derived", "error": err, "uncertainty": unc, "cost": r["cost"]})
        if "kn" in r:  # the stiffness knob's points
            out[-1]["kn"] = r["kn"]
    return out


def muller_window_rows(out, cost, windows=MULLER_WINDOWS):
    """Error of the probe pressure-drop average over 1 to 1 + w s against the full window's, with its batch-means
    uncertainty, for each w in windows that the run covers; cost: the wall seconds per core of 1 + w s of bed."""
    mon = read_table(os.path.join(out, "monitor.csv"))
    dp = mon["p_y2_5mm_avg"] - mon["p_y157_5mm_avg"]
    full = dp[mon["time"] >= 1.0].mean()
    rows = []
    for w in windows:
        if mon["time"][-1] < 1.0 + w - 1e-9:
            continue
        part = dp[(mon["time"] >= 1.0) & (mon["time"] <= 1.0 + w)]
        rows.append({"problem": "muller_window", "knob": "window", "id": "muller_window%g" % w, "window": w, "status": "derived",
                     "error": abs(part.mean() / full - 1), "uncertainty": batch_error(part) / abs(full), "cost": cost * (1.0 + w)})
    return rows


def muller_profile_window_rows(long_run, cost, windows=MULLER_LONG_WINDOWS):
    """The long run's profiles over 1 to 1 + w s against its whole window's (1 s to its end), for each w it covers
    with room to spare (1 + w at most three quarters of the way): the error a window of w s leaves, and the rms of
    the window's standard errors (0.5 s blocks) as its uncertainty; cost: wall seconds per core of 1 + w s of bed."""
    r, _, nr = muller_profiles(long_run, 1.0, float("inf"), MULLER_LONG_BLOCK)
    if not nr:
        return []
    times = muller_rows(long_run, MULLER_HEIGHTS[0])[0]
    rows = []
    for w in windows:
        if 1.0 + w > 1.0 + 0.75 * (times[-1] - 1.0):
            continue
        m, e, _ = muller_profiles(long_run, 1.0, 1.0 + w)
        rows.append({"problem": "muller_profile_window", "knob": "window", "id": "muller_profile_window%g" % w, "window": w, "status": "derived",
                     "error": float(np.sqrt(np.mean(((m - r) / r) ** 2))), "uncertainty": float(np.sqrt(np.mean((e / r) ** 2))),
                     "cost": cost * (1.0 + w)})
    return rows


def muller_long_rows(long_runs, cost):
    """Each long run's profiles (1 s to its end) against the mean of the other long runs' (leave one out): how far one
    run of that length is from an independent estimate of the answer, with both sides' standard errors (2 s blocks) as
    the uncertainty; cost: wall seconds per core of the run's length of bed."""
    rows = []
    for k, run_dir in enumerate(long_runs):
        others = tuple(long_runs[:k] + long_runs[k + 1:])
        err, unc = profile_difference(run_dir, others, MULLER_LONG_BLOCK, MULLER_LONG_BLOCK)
        end = muller_rows(run_dir, MULLER_HEIGHTS[0])[0][-1]
        seed = outputs.run_options(run_dir, {"-insert_seed": 1})["-insert_seed"]  # what tells the runs apart
        rows.append({"problem": "muller_profile_runs", "knob": "window", "id": "muller_profile_run_seed%g" % seed,
                     "window": float(end - 1.0), "status": "derived", "error": err, "uncertainty": unc, "cost": cost * float(end)})
    return rows


def jet2d_rows(path):
    """The stability map's 2D jetted-bed points at the seed's jet that finished, as chart rows (see jet2d above), each
    against the reference point of its own table (the main map's, or the ratio map's own run of it)."""
    if not os.path.exists(path):
        return []
    table = list(csv.DictReader(open(path)))
    ref = {r["id"]: r for r in table}
    r0 = ref.get("cell_dt_two_cell0.43_dt0.05_jet45.3_sub1")
    twin = ref.get("cell_dt_two_cell0.43_dt0.05_jet45.3_sub1_mirror")
    if not r0 or not r0.get("dp_over_weight"):
        return []
    rel = lambda r, k: abs(float(r[k]) / float(r0[k]) - 1)  # noqa: E731
    unc = max(rel(twin, "dp_over_weight"), rel(twin, "bed_height_mm")) if twin and twin.get("dp_over_weight") else float("nan")
    rows = []
    for r in table:
        if r["map"] not in ("cell_dt", "jet_sub", "ratio", "kn") or float(r["jet"]) != 45.3 or r["id"].endswith("_mirror") or r["id"] == r0["id"]:
            continue
        cell = "%s %s d" % (r["method"], r["cell_d"])
        if r["map"] == "ratio":
            cell += ", particle cells %s" % r["cells_per_particle_cell"]
        # the ratio and kn tables' points ran on another executable and machine load than the main map's: a panel and
        # a Pareto front of their own (jet2d_ratio, jet2d_kn), not costs to set beside the main map's
        row = {"problem": {"ratio": "jet2d_ratio", "kn": "jet2d_kn"}.get(r["map"], "jet2d"),
               "knob": {"jet_sub": "substeps", "ratio": "pgrid_ratio", "kn": "kn"}.get(r["map"], "cell_dt"),
               "id": "jet2d_" + r["id"],
               "status": r["status"], "exit_status": r["exit_status"], "dt_factor": float(r["dt_factor"]), "substeps": int(r["substeps"]),
               "cell": cell, "error": float("nan"), "uncertainty": unc,
               "cost": float(r["cost_s_per_s_core"]) if r.get("cost_s_per_s_core") else float("nan"), "overlap_max": r.get("overlap_max")}
        if r["map"] == "kn":
            row["kn"] = float(r["kn"])
            gas = int(r.get("gas_substeps") or 1)
            row["cell"] += ", %d gas steps per DEM step" % gas if gas > 1 else ""
        if r.get("dp_over_weight") and r["class"] != "unstable":
            row["error"] = max(rel(r, "dp_over_weight"), rel(r, "bed_height_mm"))
        rows.append(row)
    return rows


JET750_LX = 0.0564  # m, the bed's width
JET750_X = 0.0282  # m, the slit's centre
JET750_WINDOW = (0.5, 1.0)  # s: the spouting window averaged
JET750_BELOW = 0.25  # m: the jet column's cells above are left out (beads thrown up at the start-up slug held against the closed top)
JET750_SETTLE = ["-domain_dim", 2, "-domain_lx", JET750_LX, "-domain_ly", 0.28, "-domain_lz", 0.00075, "-particle_diameter", 7.5e-4,
                 "-particle_density", 2500, "-dem_kn", 800, "-dem_e", 0.9, "-dem_mu", 0.1, "-wall_mu", 0.5, "-dem_dt_factor", 0.1,
                 "-insert_type", "lattice", "-insert_count", 6894, "-insert_spacing", 1.05, "-insert_jitter", 0.5, "-insert_seed", 750,
                 "-t_final", 0.3, "-output_interval", 0, "-checkpoint_interval", 0]
JET750_GRIDS = {175: (175, 200, "7,2"), 105: (105, 150, "5,2")}  # gas cells x, y and particle cells (gas cells per particle cell)
JET750_REFERENCE = {"cells_x": 175, "dt_factor": 0.05, "mirror": 0}
JET750_TWINS = ({"cells_x": 105, "dt_factor": 0.1, "mirror": 0}, {"cells_x": 105, "dt_factor": 0.1, "mirror": 1})


def jet750_bed(out_dir, mirror, exe):
    """The settled one-layer bed (particles.csv of JET750_SETTLE, run once under out_dir), or its mirror image about
    the bed's centre plane x = LX / 2 (positions and the velocities' x components reflected, spins as an axial vector)."""
    settle = os.path.join(out_dir, "jet750_settle")
    s, status, _, _ = study.run(JET750_SETTLE, settle, 1, exe)
    if not s or s["status"] not in ("ok", "warned"):
        raise SystemExit("speed_accuracy.py: the jet750 bed did not settle (exit %s, %s)" % (status, settle))
    path = os.path.join(settle, "particles.csv")
    if not mirror:
        return path
    mirrored = os.path.join(settle, "particles_mirrored.csv")
    if not os.path.exists(mirrored):
        outputs.mirror_particles(path, mirrored, JET750_LX)
    return mirrored


def jet750_options(k, out_dir=None, exe=run.EXE):
    nx, ny, ratio = JET750_GRIDS[int(k["cells_x"])]
    bed = jet750_bed(out_dir, int(k["mirror"]), exe) if out_dir else "settled.csv"
    return ["-options_file", os.path.join(EX, "twogrid_750_jet1_u301_wallmu050_coarse.opts"), "-domain_dim", 2, "-domain_lz", 0.00075,
            "-grid_nx", nx, "-grid_ny", ny, "-pgrid_ratio", ratio, "-dem_dt_factor", k["dt_factor"], "-insert_type", "file", "-insert_file", bed,
            "-domain_top_outlet", 0, "-t_final", JET750_WINDOW[1], "-average_start", JET750_WINDOW[0], "-output_interval", 0,
            "-output_particles", 0, "-checkpoint_interval", 0.25] + (["-couple_gas_substeps", k["gas_substeps"]] if "gas_substeps" in k else [])


def jet750_measures(out):
    """The fountain height at solid fraction 0.05 in the jet column, the time-averaged pressure drop and the largest
    upward particle velocity in the jet column, over the run's averaging window (None before the run has averaged).
    The column is read below JET750_BELOW: the jet's start-up slug leaves some beads held against the closed top
    (docs/stability.md), whose cell would otherwise be the fountain's top."""
    import jet_fountain
    from fluidbed_tools import plot as fp
    if not os.path.exists(os.path.join(out, "analysis.h5")) or not os.path.exists(os.path.join(out, "summary.json")):
        return None
    a = fp.read_analysis(out)
    _, _, y, sf, vy = jet_fountain.jet_column(a, JET750_X)
    keep = y < JET750_BELOW
    y, sf, vy = y[keep], sf[keep], vy[keep]
    return {"fountain": jet_fountain.fountain_height(y, sf, 0.05), "dp": outputs.summary(out)["averages"]["pressure_drop_mean_Pa"],
            "v_jet": float(np.nanmax(vy))}


def jet750_difference(m, r):
    """Relative differences of measures m from r: each of the three and their largest."""
    d = {key: abs(m[key] / r[key] - 1) for key in ("fountain", "dp", "v_jet")}
    return max(d.values()), d


def jet750_error(out, k):
    """Against the reference point (its run in the same study folder), with the twins' difference as the uncertainty;
    NaN until the reference has run. The measures and each one's error go to the table as well."""
    here = os.path.dirname(out)
    m, r = jet750_measures(out), jet750_measures(os.path.join(here, point_id("jet750", JET750_REFERENCE)))
    if m is None or r is None:
        return float("nan"), float("nan"), m or {}
    t0, t1 = (jet750_measures(os.path.join(here, point_id("jet750", t))) for t in JET750_TWINS)
    unc = jet750_difference(t1, t0)[0] if t0 and t1 else float("nan")
    err, parts = jet750_difference(m, r)
    return err, unc, dict(m, **{"err_" + key: v for key, v in parts.items()})


PROBLEMS = {
    "bounce": {"options": bounce_options, "error": bounce_error, "defaults": {"dt_factor": 0.1, "kn": 800},
               "knobs": {"dt_factor": [0.5, 0.3, 0.2, 0.1, 0.05, 0.02], "kn": [800, 400, 200, 100, 50]}},
    "head_on": {"options": head_on_options, "error": head_on_error, "defaults": {"dt_factor": 0.1, "kn": 800},
                "knobs": {"dt_factor": [0.5, 0.3, 0.2, 0.1, 0.05, 0.02]}},
    "packed": {"options": packed_options, "error": packed_error, "defaults": {"dt_factor": 0.1, "substeps": 1, "rtol": 1e-8, "pc_reuse": 10},
               "knobs": {"dt_factor": [0.3, 0.2, 0.1, 0.05], "substeps": [1, 2, 5, 10], "rtol": [1e-4, 1e-6, 1e-8, 1e-10], "pc_reuse": [1, 10, 100],
                         "kn": [200, 50]}},
    "muller": {"options": muller_options, "error": muller_error, "defaults": {"dt_factor": 0.1, "substeps": 1},
               "knobs": {"dt_factor": [0.3, 0.2, 0.1, 0.05], "substeps": [1, 2, 4], "kn": [200, 50]}},
    # the gas grid and the step together (the fine grid's jet needs a gas step of t_cr/20: t_cr/10 trips the Courant guard),
    # the reference first, then the twins
    "jet750": {"options": jet750_options, "error": jet750_error, "defaults": JET750_REFERENCE, "needs_dir": True,
               "points": [("grid_dt", JET750_REFERENCE), ("grid_dt", dict(JET750_REFERENCE, dt_factor=0.1))]
               + [("mirror", t) for t in JET750_TWINS]
               + [("grid_dt", {"cells_x": 105, "dt_factor": f, "mirror": 0}) for f in (0.05, 0.25)]
               # t_cr/4 on the coarse grid trips the Courant guard (the jet's 96-118 m/s through the packed bottom cells needs
               # 4.7 us): the DEM step held and the gas stepping thrice within it
               + [("grid_dt", {"cells_x": 105, "dt_factor": 0.25, "mirror": 0, "gas_substeps": 3})]
               # t_cr/10 on the fine grid trips it too (2D as in 3D): the DEM step doubled, the gas stepping twice within
               # it, so the gas keeps the reference's step and only the DEM's share of the cost moves
               + [("grid_dt", {"cells_x": 175, "dt_factor": 0.1, "mirror": 0, "gas_substeps": 2})]},
}


def points(problems, ci):
    pts = []
    for name in problems:
        pr = PROBLEMS[name]
        if ci:
            return [(name, "dt_factor", dict(pr["defaults"], dt_factor=f)) for f in (0.2, 0.1, 0.05)]
        if "points" in pr:
            pts += [(name, knob, dict(k)) for knob, k in pr["points"]]
            continue
        seen = set()
        for knob, values in pr["knobs"].items():
            for v in values:
                k = dict(pr["defaults"], **{knob: v})
                key = tuple(sorted(k.items()))
                if key not in seen:  # the defaults appear in every knob's sweep: run them once
                    seen.add(key)
                    pts.append((name, knob, k))
    return pts


def point_id(name, k):
    return name + "_" + "_".join("%s%g" % (a, b) for a, b in sorted(k.items()))


def pareto(rows):
    """Marks the rows no other row beats in both cost and error."""
    for r in rows:
        r["pareto"] = r["error"] == r["error"] and r["cost"] == r["cost"] and not any(o is not r and o["cost"] <= r["cost"] and o["error"] <= r["error"] and (o["cost"] < r["cost"] or o["error"] < r["error"])
                              for o in rows if o["problem"] == r["problem"] and o["error"] == o["error"] and o["cost"] == o["cost"])


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    probs = sorted({r["problem"] for r in rows})
    ncols = min(4, len(probs))  # a grid of panels, four to a row
    nrows = (len(probs) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(5 * ncols, 4.5 * nrows), squeeze=False)
    for ax in axes.flat[len(probs):]:
        ax.axis("off")
    markers = dict(zip(["dt_factor", "kn", "substeps", "rtol", "pc_reuse", "window", "cell_dt", "pgrid_ratio", "grid_dt", "mirror"], "osD^vPX*hp"))

    def label(r, knob):
        if knob == "pgrid_ratio":
            return r["cell"].split(", ")[-1]
        if knob == "kn" and "gas steps" in (r.get("cell") or ""):
            return "%g, %s" % (r["kn"], r["cell"].split(", ")[-1].replace(" per DEM step", ""))
        if knob in ("grid_dt", "mirror"):
            gas = r.get("gas_substeps") or 1
            return "%d cells, dt %g%s%s" % (r["cells_x"], r["dt_factor"], ", mirrored" if r.get("mirror") else "",
                                            ", %d gas steps" % gas if gas == gas and gas > 1 else "")
        return "%s, dt %g" % (r["cell"], r["dt_factor"]) if knob == "cell_dt" else "%g" % r[knob]

    for ax, name in zip(axes.flat, probs):
        rs = [r for r in rows if r["problem"] == name and r["error"] == r["error"]]
        # the reference point (error 0) sits at half the panel's smallest error, not at an arbitrary floor that
        # would stretch the log axis over decades no point occupies
        nonzero = [r["error"] for r in rs if r["error"] > 0]
        floor = 0.5 * min(nonzero) if nonzero else 1e-7

        def y(r):
            return max(r["error"], floor)
        for knob in sorted({r["knob"] for r in rs}):
            pts = [r for r in rs if r["knob"] == knob]
            ax.scatter([r["cost"] for r in pts], [y(r) for r in pts], marker=markers.get(knob, "o"), label=knob, alpha=0.8)
            for r in pts:
                ax.annotate(label(r, knob) + (" (reference)" if r["error"] == 0 else ""), (r["cost"], y(r)), fontsize=6, xytext=(3, 3), textcoords="offset points")
        front = sorted((r for r in rs if r["pareto"]), key=lambda r: r["cost"])
        ax.plot([r["cost"] for r in front], [y(r) for r in front], "k--", lw=1, label="Pareto front")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("cost: wall s per core for the answer (1 s settling + window)" if name in ("muller_window", "muller_profile_window",
                                                                                              "muller_profile_runs") else
                      "cost: wall s per simulated s per core")
        unc = [r for r in rs if (r.get("uncertainty") or 0) > 0]
        if unc:
            # the bar's lower end is clipped to the floor: an uncertainty larger than the error reaches zero
            ax.errorbar([r["cost"] for r in unc], [y(r) for r in unc],
                        yerr=[[y(r) - max(y(r) - r["uncertainty"], floor) for r in unc], [r["uncertainty"] for r in unc]], fmt="none",
                        ecolor="grey", lw=0.8)
        ax.set_ylabel("relative error")
        ax.set_title(name)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problems", default="bounce,head_on,packed", help="comma-separated: " + ", ".join(PROBLEMS))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "speed_accuracy"), help="working directory (kept: the study resumes)")
    ap.add_argument("--csv", default=os.path.join(ROOT, "docs", "speed_accuracy", "speed_accuracy.csv"))
    ap.add_argument("--png", default=os.path.join(ROOT, "docs", "figures", "speed_accuracy.png"))
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--exe", default=run.EXE)
    ap.add_argument("--fresh", action="store_true", help="run every point again (its cost measured anew), even if finished")
    ap.add_argument("--ci", action="store_true", help="the bounce at three time steps")
    ap.add_argument("--only", default="", help="comma-separated point ids (as in the table's id column) to run, in this order; default all")
    ap.add_argument("--keep-csv", action="store_true",
                    help="keep the rows of the existing --csv table that this run does not produce (a study continued on a fresh machine)")
    ap.add_argument("--report", action="store_true", help="tabulate and draw the finished points only (runs nothing)")
    ap.add_argument("--stability-csv", default=os.path.join(ROOT, "docs", "stability", "stability_map.csv"),
                    help="the stability map's table, whose 2D jetted-bed points are the jet2d problem's")
    ap.add_argument("--ratio-csv", default=os.path.join(ROOT, "docs", "stability", "pgrid_ratio.csv"),
                    help="the stability map's particle-grid ratio table (its --maps ratio, with its own reference run): jet2d points of knob pgrid_ratio")
    ap.add_argument("--kn-csv", default=os.path.join(ROOT, "docs", "stability", "kn_map.csv"),
                    help="the stability map's stiffness table (its --maps kn): jet2d points of knob kn")
    ap.add_argument("--muller-long", help="long runs of examples/muller_bed_u060.opts with gas snapshots every 0.05 s, comma-separated: the "
                    "profiles' reference (their mean; see muller above), the first one's series the windows'")
    args = ap.parse_args()
    problems = ["bounce"] if args.ci else args.problems.split(",")
    derived = "jet2d" in problems
    problems = [p for p in problems if p != "jet2d"]
    os.makedirs(args.out, exist_ok=True)

    def options_of(name, k):
        """A point's options; a problem whose runs start from a bed of its own (jet750) makes it in the study folder."""
        if PROBLEMS[name].get("needs_dir"):
            return PROBLEMS[name]["options"](k, args.out, args.exe)
        return PROBLEMS[name]["options"](k)

    def work(pt):
        name, knob, k = pt
        out = os.path.join(args.out, point_id(name, k))
        s, status, wall, reused = study.run(options_of(name, k), out, args.ranks, args.exe, fresh=args.fresh)
        row = {"problem": name, "knob": knob, "id": point_id(name, k), "status": s["status"] if s else "failed", "exit_status": status}
        row.update(k)
        if s and s["status"] != "stopped" and s["time"] > 0:
            res = PROBLEMS[name]["error"](out, k)  # (error, uncertainty[, more columns])
            row["error"], row["uncertainty"] = res[0], res[1]
            row.update(res[2] if len(res) > 2 else {})
            row["cost"], row["cpu_share"] = outputs.run_cost(s)
            row["steps"] = s["steps"]
            row["overlap_max"] = s.get("guard_figures", {}).get("overlap_max", float("nan"))
        else:
            row["error"], row["uncertainty"], row["cost"] = float("nan"), float("nan"), float("nan")
        return row, reused

    rows = []
    pts = points(problems, args.ci)
    if args.only:
        order = [x for x in args.only.split(",") if x]
        known = {point_id(pt[0], pt[2]): pt for pt in pts}
        unknown = [x for x in order if x not in known]
        if unknown:
            raise SystemExit("speed_accuracy.py: --only names no point of --problems %s: %s (known: %s)" % (",".join(problems), ",".join(unknown),
                                                                                                          ",".join(sorted(known))))
        pts = [known[x] for x in order]
    if args.report:
        pts = [pt for pt in pts if run.done(options_of(pt[0], pt[2]), os.path.join(args.out, point_id(pt[0], pt[2])), args.ranks, args.exe)]
    for pt, (row, reused) in study.run_all(pts, args.jobs, work):
        rows.append(row)
        study.log("%-60s error %.3e cost %.3g%s" % (row["id"], row["error"], row["cost"], " (reused)" if reused else ""))
        if (row["problem"] == "muller" and row["knob"] == "dt_factor" and pt[2] == PROBLEMS["muller"]["defaults"] and row["cost"] == row["cost"]
                and not args.muller_long):
            rows += muller_window_rows(os.path.join(args.out, row["id"]), row["cost"])
    if "muller" in problems:
        long_runs = [x for x in (args.muller_long or "").split(",") if x]
        rows += muller_profile_rows(rows, args.out, long_runs or None)
        if long_runs:
            # the windows are cut from the first long run; a run still going (or stopped without its summary), or one
            # that did not have its core to itself (processor share below 0.9, or not recorded), is costed as the
            # default point: the same settings
            first = long_runs[0]
            default_id = point_id("muller", PROBLEMS["muller"]["defaults"])
            default = [r["cost"] for r in rows if r["id"] == default_id]
            own = outputs.run_cost(outputs.summary(first)) if os.path.exists(os.path.join(first, "summary.json")) else (float("nan"), float("nan"))
            if own[1] >= 0.9 or (own[0] == own[0] and not default):
                cost = own[0]
            elif default:
                cost = default[0]
            else:
                raise SystemExit("speed_accuracy.py: %s has no summary.json, and the default Muller point has not run: no cost for its windows" % first)
            rows += muller_window_rows(first, cost, MULLER_LONG_WINDOWS) + muller_profile_window_rows(first, cost)
            if len(long_runs) > 1:
                rows += muller_long_rows(long_runs, cost)
    if derived:
        rows += jet2d_rows(args.stability_csv) + jet2d_rows(args.ratio_csv) + jet2d_rows(args.kn_csv)
    if args.keep_csv:
        have = set(r["id"] for r in rows)
        rows += study.kept_rows(args.csv, lambda r: r["id"] not in have)
        for r in rows:  # the kept rows' empty cells as the new rows have them
            for k in ("error", "uncertainty", "cost"):
                if r.get(k) is None:
                    r[k] = float("nan")
    pareto(rows)
    rows.sort(key=lambda r: (r["problem"], r["knob"], r["id"]))
    keys = ["problem", "knob", "id", "cell", "dt_factor", "kn", "substeps", "rtol", "pc_reuse", "window", "cells_x", "mirror", "status", "exit_status",
            "gas_substeps", "error", "uncertainty", "cost", "cpu_share", "steps", "overlap_max", "fountain", "dp", "v_jet", "err_fountain", "err_dp", "err_v_jet",
            "pareto"]
    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.4g" % r[k] if isinstance(r.get(k), float) else r.get(k, "")) for k in keys})
    if not args.ci:
        os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
        plot(rows, args.png)
    study.log("speed-accuracy: %d points; table %s" % (len(rows), args.csv))


if __name__ == "__main__":
    main()
