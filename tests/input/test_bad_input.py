"""Bad input ends with a clear message naming the option (or the offending particle) and the allowed range, a
nonzero exit status, and no crash or hang, on 1 and 2 ranks: values out of range, values that are not numbers,
whole numbers or booleans, options without a value, unknown names (enums, KSP and PC types), a bed taller than
the box, and -restart files that are not checkpoints of the scene (docs/reliability.md, "Input errors")."""
import os
import shutil

from fluidbed_tools import testing as t

EXIT_INPUT = 2  # include/fluidbed/status.hpp


def check_cases(cases, common=(), ranks=(1, 2), tail=("-t_final", "0")):
    """testing.check_bad_input, stricter: exit status EXIT_INPUT, no PETSc traceback or HDF5 error stack, exactly one
    error line, and every word in the output. `tail` follows the case's arguments (empty: they are the last words)."""
    for nprocs in ranks:
        for args, words in cases:
            _, p = t.run(None, args=list(common) + list(args) + list(tail), nprocs=nprocs, outdir="bad_input", expect_fail=True, timeout=60)
            text = p.stdout + p.stderr
            errors = [line for line in text.splitlines() if "error" in line.lower()]
            missing = [w for w in words if w not in text]
            clean = "PETSC ERROR" not in text and "HDF5-DIAG" not in text and "Caught signal" not in text and len(errors) == 1
            t.check(p.returncode == EXIT_INPUT and clean and not missing,
                    "%d rank(s) %s: exit %d, %s%s" % (nprocs, " ".join(args), p.returncode, errors[0].strip()[:160] if errors else "(no error line)",
                                                     " MISSING %s" % missing if missing else ""))

