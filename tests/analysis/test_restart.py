"""Restart continuity of the averages: a run averaged from t = 5 ms is stopped at 20 ms with checkpoints and
continued from its checkpoint on 1 and on 2 ranks; analysis.h5 (every dataset: fields, profiles, series,
measures) agrees with the uninterrupted run's to 1e-12 relative to each dataset's largest value, and so do the
summary's averages (to their 10 printed digits). A coupled run with a jet (pressure drop and jet-height series)
continues the same way, to 1e-12, on 1 and on 2 ranks. A checkpoint written without averaging starts the averages at the restart;
so does -average_reset with a checkpoint that holds them, and with a later -average_start it writes the same analysis.h5,
to 1e-12, as one run averaged from that start."""
import os
import shutil

import numpy as np

import analysis_files as af
from fluidbed_tools import testing as t

dem = ["-insert_type", "random", "-insert_count", 2000, "-insert_velocity_random", 0.3, "-insert_seed", 5,
       "-average_start", 0.005, "-average_interval", 0.002, "-average_heights", "0.005,0.02"]
gas = ["-inlet_velocity", 0.1, "-inlet_jets", "0.01,0.0066666667,5",
       "-couple_substeps", 5, "-average_start", 0, "-average_interval", 5e-4, "-average_heights", "0.005"]


def replaced(args, option, *new):
    """args with `option` and its value replaced by `new` (options and values)."""
    i = args.index(option)
    return args[:i] + list(new) + args[i + 2:]


def compare(full, cont, label, limit):
    a, b = af.read(full), af.read(cont)
    t.check(sorted(a) == sorted(b), "%s: the same %d datasets" % (label, len(a)))
    worst, where = 0.0, ""
    for k in a:
        x, y = np.asarray(a[k], float), np.asarray(b[k], float)
        if x.shape != y.shape:
            t.fail("%s: %s shaped %s, uninterrupted %s" % (label, k, y.shape, x.shape))
        nan = np.isnan(x)
        if not np.array_equal(nan, np.isnan(y)):
            t.fail("%s: %s has NaN in other places" % (label, k))
        scale = np.max(np.abs(x[~nan])) if np.any(~nan) else 0.0
        err = np.max(np.abs(x[~nan] - y[~nan])) / scale if scale > 0 else np.max(np.abs(y[~nan]), initial=0.0)
        if err > worst:
            worst, where = err, k
    t.check(worst <= limit, "%s: analysis.h5 largest relative difference %.1e%s (limit %.0e)" % (label, worst, " in " + where if where else "", limit))
    sa, sb = t.summary(full)["averages"], t.summary(cont)["averages"]
    keys = [k for k in sa if k != "wall_time_s"]
    bad = [k for k in keys if abs(sa[k] - sb[k]) > max(limit, 5e-10) * abs(sa[k])]  # summary.json prints 10 digits
    t.check(not bad and sorted(sa) == sorted(sb), "%s: summary.json averages agree in %d keys%s" % (label, len(keys), " (differ: %s)" % bad if bad else ""))
    return a


def restart(opts, args, t_half, t_end, ranks_first, ranks_cont, tag, limit):
    # the uninterrupted run writes the same checkpoints (a checkpoint makes the next pressure solve rebuild its
    # preconditioner, so the gas repeats the run exactly only when both runs write them)
    full, _ = t.run(opts, args=args + ["-t_final", t_end, "-checkpoint_interval", t_half / 2], nprocs=ranks_first, outdir="avg_full_%s" % tag)
    first, _ = t.run(opts, args=args + ["-t_final", t_half, "-checkpoint_interval", t_half / 2], nprocs=ranks_first, outdir="avg_part_%s" % tag)
    results = []
    for m in ranks_cont:
        cont = "avg_cont_%s_%d" % (tag, m)
        if os.path.isdir(cont):
            shutil.rmtree(cont)
        shutil.copytree(first, cont)
        out, _ = t.run(opts, args=args + ["-t_final", t_end, "-checkpoint_interval", t_half / 2, "-restart", os.path.join(first, "checkpoint.h5")], nprocs=m, outdir=cont, clean=False)
        pa, pb = t.table(os.path.join(full, "particles.csv")), t.table(os.path.join(out, "particles.csv"))
        dv = max(np.max(np.abs(pa[c] - pb[c])) for c in ("vx", "vy", "vz")) / max(np.max(np.abs(pa[c])) for c in ("vx", "vy", "vz"))
        print("      %s: the particles' velocities differ from the uninterrupted run's by %.1e relative" % (tag, dv))
        results.append(compare(full, out, "%s: checkpoint from %d rank(s), continued on %d" % (tag, ranks_first, m), limit))
    return results


