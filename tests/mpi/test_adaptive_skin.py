"""The adaptive skin (-dem_skin_adaptive): each particle's share of its pairs' skin is its speed at the rebuild times
twice the last interval between rebuilds, between the halves of -dem_skin_min and -dem_skin, and the lists are rebuilt once a particle has
moved its own share. Every contact then stays listed between rebuilds, and the forces are summed in partner-id order
whatever the lists hold, so the answers may not change: a pour (many collisions, particles from rest to falling
fast) ends with the same particles.csv, as text, with the uniform 0.1 d skin and with adaptive skins on 1 and 2
ranks; the adaptive lists, whose fast particles have up to 0.3 d, are rebuilt less often. A trigger that waited for
the largest share instead of each particle's own would miss contacts of slow particles and change the text. The
coupled 2D jetted bed on 2 ranks (a fast jet beside a packed bed) ends with the same particles and gas cells."""
import json
import os

from fluidbed_tools import testing as t

COMMON = ["-insert_count", "1500", "-max_steps", "4000", "-checkpoint_interval", "0", "-output_interval", "0", "-monitor_dt", "0"]
ADAPTIVE = {"a": ["-dem_skin", "0.6", "-dem_skin_adaptive", "-dem_skin_min", "0.1"],
            "a_slow": ["-dem_skin", "0.6", "-dem_skin_adaptive", "-dem_skin_min", "0.03"]}


def run(scene, args, ranks, name):
    out, _ = t.run(t.example(scene), args=args, nprocs=ranks, outdir=name)
    summary = json.load(open(os.path.join(out, "summary.json")))
    return out, summary


runs = {}
for ranks, kind in ((1, "uniform"), (1, "a"), (1, "a_slow"), (2, "a")):
    out, summary = run("dem/settle_box.opts", COMMON + ADAPTIVE.get(kind, []), ranks, "skin_np%d_%s" % (ranks, kind))
    runs[(ranks, kind)] = (open(os.path.join(out, "particles.csv")).read(), summary["neighbour_rebuilds"])

ref, ref_rebuilds = runs[(1, "uniform")]
t.check(ref_rebuilds > 20, "the pour rebuilds its lists %d times with the uniform 0.1 d skin" % ref_rebuilds)
for (ranks, kind), (text, rebuilds) in runs.items():
    t.check(text == ref, "%d rank(s), skin %s: particles.csv identical to the uniform skin on 1 rank" % (ranks, kind))
    if kind != "uniform":
        t.check(rebuilds < ref_rebuilds, "%d rank(s), skin %s: %d rebuilds, fewer than the uniform skin's %d" % (ranks, kind, rebuilds, ref_rebuilds))
print("rebuilds: uniform %d, adaptive %d, adaptive with 0.03 d for slow particles %d" % (ref_rebuilds, runs[(1, "a")][1], runs[(1, "a_slow")][1]))

coupled = []
for kind in ("uniform", "a"):
    out, summary = run("jetted_bed_2d.opts", ["-max_steps", "400", "-checkpoint_interval", "0"] + ADAPTIVE.get(kind, []), 2, "skin_jet2d_%s" % kind)
    coupled.append((open(os.path.join(out, "particles.csv")).read(), open(os.path.join(out, "fluid_cells.csv")).read(), summary["neighbour_rebuilds"]))
t.check(coupled[0][2] > 1, "the jetted bed rebuilds its lists %d times in 400 steps" % coupled[0][2])
t.check(coupled[0][0] == coupled[1][0], "jetted bed, 2 ranks: particles.csv the same with the uniform and the adaptive skin")
t.check(coupled[0][1] == coupled[1][1], "jetted bed, 2 ranks: fluid_cells.csv the same with the uniform and the adaptive skin")
print("jetted bed rebuilds: uniform %d, adaptive %d" % (coupled[0][2], coupled[1][2]))
