"""-pgrid_layout particles shares a lopsided bed among the ranks, and the results do not depend on the layout.

A 2D box 42 x 120 mm holds a heap of 1 mm particles in its bottom-left corner only (x < 21 mm, y < 12 mm): a bed in
the bottom tenth of a tall box that also fills only half its width. The default horizontal layout splits x alone,
so on 4 ranks two ranks hold almost nothing; the particles layout chooses the process grid and the ownership ranges
from the particles' positions (read from the -insert_file before the grids exist). Checks, on 2 and 4 ranks:
- the particles layout's busiest rank holds at most 15% more than the mean (the whole particle cells of about 3 d
  set the granularity), and fewer than the horizontal layout's;
- summary.json names the layout;
- the particles after 150 DEM steps of the heap collapsing are identical, as text, to those of 1 rank: the
  decomposition does not change a result;
- with -insert_type lattice (positions not known before insertion) the layout falls back to horizontal, saying so.
"""
import os

from fluidbed_tools import testing as t

# the heap: a jittered lattice, written as an insertion file
import random

rng = random.Random(3)
rows = ["x,y,z,d"]
d, gap = 1.0e-3, 1.05e-3
for j in range(11):
    for i in range(19):
        x = 0.6e-3 + i * gap + rng.uniform(-1e-5, 1e-5)
        y = 0.6e-3 + j * gap + rng.uniform(-1e-5, 1e-5)
        rows.append("%.9e,%.9e,0,%.9e" % (x, y, d))
os.makedirs("layout_particles", exist_ok=True)
heap = os.path.abspath("layout_particles/heap.csv")
open(heap, "w").write("\n".join(rows) + "\n")
n = len(rows) - 1

common = ["-domain_dim", "2", "-domain_lx", "0.042", "-domain_ly", "0.12", "-particle_diameter", "1e-3", "-particle_density", "2500",
          "-dem_kn", "800", "-dem_e", "0.9", "-dem_mu", "0.3", "-insert_type", "file", "-insert_file", heap, "-max_steps", "150",
          "-progress_interval", "0", "-output_particles", "1"]


def imbalance(s):
    per = s["decomposition"]["particles_per_rank"]
    return max(per) / (sum(per) / len(per)), per


ref_dir, _ = t.run(None, args=common, nprocs=1, outdir="layout_particles/r1")
ref = open(os.path.join(ref_dir, "particles.csv")).read()
for ranks in (2, 4):
    hdir, _ = t.run(None, args=common + ["-pgrid_layout", "horizontal"], nprocs=ranks, outdir="layout_particles/h%d" % ranks)
    pdir, _ = t.run(None, args=common + ["-pgrid_layout", "particles"], nprocs=ranks, outdir="layout_particles/p%d" % ranks)
    sh, sp = t.summary(hdir), t.summary(pdir)
    ih, per_h = imbalance(sh)
    ip, per_p = imbalance(sp)
    print("%d ranks: horizontal %s %s (imbalance %.3f); particles %s %s (imbalance %.3f)" %
          (ranks, sh["decomposition"]["process_grid"], per_h, ih, sp["decomposition"]["process_grid"], per_p, ip))
    t.check(sp["decomposition"]["layout"] == "particles", "%d ranks: summary.json names the particles layout" % ranks)
    t.check(ip <= 1.15, "%d ranks: the particles layout's busiest rank %.3f x the mean (at most 1.15)" % (ranks, ip))
    t.check(ip < ih, "%d ranks: more even than the horizontal layout (%.3f against %.3f)" % (ranks, ip, ih))
    for name, dd in (("horizontal", hdir), ("particles", pdir)):
        same = open(os.path.join(dd, "particles.csv")).read() == ref
        t.check(same, "%d ranks, %s layout: particles.csv after 150 steps identical to 1 rank's (%d particles)" % (ranks, name, n))

lat = ["-domain_dim", "2", "-domain_lx", "0.042", "-domain_ly", "0.12", "-particle_diameter", "1e-3", "-insert_count", "200",
       "-max_steps", "5", "-progress_interval", "0", "-pgrid_layout", "particles"]
ldir, p = t.run(None, args=lat, nprocs=2, outdir="layout_particles/lattice")
t.check("horizontal layout is used" in p.stdout and t.summary(ldir)["decomposition"]["layout"] == "horizontal",
        "lattice insertion: the particles layout falls back to horizontal and says so")
print("PASS")