a = restart(None, dem, 0.02, 0.04, 1, (1, 2), "dem", 1e-12)[0]
ns = len(a["series/time"])
t.check(ns == 18 and abs(a["series/time"][0] - 0.005) < 1e-4, "dem: %d samples from t = %.4f s to %.4f s" % (ns, a["series/time"][0], a["series/time"][-1]))

# the coupled run continues bit for bit too (tests/io/test_coupled_restart.py), on 1 and 2 ranks
g = restart(t.example("coupling/small_bed.opts"), gas, 0.006, 0.012, 1, (1,), "gas", 1e-12)[0]
restart(t.example("coupling/small_bed.opts"), gas, 0.006, 0.012, 2, (2,), "gas2", 1e-12)
# and with two gas steps per DEM step (-couple_gas_substeps)
gas_sub = replaced(gas, "-couple_substeps", "-couple_substeps", 1, "-couple_gas_substeps", 2)
restart(t.example("coupling/small_bed.opts"), gas_sub, 0.006, 0.012, 1, (1,), "gas_sub", 1e-12)
t.check("series/pressure_drop" in g and "series/jet_height" in g and np.isfinite(g["series/pressure_drop"][1:]).all(),
        "gas: pressure drop and jet height series continue across the restart (%d samples, drop %.1f..%.1f Pa)"
        % (len(g["series/time"]), np.nanmin(g["series/pressure_drop"]), np.nanmax(g["series/pressure_drop"])))

# a checkpoint without averages: the restarted run starts them after the checkpoint's time
first, _ = t.run(None, args=dem[:6] + ["-t_final", 0.02, "-checkpoint_interval", 0.01], outdir="avg_plain_part")
out, p = t.run(None, args=dem + ["-t_final", 0.03, "-restart", os.path.join(first, "checkpoint.h5")], outdir="avg_plain_cont")
b = af.read(out)
t.check("the checkpoint holds none" in p.stdout and abs(b["series/time"][0] - 0.021) < 1e-4 and len(b["series/time"]) == 5,
        "no averages in the checkpoint: %d samples from t = %.4f s" % (len(b["series/time"]), b["series/time"][0]))

# -average_reset drops the checkpoint's averages (from 5 ms) and starts afresh after the checkpoint's time
part = os.path.join("avg_part_dem", "checkpoint.h5")
out_r, p = t.run(None, args=dem + ["-t_final", 0.03, "-restart", part, "-average_reset"], outdir="avg_reset_cont")
r = af.read(out_r)["series/time"]
t.check("dropped (-average_reset)" in p.stdout and len(r) == 5 and abs(r[0] - 0.021) < 1e-4,
        "-average_reset: %d samples from t = %.4f s" % (len(r), r[0]))
# or at a later -average_start: the same averages as a run made in one go with that start (the particles are the
# same across the restart, above)
later = replaced(dem, "-average_start", "-average_start", 0.025)
whole, _ = t.run(None, args=later + ["-t_final", 0.03, "-checkpoint_interval", 0.01], outdir="avg_later_whole")
out_l, _ = t.run(None, args=later + ["-t_final", 0.03, "-restart", part, "-average_reset"], outdir="avg_reset_later")
s_l = compare(whole, out_l, "-average_reset -average_start 0.025 against one run averaged from 0.025 s", 1e-12)["series/time"]
t.check(len(s_l) == 3 and abs(s_l[0] - 0.025) < 1e-4, "-average_reset -average_start 0.025: %d samples from t = %.4f s" % (len(s_l), s_l[0]))
