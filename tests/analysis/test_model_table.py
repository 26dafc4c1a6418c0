"""What a scene models: the start-up table of what is active and why, summary.json's "model" and "model_warnings", and
each warning where a scene asks for more than it can use or less than it needs, provoked by a scene built for it
(the default scene or small_bed with one option changed, one step each). The default scene and the shipped scenes
below warn of nothing; tsuji_jet does (its single grid has cells of 2.5 d, Tsuji et al.'s own grid)."""
from fluidbed_tools import testing as t

jet2d = t.example("jetted_bed_2d.opts")
one = ["-max_steps", 1]
ROWS = ["particles", "gas", "dimension", "rotation", "contact", "drag", "grids", "gas step", "pressure", "guards", "averaging",
        "output", "heat", "periodic", "outlet"]


def table(p):
    """The table's rows as {feature: line}, read between its title and the first line after it."""
    lines = p.stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Model: what this scene simulates"))
    rows = {}
    for line in lines[start + 2:]:
        if not line.startswith("  "):
            break
        for name in ROWS:
            if line[2:].startswith(name + " "):
                rows[name] = line
    return rows


def warnings(p):
    return [line[len("WARNING: "):] for line in p.stdout.splitlines() if line.startswith("WARNING: ")]


def close(a, b, tol=1e-6):
    return len(a) == len(b) and all(abs(x - y) <= tol * max(1.0, abs(y)) for x, y in zip(a, b))


# The default scene: every row once, before the run starts; summary.json says 2D, planar, two grids of 3 x 2 fluid
# cells per particle cell, particle cells of 3 d (the z entry is the 1 mm depth), and warns of nothing.
out, p = t.run(jet2d, args=one, outdir="model_default")
rows, s = table(p), t.summary(out)
m = s["model"]
t.check(list(rows) == ROWS, "default scene: the table has the rows %s" % list(rows))
t.check(p.stdout.index("Model: what") < p.stdout.index("Running "), "the table is printed before the run starts")
t.check("two: 3 x 2 fluid cells per particle cell of 3 x 3 d" in rows["grids"] and "-pgrid_ratio 3,2" in rows["grids"],
        "grids row: %s" % rows["grids"].strip())
t.check("not modelled" in rows["heat"] and rows["periodic"].split()[1] == "off", "heat and periodic rows: off")
t.check("-domain_top_outlet -fluid_bc_yhi outlet" in rows["outlet"], "outlet row names its options: %s" % rows["outlet"].strip())
t.check(m["dim"] == 2 and m["planar"] is True and m["gas"] is True and m["particles"] == 900,
        "model: dim %s, planar %s, gas %s, %s particles" % (m["dim"], m["planar"], m["gas"], m["particles"]))
t.check(m["grid"] == "two" and m["fluid_cells_per_particle_cell"] == [3, 2, 1] and close(m["particle_cell_diameters"], [3, 3, 1]),
        "model: grid %s, %s fluid cells per particle cell, particle cells %s d" % (m["grid"], m["fluid_cells_per_particle_cell"],
                                                                                 m["particle_cell_diameters"]))
t.check(m["substeps"] == 1 and m["drag_model"] == "ergun_wenyu" and m["contact"] == "linear spring-dashpot" and m["k_n"] == 800
        and m["e"] == 0.9 and m["mu"] == 0.1, "model: substeps, drag, contact %s k_n %s e %s mu %s" % (m["contact"], m["k_n"], m["e"], m["mu"]))
t.check(m["pressure_ksp"] == "cg" and m["pressure_pc"] == "fastpoisson" and m["guards"] == "stop" and m["averaging"] is False,
        "model: pressure %s + %s, guards %s, averaging %s" % (m["pressure_ksp"], m["pressure_pc"], m["guards"], m["averaging"]))
t.check(m["heat"] is False and m["periodic"] == [False, False, False] and m["outlet"] is True and m["gas_outlet"] == "outlet",
        "model: heat %s, periodic %s, outlet %s (%s)" % (m["heat"], m["periodic"], m["outlet"], m["gas_outlet"]))
t.check(warnings(p) == [] and s["model_warnings"] == [], "default scene: no warning (%s)" % warnings(p))

# A 3D two-grid scene (the seed's 750 um bed) and a particles-only one.
out, p = t.run(t.example("twogrid_750_jet1_u301.opts"), args=one, outdir="model_750")
m, s = t.summary(out)["model"], t.summary(out)
t.check(m["dim"] == 3 and m["planar"] is False and m["grid"] == "two" and m["fluid_cells_per_particle_cell"] == [7, 2, 5]
        and close(m["particle_cell_diameters"], [0.0564 / 25 / 7.5e-4, 0.28 / 100 / 7.5e-4, 0.00495 / 7.5e-4]),
        "750 bed: dim %s, %s fluid cells per particle cell, particle cells %s d" % (m["dim"], m["fluid_cells_per_particle_cell"],
                                                                                m["particle_cell_diameters"]))
