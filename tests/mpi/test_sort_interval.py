"""The particles' storage is sorted by neighbour bin only every -dem_sort_interval list rebuilds (0, the default: when
a particle may have moved one bin since the last sort, 2 (d_max + skin) / skin rebuilds). Nothing may depend on the
storage order: a pouring bed (many rebuilds) ends with the same particles.csv, as text, whether the storage is
sorted at every rebuild (the behaviour before the option), every third, automatically, or only at set-up, on 1 and 2
ranks; and summary.json counts the sorts the interval implies. The coupled 2D jetted bed on 2 ranks (the coupling
sums its cells in an order of its own, by cell and id) ends with the same particles and gas cells sorting at every
rebuild and only at set-up."""
import json
import os

from fluidbed_tools import testing as t

COMMON = ["-insert_count", "1500", "-max_steps", "4000", "-checkpoint_interval", "0", "-output_interval", "0", "-monitor_dt", "0"]
AUTO = 22  # 2 (1 + 0.1) / 0.1 at the default skin of 0.1 d

runs = {}
for ranks, interval in ((1, 1), (1, 0), (1, 3), (2, 0), (2, 3), (2, 1000)):
    name = "sort_np%d_i%d" % (ranks, interval)
    out, _ = t.run(t.example("dem/settle_box.opts"), args=COMMON + ["-dem_sort_interval", str(interval)], nprocs=ranks, outdir=name)
    summary = json.load(open(os.path.join(out, "summary.json")))
    runs[(ranks, interval)] = (open(os.path.join(out, "particles.csv")).read(), summary["neighbour_rebuilds"], summary["storage_sorts"])

ref, rebuilds, sorts = runs[(1, 1)]
t.check(rebuilds > AUTO, "the pour rebuilds its lists %d times (more than %d, so the automatic interval sorts after set-up too)" % (rebuilds, AUTO))
t.check(sorts == rebuilds, "-dem_sort_interval 1 sorts at every rebuild: %d sorts, %d rebuilds" % (sorts, rebuilds))
for (ranks, interval), (text, n_rebuilds, n_sorts) in runs.items():
    t.check(text == ref, "%d rank(s), -dem_sort_interval %d: particles.csv identical to 1 rank sorting at every rebuild" % (ranks, interval))
    t.check(n_rebuilds == rebuilds, "%d rank(s), -dem_sort_interval %d: %d rebuilds (the same as the reference's %d)" % (ranks, interval, n_rebuilds, rebuilds))
    every = {0: AUTO, 1: 1}.get(interval, interval)
    expect = 1 + (n_rebuilds - 1) // every  # the set-up rebuild always sorts
    t.check(n_sorts == expect, "%d rank(s), -dem_sort_interval %d: %d sorts in %d rebuilds, expected %d" % (ranks, interval, n_sorts, n_rebuilds, expect))
print("rebuilds %d; sorts: every rebuild %d, every 3 %d, automatic %d, set-up only %d" % (rebuilds, sorts, runs[(1, 3)][2], runs[(1, 0)][2], runs[(2, 1000)][2]))

coupled = []
for interval in (1, 1000):
    out, _ = t.run(t.example("jetted_bed_2d.opts"), args=["-max_steps", "400", "-dem_sort_interval", str(interval), "-checkpoint_interval", "0"], nprocs=2,
                   outdir="sort_jet2d_i%d" % interval)
    summary = json.load(open(os.path.join(out, "summary.json")))
    coupled.append((open(os.path.join(out, "particles.csv")).read(), open(os.path.join(out, "fluid_cells.csv")).read(), summary["storage_sorts"],
                    summary["neighbour_rebuilds"]))
t.check(coupled[0][3] > 1, "the jetted bed rebuilds its lists %d times in 400 steps" % coupled[0][3])
t.check(coupled[0][2] == coupled[0][3] and coupled[1][2] == 1, "jetted bed: %d and %d sorts" % (coupled[0][2], coupled[1][2]))
t.check(coupled[0][0] == coupled[1][0], "jetted bed, 2 ranks: particles.csv the same sorting at every rebuild and only at set-up")
t.check(coupled[0][1] == coupled[1][1], "jetted bed, 2 ranks: fluid_cells.csv the same sorting at every rebuild and only at set-up")
