"""Options without effect are listed in a warning line each, and in summary.json ("unused_options"): at the end of a
run a misspelled option, 3D options in a 2D run, a gas option in a run without gas; at start-up, with the scene
model's warnings, -average_start at or after -t_final (printed once); in a restart the insertion options, as without
effect there. A normal run, PETSc's own options that it reads
in PetscFinalize (-options_left) and -help give no such warning."""
import os

from fluidbed_tools import testing as t

jet2d = t.example("jetted_bed_2d.opts")  # the default scene: 2D, gas and particles
settle = t.example("dem/settle_box.opts")  # 3D, particles only
short = ["-max_steps", 2]


def warnings(p):
    return [line for line in p.stdout.splitlines() if line.startswith("WARNING: option")]


# A normal run of each scene warns of nothing, on 1 and 2 ranks.
for scene in (jet2d, settle):
    for nprocs in (1, 2):
        out, p = t.run(scene, args=short, nprocs=nprocs, outdir="unused_none")
        w, listed = warnings(p), t.summary(out)["unused_options"]
        t.check(not w and listed == [], "%s on %d rank(s): %d warnings, unused_options %s" % (os.path.basename(scene), nprocs, len(w), listed))

# Each kind of option without effect, in a 2D run with the gas.
given = ["-dem_kn_typo", 5, "-grid_nz", 4, "-domain_periodic_z", "-gravity", "0,-9.81,1", "-average_start", 1, "-fluid_bc_zlo", "noslip"]
expect = {
    "-dem_kn_typo": "WARNING: option -dem_kn_typo 5 was not used (misspelled, or no effect in this scene)",
    "-fluid_bc_zlo": "WARNING: option -fluid_bc_zlo noslip was not used",
    "-grid_nz": "WARNING: option -grid_nz 4 has no effect in a 2D run (-domain_dim 2)",
    "-domain_periodic_z": "WARNING: option -domain_periodic_z has no effect in a 2D run",
    "-gravity": "WARNING: option -gravity 0,-9.81,1 has a z component that has no effect in a 2D run",
    "-average_start": "WARNING: option -average_start 1 is at or after -t_final 0.25 s",
}
for nprocs in (1, 2):
    out, p = t.run(jet2d, args=short + given, nprocs=nprocs, outdir="unused_2d")
    w, listed = warnings(p), t.summary(out)["unused_options"]
    missing = [k for k, line in expect.items() if not any(x.startswith(line) for x in w)]
    t.check(not missing and len(w) == len(expect), "2D on %d rank(s): %d warnings (once each), missing %s" % (nprocs, len(w), missing))
    t.check(sorted(listed) == sorted(expect), "2D on %d rank(s): summary.json unused_options %s" % (nprocs, listed))
    t.check(p.stdout.rstrip().endswith(w[-1]), "the warnings end the output")

# The same options where they do have an effect are not listed: -grid_nz and -domain_periodic_z in 3D.
out, p = t.run(settle, args=short + ["-grid_nz", 6, "-domain_periodic_z"], outdir="unused_3d")
t.check(not warnings(p) and t.summary(out)["unused_options"] == [], "3D with -grid_nz, -domain_periodic_z: %s" % warnings(p))

# A gas solver option in a particles-only run has no effect.
out, p = t.run(settle, args=short + ["-fluid_p_ksp_type", "cg"], outdir="unused_gas")
t.check(t.summary(out)["unused_options"] == ["-fluid_p_ksp_type"] and len(warnings(p)) == 1, "-fluid_p_ksp_type without -fluid: %s" % warnings(p))

# PETSc's -options_left (read in PetscFinalize, after the list is made) and -log_view are not reported; -options_left
# itself still lists the misspelled option.
out, p = t.run(settle, args=short + ["-options_left", "-log_view", "ascii:%s" % os.path.abspath("log_view.txt"), "-dem_kn_typo", 5],
               outdir="unused_petsc")
t.check([x.split()[2] for x in warnings(p)] == ["-dem_kn_typo"] and "Option left: name:-dem_kn_typo" in p.stdout,
        "-options_left -log_view: warnings %s" % warnings(p))

# -help prints the options and runs the scene: no warning either.
out, p = t.run(settle, args=short + ["-help"], outdir="unused_help")
t.check(not warnings(p) and "-dem_kn <" in p.stdout, "-help: %d warnings" % len(warnings(p)))

# A run continued from a checkpoint keeps its first command's insertion options (scripts/validate.sh continues that
# way): they are listed as having no effect in a restart, not as misspelled; a misspelled option still is.
first, _ = t.run(settle, args=short + ["-checkpoint_interval", 1], outdir="unused_first")
ck = os.path.join(os.path.abspath(first), "checkpoint.h5")
out, p = t.run(settle, args=["-max_steps", 4, "-restart", ck, "-dem_kn_typo", 5], outdir="unused_restart")
w = warnings(p)
inserted = [x for x in w if x.split()[2].startswith("-insert_")]
t.check(len(inserted) == 5 and all("has no effect in a restart (the particles come from -restart)" in x for x in inserted),
        "restart: the scene's five -insert_ options listed as without effect in a restart: %s" % inserted)
t.check([x for x in w if x not in inserted] == ["WARNING: option -dem_kn_typo 5 was not used (misspelled, or no effect in this scene)"],
        "restart: the misspelled option still listed as not used: %s" % w)