t.check(m["averaging"] is True and m["averaging_start"] == 5 and m["snapshot_interval"] == 0.1 and m["checkpoint_interval"] == 0.5,
        "750 bed: averaging from %s s, snapshots %s s, checkpoints %s s" % (m.get("averaging_start"), m["snapshot_interval"],
                                                                          m["checkpoint_interval"]))
t.check(warnings(p) == [] and s["model_warnings"] == [], "750 bed (slit of 5 gas cells): no warning (%s)" % warnings(p))

for scene, grid in (("dem/settle_box.opts", "particles only"), ("coupling/small_bed.opts", "single")):
    out, p = t.run(t.example(scene), args=one, outdir="model_quiet")
    s = t.summary(out)
    t.check(s["model"]["grid"] == grid and warnings(p) == [] and s["model_warnings"] == [],
            "%s: grid %s, no warning (%s)" % (scene, s["model"]["grid"], warnings(p)))
t.check(s["model"]["drag_model"] == "ergun_wenyu" and s["model"]["substeps"] == 20, "small_bed: 20 DEM steps per gas step")


def provoke(name, scene, args, expect, also=()):
    """Runs the scene with args; the warnings must be exactly one containing every word of expect (plus one per entry
    of also), printed once, before the run, and listed in summary.json."""
    out, p = t.run(scene, args=one + list(args), outdir="model_warn")
    w, listed = warnings(p), t.summary(out)["model_warnings"]
    hits = [x for x in w if all(e in x for e in expect)]
    t.check(len(hits) == 1 and len(w) == 1 + len(also) and all(any(a in x for x in w) for a in also),
            "%s: %s" % (name, hits[0] if hits else "MISSING; warnings: %s" % w))
    t.check(sorted(listed) == sorted(w) and all(x.endswith("the run goes on") for x in w), "%s: in summary.json, the run goes on" % name)
    t.check(p.stdout.index("WARNING: " + hits[0]) < p.stdout.index("Running "), "%s: printed at start-up" % name)
    return out, p


# A 3D gas grid 3 cells deep on a bed 1.5 d deep.
provoke("deep gas grid", jet2d, ["-domain_dim", 3, "-domain_lz", 0.0015, "-grid_nz", 3, "-pgrid_ratio", "3,2,3",
                                 "-insert_region", "0,0.033,0,0.060,0,0.0015"],
        ["-grid_nz 3", "one particle deep", "1.5 d", "use -grid_nz 1"])
# A single grid of the default scene's 1 x 1.5 mm gas cells: below 3 d, and 1.7 particles per cell.
provoke("single grid", jet2d, ["-couple_grid", "single"],
        ["single grid", "1 x 1.5 d", "along x, y", "-grid_nx at most 11", "-couple_grid two -pgrid_ratio 3,2"],
        also=["holds about 1.72 particles"])
# The shipped Tsuji jet: cells of 2.5 d along x (14 particles per cell, enough).
provoke("single grid, tsuji_jet", t.example("tsuji_jet.opts"), [], ["single grid", "2.5 x 5 d", "along x:", "-grid_nx at most 12"])
# Particle cells of 3 x 1.5 x 1 mm hold 5 particles at packing.
provoke("few particles per cell", jet2d, ["-pgrid_ratio", "3,1"],
        ["holds about 5.16 particles", "fewer than 10", "-pgrid_ratio 3,2", "about 10.3 particles", "-domain_lz"])
# A step of 0.01 t_cr costs 10 times the steps of 0.1 t_cr.
provoke("short DEM step", jet2d, ["-dem_dt_factor", 0.01], ["-dem_dt_factor 0.01", "10 times the steps", "use -dem_dt_factor 0.1"])
# A 7 mm slit on 1 mm gas cells, and 0.69 d gas cells without any slit.
provoke("slit over-resolved", jet2d, ["-inlet_jets", "0.0165,0.007,25"], ["7 mm wide", "7 gas cells", "-grid_nx at most 23"])
provoke("fine gas cells without a slit", t.example("coupling/small_bed.opts"), ["-grid_nx", 24, "-pgrid_ratio", "4,1,1"],
        ["0.694 d along x", "no -inlet_jets", "-grid_nx at most 16"])
# Averaging that never starts: warned of once, at start-up (not again at the end), and still an unused option.
out, p = provoke("averaging after the end", jet2d, ["-average_start", 1], ["option -average_start 1 is at or after -t_final 0.25 s"])
t.check(p.stdout.count("-average_start 1 is at") == 1 and "-average_start" in t.summary(out)["unused_options"],
        "averaging after the end: printed once, in unused_options %s" % t.summary(out)["unused_options"])
out, p = provoke("averaging options without -average", jet2d, ["-average_interval", 0.01],
                 ["option -average_interval 0.01 has no effect: averaging is off", "add -average"])
t.check(t.summary(out)["unused_options"] == ["-average_interval"], "-average_interval: unused_options %s" % t.summary(out)["unused_options"])
