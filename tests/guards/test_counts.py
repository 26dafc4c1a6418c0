"""Particle counts agree everywhere: inserted = present + left through the outlet (+ lost), in the Done line,
summary.json, the last row of monitor.csv and particles.csv, with checkpoints on or off, uninterrupted and restarted,
on 1 and 2 ranks. A particle past the outlet is removed in the step it crosses, so no file ever holds one above it.

The scene: 300 spheres in a 10 x 20 x 10 mm box without gravity, random velocities up to 1 m/s per component, the top
an outlet: about a third leave within 40 ms."""
import os
import re

from fluidbed_tools import testing as t

scene = ["-domain_lx", "0.01", "-domain_ly", "0.02", "-domain_lz", "0.01", "-domain_top_outlet", "-gravity", "0,0,0",
         "-particle_diameter", "1e-3", "-insert_type", "random", "-insert_count", "300", "-insert_velocity_random", "1.0",
         "-insert_seed", "5", "-t_final", "0.04", "-monitor_dt", "0.001"]


def counts(out, stdout):
    s = t.summary(out)
    m = t.table(os.path.join(out, "monitor.csv"))
    rows = open(os.path.join(out, "particles.csv")).read().splitlines()[1:]
    ys = [float(r.split(",")[3]) for r in rows]
    done = re.search(r"Done: .* (\d+) particles \((\d+) left through the outlet\)", stdout)
    c = {"inserted": s["particles_inserted"], "present": s["particles"], "outlet": s["particles_outlet"], "lost": s["particles_lost"],
         "monitor_present": int(m["particles"][-1]), "monitor_outlet": int(m["outlet_removed"][-1]), "csv_rows": len(rows),
         "done_present": int(done.group(1)), "done_outlet": int(done.group(2)), "csv_max_y": max(ys)}
    return c


def agree(name, c):
    t.check(c["outlet"] > 0, "%s: %d particles left through the outlet" % (name, c["outlet"]))
    t.check(c["inserted"] == 300 and c["inserted"] == c["present"] + c["outlet"] + c["lost"],
            "%s: inserted %d = present %d + outlet %d + lost %d" % (name, c["inserted"], c["present"], c["outlet"], c["lost"]))
    same = {c["present"], c["monitor_present"], c["csv_rows"], c["done_present"]}
    t.check(len(same) == 1, "%s: present %d (summary) = %d (monitor.csv) = %d (particles.csv) = %d (Done)"
            % (name, c["present"], c["monitor_present"], c["csv_rows"], c["done_present"]))
    t.check(c["outlet"] == c["monitor_outlet"] == c["done_outlet"], "%s: outlet %d (summary) = %d (monitor.csv) = %d (Done)"
            % (name, c["outlet"], c["monitor_outlet"], c["done_outlet"]))
    t.check(c["csv_max_y"] < 0.02, "%s: highest particle in particles.csv at y = %.6f m, below the outlet at 0.02 m" % (name, c["csv_max_y"]))


reference = None
for n in (1, 2):
    for ck in (False, True):
        name = "outlet_%d%s" % (n, "_checkpoints" if ck else "")
        out, p = t.run(None, args=scene + (["-checkpoint_interval", "0.01"] if ck else []), outdir=name, nprocs=n)
        c = counts(out, p.stdout)
        agree(name, c)
        reference = reference or c
        t.check(c == reference, "%s: the same counts as the first run (pure DEM is rank-independent)" % name)
    # stopped at 20 ms, then continued from the checkpoint to 40 ms in the same directory
    name = "outlet_%d_restarted" % n
    t.run(None, args=scene + ["-checkpoint_interval", "0.01", "-t_final", "0.02"], outdir=name, nprocs=n)
    out, p = t.run(None, args=scene + ["-checkpoint_interval", "0.01", "-restart", os.path.join(name, "checkpoint.h5")], outdir=name, nprocs=n,
                   clean=False)
    c = counts(out, p.stdout)
    agree(name, c)
    t.check(c == reference, "%s: the same counts as the uninterrupted run (%d present, %d out)" % (name, c["present"], c["outlet"]))
