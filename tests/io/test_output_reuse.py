"""A run into a directory that holds a previous run's files never mixes with them, on 1 and 2 ranks.

- A fresh run removes the previous run's files first (snapshots, XDMF series, averages, checkpoint and temporaries,
  monitor.csv, track.csv, particles.csv, fluid_cells.csv, summary.json, guard diagnostics) and says so in one line;
  afterwards the directory lists exactly what the same run writes into an empty one, plus the user's own files.
- A particle file the run reads (-insert_file) is never removed, even when it is the previous run's particles.csv.
- A restart in the directory of the run it continues removes the snapshots that run wrote after the checkpoint and
  the monitor.csv / track.csv rows after its step; the XDMF series lists only snapshots that exist."""
import os
import re
import shutil
import xml.etree.ElementTree as ET

import h5py

from fluidbed_tools import testing as t

SCENE = t.example("jetted_bed_2d.opts")
FIRST = ["-max_steps", 60, "-output_interval", 1e-4, "-checkpoint_interval", 3e-4, "-average", "-average_start", 0, "-fluid_output_cells",
         "-monitor_track_ids", "1,2"]
SECOND = ["-max_steps", 25, "-output_interval", 2e-4]


def listing(d):
    return sorted(os.listdir(d))


def series(d):
    """The files particles.xmf and fluid.xmf point at."""
    files = set()
    for x in ("particles.xmf", "fluid.xmf"):
        if os.path.exists(os.path.join(d, x)):
            files |= {item.text.strip().split(":")[0] for item in ET.parse(os.path.join(d, x)).getroot().iter("DataItem") if ":" in (item.text or "")}
    return files


def removal_line(p):
    return next((line for line in p.stdout.splitlines() if line.startswith("Output: removed")), "")


for n in (1, 2):
    fresh, used = "fresh_%d" % n, "used_%d" % n
    t.run(SCENE, args=SECOND, nprocs=n, outdir=fresh)
    t.run(SCENE, args=FIRST, nprocs=n, outdir=used)
    first = listing(used)
    # a user's files, and stale names left by some earlier failure, next to the first run's
    open(os.path.join(used, "notes.txt"), "w").write("my notes\n")
    os.makedirs(os.path.join(used, "mydata"), exist_ok=True)
    open(os.path.join(used, "mydata", "monitor.csv"), "w").write("kept\n")
    for stale in ("guard_failure.h5", "snapshot_00077.h5.tmp", "summary.json.tmp"):
        open(os.path.join(used, stale), "w").write("stale\n")
    t.check({"checkpoint.h5", "analysis.h5", "analysis.xmf", "fluid_cells.csv", "track.csv", "fluid.xmf"} <= set(first),
            "%d rank(s): the first run wrote %d files: %s" % (n, len(first), ", ".join(first)))

    _, p = t.run(SCENE, args=SECOND, nprocs=n, outdir=used, clean=False)
    line = removal_line(p)
    count = re.search(r"removed (\d+) file", line)
    t.check(count and int(count.group(1)) == len(first) + 3 and "checkpoint.h5" in line and "guard_failure.h5" in line,
            "%d rank(s): %s" % (n, line or "(no removal line)"))
    t.check(listing(used) == sorted(listing(fresh) + ["mydata", "notes.txt"]),
            "%d rank(s): the used directory now lists the second run's files and the user's: %s" % (n, ", ".join(listing(used))))
    t.check(open(os.path.join(used, "notes.txt")).read() == "my notes\n" and open(os.path.join(used, "mydata", "monitor.csv")).read() == "kept\n",
            "%d rank(s): the user's file and directory are untouched" % n)
    # the series' snapshots (fluid.xmf of a 2D run also points at the grid's node file, fluid_grid.h5)
    t.check(series(used) - {"fluid_grid.h5"} == {f for f in listing(used) if f.startswith("snapshot_")},
            "%d rank(s): the XDMF series lists exactly the snapshots present: %s" % (n, sorted(series(used))))
    times = [float(h5py.File(os.path.join(d, "snapshot_00001.h5"), "r").attrs["time"]) for d in (used, fresh)]
    t.check(t.table(os.path.join(used, "monitor.csv"))["step"][-1] == 25 and times[0] == times[1],
            "%d rank(s): monitor.csv and the snapshots are the second run's (snapshot_00001.h5 at t = %.3g s, as in the empty directory)"
            % (n, times[0]))

    # a fresh run in an empty directory prints no removal line
    _, p = t.run(SCENE, args=SECOND, nprocs=n, outdir="empty_%d" % n)
    t.check(not removal_line(p), "%d rank(s): nothing to remove in a new directory, no line" % n)

    # the previous run's particles.csv as this run's input
    _, p = t.run(None, args=["-insert_count", 200, "-max_steps", 10], nprocs=n, outdir="pour_%d" % n)
    _, p = t.run(None, args=["-insert_type", "file", "-insert_file", "pour_%d/particles.csv" % n, "-max_steps", 10], nprocs=n,
                 outdir="pour_%d" % n, clean=False)
    line = removal_line(p)
    t.check("particles.csv" not in line and "monitor.csv" in line and t.summary("pour_%d" % n)["particles"] == 200,
            "%d rank(s): -insert_file in the output directory is read and kept: %s" % (n, line))

    # a restart in the directory of the run it continues, from a checkpoint older than that run's end
    run_dir, ck = "cont_%d" % n, "cont_%d_ck.h5" % n
    dem = ["-insert_count", 200, "-output_interval", 1e-4, "-checkpoint_interval", 4e-4, "-monitor_dt", 0, "-monitor_track_ids", "1,2"]
    t.run(None, args=dem + ["-max_steps", 50], nprocs=n, outdir=run_dir)
    shutil.copy(os.path.join(run_dir, "checkpoint.h5"), ck)
    t.run(None, args=dem + ["-t_final", 9e-4, "-restart", ck], nprocs=n, outdir=run_dir, clean=False)
    before = {f for f in listing(run_dir) if f.startswith("snapshot_")}
    _, p = t.run(None, args=dem + ["-t_final", 7e-4, "-restart", ck], nprocs=n, outdir=run_dir, clean=False)
    after = {f for f in listing(run_dir) if f.startswith("snapshot_")}
    removed = next((line for line in p.stdout.splitlines() if "written after the checkpoint" in line), "")
    dropped = [line for line in p.stdout.splitlines() if line.startswith("Output: dropped")]
    t.check(removed and after < before and series(run_dir) == after,
            "%d rank(s): restart in place: %d snapshots before, %d after; %s" % (n, len(before), len(after), removed or "(no removal line)"))
    for name in ("monitor.csv", "track.csv"):
        steps = t.table(os.path.join(run_dir, name))["step"]
        unique = sorted(set(steps)) == list(steps) if name == "monitor.csv" else all(a <= b for a, b in zip(steps, steps[1:]))
        t.check(unique and steps[-1] == t.summary(run_dir)["steps"] and any(name in d for d in dropped),
                "%d rank(s): %s continues at the checkpoint's step, ends at step %d: %s" % (n, name, steps[-1], "; ".join(dropped)))
