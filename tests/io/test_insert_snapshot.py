"""A run starts from a saved moment of another: -insert_type file -insert_file takes a snapshot or checkpoint .h5 as
well as a CSV file. The particles a run starts with (its particles.csv after 0 steps, sorted by id) are those of the
file, to the last bit: positions, diameters, ids, velocities and spins, in 2D (the snapshot holds x, y) and 3D, on 1
and 2 ranks, from a snapshot and from a checkpoint, and on another gas grid than the run that wrote them (the use:
the same bed at a moment of a coarse-grid run, continued or solved again on a fine grid). A file without particles
stops with a message naming -insert_file and the missing dataset, and a nonzero exit."""
import os

import h5py
import numpy as np

from fluidbed_tools import testing as t


def particles_of(h5):
    with h5py.File(h5, "r") as f:
        p = f["particles"]
        order = np.argsort(p["id"][()])
        pos = p["position"][()][order]
        if pos.shape[1] == 2:
            pos = np.column_stack([pos, np.zeros(len(pos))])
        return {"id": p["id"][()][order].astype(int), "pos": pos, "d": p["diameter"][()][order], "v": p["velocity"][()][order],
                "w": p["omega"][()][order]}


def particles_csv(out):
    rows = t.table(os.path.join(out, "particles.csv"))
    order = np.argsort(rows["id"])
    col = lambda *names: np.column_stack([rows[n][order] for n in names])
    return {"id": rows["id"][order].astype(int), "pos": col("x", "y", "z"), "d": rows["d"][order], "v": col("vx", "vy", "vz"),
            "w": col("wx", "wy", "wz")}


scenes = [  # label, options file, steps of the first run, its output interval (s), options of the second run
    ("2D jetted bed", t.example("jetted_bed_2d.opts"), 60, 1e-4, ["-grid_nx", 66, "-grid_ny", 120, "-pgrid_ratio", "6,4"]),
    ("3D coupled bed", t.example("coupling/small_bed.opts"), 120, 2e-4, ["-grid_nx", 12, "-grid_ny", 36, "-grid_nz", 6, "-pgrid_ratio", "2"]),
]
for label, opts, steps, interval, regrid in scenes:
    first, _ = t.run(opts, args=["-max_steps", steps, "-output_interval", interval, "-checkpoint_interval", interval],
                     outdir="insert_h5_%s" % label.split()[0])
    snaps = sorted(f for f in os.listdir(first) if f.startswith("snapshot_") and f.endswith(".h5"))
    t.check(len(snaps) >= 3 and os.path.isfile(os.path.join(first, "checkpoint.h5")),
            "%s: the first run wrote %d snapshots and a checkpoint" % (label, len(snaps)))
    sources = [(snaps[-2], os.path.join(first, snaps[-2])), ("checkpoint.h5", os.path.join(first, "checkpoint.h5"))]
    for name, h5 in sources:
        want = particles_of(h5)
        moving = float(np.abs(want["v"]).max())
        for n in (1, 2):
            for grid in ([], regrid) if name != "checkpoint.h5" else ([],):
                out, _ = t.run(opts, args=["-insert_type", "file", "-insert_file", os.path.abspath(h5), "-max_steps", 0] + grid, nprocs=n,
                               outdir="insert_h5_%s_%d_%d" % (label.split()[0], n, len(grid)))
                got = particles_csv(out)
                same = len(got["id"]) == len(want["id"]) and all(np.array_equal(got[k], want[k]) for k in want)
                worst = {k: float(np.abs(got[k] - want[k]).max()) for k in want} if len(got["id"]) == len(want["id"]) else {}
                t.check(same and moving > 0, "%s, from %s on %d rank(s)%s: %d particles start as the file holds them (moving, up to %.3g "
                        "m/s), largest differences %s" % (label, name, n, ", gas grid %s" % "x".join(str(v) for v in grid[1::2] if isinstance(v, int)) if grid else "",
                                                         len(got["id"]), moving, worst))

# a file without /particles: the gas grid file of the 2D run
grid_file = os.path.join(os.path.abspath("insert_h5_2D"), "fluid_grid.h5")
for n in (1, 2):
    _, p = t.run(t.example("jetted_bed_2d.opts"), args=["-insert_type", "file", "-insert_file", grid_file, "-max_steps", 0], nprocs=n,
                 outdir="insert_h5_bad_%d" % n, expect_fail=True)
    text = p.stdout + p.stderr
    line = next((l for l in text.splitlines() if "-insert_file" in l and "error" in l), "")
    t.check(p.returncode != 0 and "/particles/position" in line and "Segmentation" not in text and "signal" not in text.lower(),
            "%d rank(s): a file without particles stops (status %d): %s" % (n, p.returncode, line.strip()))