cases = [
    # out of range
    (["-particle_diameter", "-1e-3"], ["-particle_diameter", "out of range", "(0, 0.1]"]),
    (["-dem_e", "1.2"], ["-dem_e", "out of range", "(0, 1]"]),
    (["-dem_dt_factor", "0"], ["-dem_dt_factor", "out of range"]),
    (["-domain_dim", "4"], ["-domain_dim", "[2, 3]"]),
    (["-gravity", "1,2"], ["-gravity 1,2", "needs 3", "[-1000, 1000] m/s^2"]),
    (["-grid_nx", "40", "-pgrid_ratio", "1"], ["particle cell", "smaller than the largest particle diameter", "-pgrid_ratio"]),
    (["-grid_nx", "10", "-pgrid_ratio", "3"], ["non-integer grid ratio", "-grid_nx 10", "-pgrid_ratio 3", "1, 2, 5, 10"]),
    (["-insert_type", "list", "-insert_positions", "0.5,0.01,0.01"], ["particle 0", "outside the box"]),
    (["-insert_count", "100000"], ["-insert_type lattice", "lattice sites", "100000"]),
    (["-particle_diameter_min", "2e-3", "-particle_diameter_max", "1e-3"], ["-particle_diameter_max", "-particle_diameter_min"]),
    (["-insert_type", "file", "-insert_file", "/nonexistent.csv"], ["-insert_file", "/nonexistent.csv"]),
    # values that are not what the option takes
    (["-dem_kn", "abc"], ["-dem_kn abc", "not a number", "(0, 1e+12] N/m"]),
    (["-max_steps", "2.5"], ["-max_steps 2.5", "not a whole number", "[-1, inf]"]),
    (["-gravity", "0,x,0"], ["-gravity 0,x,0", "x is not a number", "3 comma-separated numbers in [-1000, 1000] m/s^2"]),
    (["-gravity", "0,-9.81,0,1"], ["-gravity 0,-9.81,0,1", "more than 3 values"]),
    (["-pgrid_ratio", "2,y"], ["-pgrid_ratio 2,y", "y is not a whole number"]),
    (["-fluid", "maybe"], ["-fluid maybe", "not a boolean", "true, false"]),
    # an option without a value: followed by another option (check_bad_input appends -t_final 0)
    (["-dem_kn"], ["-dem_kn", "without a value", "(0, 1e+12] N/m"]),
    (["-insert_type"], ["-insert_type", "without a value", "lattice, random, list, file"]),
    (["-restart"], ["-restart", "without a value"]),
    # names chosen from a list
    (["-insert_type", "foo"], ["-insert_type foo", "not one of", "lattice, random, list, file"]),
    (["-fluid", "-drag_model", "foo"], ["-drag_model foo", "ergun_wenyu", "gidaspow"]),
    (["-fluid", "-couple_gas_substeps", "0"], ["-couple_gas_substeps", "out of range", "[1, 1000]"]),
    (["-dem_skin", "0.3", "-dem_skin_adaptive", "-dem_skin_min", "0.5"], ["-dem_skin_min 0.5", "must not exceed -dem_skin 0.3"]),
    (["-dem_skin_min", "3"], ["-dem_skin_min", "out of range", "[0.01, 2]"]),
    (["-fluid", "-couple_substeps", "2", "-couple_gas_substeps", "3"], ["-couple_substeps 2", "-couple_gas_substeps 3", "one of them must be 1"]),
    (["-fluid", "-fluid_p_ksp_type", "foo"], ["-fluid_p_ksp_type foo", "KSP type", "bcgs", "cg", "gmres"]),
    (["-fluid", "-fluid_p_pc_type", "bar"], ["-fluid_p_pc_type bar", "PC type", "hypre", "jacobi", "mg"]),
    (["-fluid", "-fluid_p_pc_fastpoisson_jacobi", "-fluid_p_pc_fastpoisson_jacobi_weight", "1"],
     ["-fluid_p_pc_fastpoisson_jacobi_weight = 1", "out of range", "(0, 1)"]),
    (["-fluid", "-fluid_p_pc_fastpoisson_jacobi_contrast", "0.5"], ["-fluid_p_pc_fastpoisson_jacobi_contrast = 0.5", "out of range", "[1, inf]"]),
    (["-fluid", "-fluid_p_pc_type", "mg", "-fluid_p_mg_levels_ksp_type", "foo"], ["-fluid_p_mg_levels_ksp_type foo", "KSP type", "chebyshev"]),
    (["-fluid", "-fluid_p_mat_type", "foo"], ["-fluid_p_mat_type foo", "Mat type", "aij"]),
    (["-fluid", "-fluid_p_ksp_rtol", "abc"], ["-fluid_p_ksp_rtol", "abc"]),  # read by PETSc itself
    # the bed and the box
    (["-insert_bed_height", "0.05"], ["-insert_bed_height 0.05 m", "taller than the box -domain_ly", "at most 0.04 m"]),
    (["-insert_bed_height", "0.03", "-insert_region", "0,0.02,0,0.01,0,0.02"], ["-insert_bed_height 0.03 m", "-insert_region", "at most 0.01 m"]),
    (["-insert_bed_height", "0.035"], ["-insert_bed_height 0.035 m", "does not fit", "lattice sites"]),
    (["-insert_region", "0,0.02,0,0.05,0,0.02"], ["-insert_region", "outside the box", "[0, 0.04] m", "-domain_ly"]),
]
check_cases(cases)

# The last word of the command line: no value at all.
check_cases([(["-t_final", "0", "-dem_kn"], ["-dem_kn", "without a value"]), (["-t_final", "0", "-output_dir"], ["-output_dir", "without a value"])],
            tail=())

# A fluid grid that leaves a rank one cell (a check on one rank's data, which used to stop that rank alone and hang
# the other): every rank reports it.
check_cases([(["-fluid", "-domain_dim", "2", "-domain_lx", "0.01", "-domain_ly", "0.02", "-domain_lz", "0.001", "-insert_count", "50"],
                    ["-grid_nx 3", "2 ranks", "at least 2 per rank"])], ranks=(2,))

# A subdomain narrower than the ghost layer (ghosts reach the neighbouring subdomains only): 3 particle cells of one
# diameter over 2 ranks leave one of them a single cell, 1 mm, under d + skin = 1.1 mm.
# the fast Poisson PC's pencils need at least as many cells as ranks along x and y: a gas one cell wide on 2 ranks
check_cases([(["-particles", "0", "-fluid", "-domain_dim", "2", "-grid_nx", "1", "-grid_ny", "16", "-pgrid_processors", "1,2",
               "-fluid_p_pc_type", "fastpoisson"], ["-fluid_p_pc_type fastpoisson", "1 x 16 cells on 2 ranks", "pfmg, hypre"])], ranks=(2,))
check_cases([(["-domain_dim", "2", "-domain_lx", "0.003", "-domain_ly", "0.02", "-domain_lz", "0.001", "-pgrid_cell_diameters", "1",
               "-insert_count", "20"], ["process 1 of 2 along x", "narrower than the ghost layer", "-pgrid_processors", "-dem_skin"])],
            ranks=(2,))

# -restart files: a real checkpoint of a small 2D scene, cut to half, an empty file, random bytes, a snapshot,
# and checkpoints of another scene.
scene = ["-domain_dim", "2", "-domain_lx", "0.02", "-domain_ly", "0.02", "-domain_lz", "0.001", "-insert_count", "50"]
src, _ = t.run(None, args=scene + ["-t_final", "0.002", "-checkpoint_interval", "0.001", "-output_interval", "0.001", "-average"], outdir="restart_src")
files = os.path.abspath("restart_files")
shutil.rmtree(files, ignore_errors=True)
os.makedirs(files)
checkpoint = os.path.join(files, "checkpoint.h5")
shutil.copy(os.path.join(src, "checkpoint.h5"), checkpoint)
data = open(checkpoint, "rb").read()
open(os.path.join(files, "half.h5"), "wb").write(data[:len(data) // 2])
open(os.path.join(files, "empty.h5"), "wb").close()
open(os.path.join(files, "random.h5"), "wb").write(os.urandom(4096))
for name in ("snapshot_00001.h5", "analysis.h5"):
    shutil.copy(os.path.join(src, name), os.path.join(files, name))


def f(name):
    return os.path.join(files, name)


check_cases([
    (["-restart", f("half.h5")], ["-restart", f("half.h5"), "truncated"]),
    (["-restart", f("empty.h5")], ["-restart", f("empty.h5"), "empty"]),
    (["-restart", f("random.h5")], ["-restart", f("random.h5"), "not an HDF5 file"]),
    (["-restart", f("snapshot_00001.h5")], ["-restart", f("snapshot_00001.h5"), "a snapshot", "not a checkpoint"]),
    (["-restart", f("analysis.h5")], ["-restart", f("analysis.h5"), "time averages", "not a checkpoint"]),
    (["-restart", f("missing.h5")], ["-restart", f("missing.h5"), "no such file"]),
    (["-restart", files], ["-restart", files, "a directory"]),
    (["-restart", checkpoint, "-domain_dim", "3", "-domain_lz", "0.02"], ["-restart", checkpoint, "2D run", "-domain_dim"]),
    (["-restart", checkpoint, "-fluid"], ["-restart", checkpoint, "no gas state"]),
], common=scene)

# ... and the checkpoint itself restarts.
_, p = t.run(None, args=scene + ["-t_final", "0.003", "-restart", checkpoint], outdir="good_restart")
t.check("Restart from" in p.stdout, "the checkpoint restarts: %s" % [l for l in p.stdout.splitlines() if "Restart" in l])

# An error raised on one rank only (rank 0 cannot open monitor.csv, here a directory) must not leave the other rank
# waiting forever: the run ends, with the message, within the 60 s timeout (main aborts after waiting 10 s).
blocked = os.path.abspath("blocked_output")
shutil.rmtree(blocked, ignore_errors=True)
os.makedirs(os.path.join(blocked, "monitor.csv"))
_, p = t.run(None, args=["-t_final", "0"], nprocs=2, outdir=blocked, expect_fail=True, timeout=60, clean=False)
t.check(p.returncode != 0 and "monitor.csv" in p.stdout + p.stderr, "2 ranks, an error on rank 0 only: exit %d, %s" %
        (p.returncode, [l for l in (p.stdout + p.stderr).splitlines() if "error" in l.lower()][:1]))
