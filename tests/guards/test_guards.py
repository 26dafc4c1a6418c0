"""One scene per run-time guard, built to trip it: the run stops with the guard's exit status (include/fluidbed/status.hpp)
and message, summary.json says "stopped" with the guard's name, and guard_failure.h5/.xmf marks the particles or cells
it names. The same scene just inside the limit runs to its end with status "ok"; where the figure has an analytic
value (the head-on overlap, a free particle's step) the guard's measured figure is checked against it."""
import json
import math
import os

import h5py
import numpy as np

from fluidbed_tools import testing as t

STATUS = {"nan": 10, "escape": 11, "pressure": 12, "overlap": 13, "displacement": 14, "energy": 15, "void_fraction": 16, "courant": 17}


def stopped(name, options_file, args, guard, words=(), nprocs=1):
    """Runs a scene that must trip `guard`; returns (output directory, summary)."""
    out, p = t.run(options_file, args=args, outdir=name, nprocs=nprocs, expect_fail=True)
    text = p.stdout + p.stderr
    t.check(p.returncode == STATUS[guard], "%s (%d rank(s)): exit status %d (guard '%s': %d)" % (name, nprocs, p.returncode, guard, STATUS[guard]))
    for w in ("guard '%s' stopped the run" % guard, "likely remedy") + tuple(words):
        t.check(w in text, "%s: the message says %r" % (name, w))
    t.check("Traceback" not in text and "Caught signal" not in text, "%s: no traceback or crash" % name)
    s = t.summary(out)
    t.check(s["status"] == "stopped" and s["guard"] == guard and s["exit_code"] == STATUS[guard],
            "%s: summary.json status %s, guard %s, exit_code %d" % (name, s["status"], s["guard"], s["exit_code"]))
    t.check(os.path.isfile(os.path.join(out, "guard_failure.xmf")) and os.path.isfile(os.path.join(out, "guard_failure.h5")),
            "%s: diagnostic snapshot guard_failure.h5/.xmf written" % name)
    xmf = open(os.path.join(out, "guard_failure.xmf")).read()
    t.check("flagged" in xmf, "%s: guard_failure.xmf shows the flagged field" % name)
    t.check(not os.path.exists(os.path.join(out, "particles.csv")), "%s: no final particles.csv from the failed state" % name)
    return out, s


def ok(name, options_file, args, nprocs=1):
    out, p = t.run(options_file, args=args, outdir=name, nprocs=nprocs)
    s = t.summary(out)
    t.check(p.returncode == 0 and s["status"] == "ok", "%s: just inside the limit: exit %d, status %s" % (name, p.returncode, s["status"]))
    return out, s


def flagged_particles(out):
    with h5py.File(os.path.join(out, "guard_failure.h5"), "r") as f:
        ids = np.asarray(f["particles/id"]).ravel()
        flag = np.asarray(f["particles/flagged"]).ravel()
    return sorted(int(i) for i in ids[flag > 0])


def flagged_cells(out):
    with h5py.File(os.path.join(out, "guard_failure.h5"), "r") as f:
        return int(np.asarray(f["fluid/flagged"]).sum())


def paraview(out):
    """The diagnostic snapshot as ParaView's XDMF reader loads it (pvbatch in a virtual X server): a list of blocks."""
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview_diagnostic.py")
    result = os.path.join(out, "paraview.json")
    t.pvbatch(script, [os.path.join(out, "guard_failure.xmf"), result], first_display=500)  # 500-899 (io_paraview: 100-499)
    if not os.path.isfile(result):
        t.fail("pvbatch could not open %s/guard_failure.xmf" % out)
    return json.load(open(result))


settle = t.example("dem/settle_box.opts")
head_on = t.example("dem/head_on.opts")
jetted = t.example("jetted_bed_2d.opts")
gas = t.example("dem/granular_gas.opts")

# NaN: two particles at the same point (the contact normal is 0/0), on 1 and 2 ranks
for n in (1, 2):
    out, s = stopped("nan_%d" % n, settle, ["-max_steps", "50", "-insert_type", "list", "-insert_positions", "0.01,0.01,0.01,0.01,0.01,0.01"],
                     "nan", ["same point", "-insert_positions"], nprocs=n)
    ids = flagged_particles(out)
    t.check(ids == [0, 1], "nan_%d: the snapshot flags particles %s (expected [0, 1])" % (n, ids))
pv = paraview("nan_1")
t.check(len(pv) == 1 and pv[0]["points"] == 2 and pv[0]["flagged"] == 2,
        "ParaView opens nan_1/guard_failure.xmf: %d block(s), %d particles, %s flagged" % (len(pv), pv[0]["points"], pv[0]["flagged"]))
ok("nan_inside", settle, ["-max_steps", "50", "-insert_type", "list", "-insert_positions", "0.01,0.01,0.01,0.01,0.0109,0.01"])

# Overlap: a head-on collision at 1 m/s closing speed, e = 1: the largest overlap is v sqrt(m_eff / k_n)
d, rho, kn, v = 1.2e-3, 1000.0, 800.0, 1.0
m = rho * math.pi / 6 * d ** 3
peak = v * math.sqrt(0.5 * m / kn) / d
fine = ["-dem_dt_factor", "0.01"]
out, s = ok("overlap_inside", head_on, fine + ["-guard_overlap", "%.6g" % (1.05 * peak)])
got = s["guard_figures"]["overlap_max"]
t.check(abs(got - peak) / peak < 2e-3, "overlap guard measures %.6f d, analytic %.6f d (%.2e, limit 2e-3)" % (got, peak, abs(got - peak) / peak))
out, s = stopped("overlap", head_on, fine + ["-guard_overlap", "%.6g" % (0.95 * peak)], "overlap", ["-guard_overlap", "-dem_kn"])
t.check(flagged_particles(out) == [0, 1], "overlap: the snapshot flags the pair %s" % flagged_particles(out))

# Displacement: a free particle at 2 m/s moves v dt / d per step
single = ["-insert_positions", "0.005,0.005,0.005", "-insert_velocities", "2,0,0", "-max_steps", "20"]
out, s = ok("displacement_inside", head_on, single + ["-guard_displacement", "1"])
step = 2.0 * s["dt"] / d
got = s["guard_figures"]["displacement_max"]
t.check(abs(got - step) / step < 1e-9, "displacement guard measures %.9f d per step, v dt / d = %.9f" % (got, step))
ok("displacement_inside_limit", head_on, single + ["-guard_displacement", "%.9g" % (1.01 * step)])
out, s = stopped("displacement", head_on, single + ["-guard_displacement", "%.9g" % (0.99 * step)], "displacement", ["-dem_dt_factor"])
t.check(flagged_particles(out) == [0], "displacement: the snapshot flags particle %s" % flagged_particles(out))

# Escape: a particle driven into a wall too soft to stop it
wall = ["-insert_positions", "0.002,0.005,0.005", "-insert_velocities", "-2,0,0", "-t_final", "4e-3"]
ok("escape_inside", head_on, wall)
out, s = stopped("escape", head_on, wall + ["-wall_kn", "1e-4", "-guard_overlap", "0"], "escape", ["left the domain through a wall", "-wall_kn"])
t.check(s["particles_lost"] == 1 and s["particles"] == 0, "escape: counted as lost (%d), none left (%d)" % (s["particles_lost"], s["particles"]))

# Energy: a closed box of 3000 colliding spheres; dt = 0.6 t_cr feeds energy in (other guards off to isolate it)
only_energy = ["-t_final", "0.01", "-guard_displacement", "0", "-guard_overlap", "0", "-guard_energy_interval", "10"]
stopped("energy", gas, only_energy + ["-dem_dt_factor", "0.6"], "energy", ["without energy input", "-dem_dt_factor"])
# elastic, frictionless, dt = t_cr / 10: kinetic + gravitational + spring energy is conserved to well under the limit
out, s = ok("energy_inside", gas, only_energy + ["-dem_e", "1", "-dem_mu", "0", "-wall_e", "1", "-wall_mu", "0"])
got = s["guard_figures"]["energy_growth_max"]
t.check(s["guard_figures"]["energy_checks"] >= 10 and got < 0.01,
        "elastic granular gas: energy growth at most %.2e over %d checks (limit 1e-2)" % (got, s["guard_figures"]["energy_checks"]))

# Void fraction: a single grid of 0.5 d cells (the gas grid that resolves the jet), on 1 and 2 ranks
fine_grid = ["-max_steps", "200", "-grid_nx", "66", "-grid_ny", "180", "-inlet_jets", "0.0165,0.001,20"]
for n in (1, 2):
    out, s = stopped("void_fraction_%d" % n, jetted, fine_grid + ["-pgrid_ratio", "2,2", "-couple_grid", "single"], "void_fraction",
                     ["held at the floor", "-pgrid_ratio"], nprocs=n)
    t.check(flagged_cells(out) > 0, "void_fraction_%d: the snapshot flags %d gas cells" % (n, flagged_cells(out)))
pv = paraview("void_fraction_1")
particles, cells = pv
inside = all(cells["bounds"][2 * a] <= particles["bounds"][2 * a] and particles["bounds"][2 * a + 1] <= cells["bounds"][2 * a + 1] for a in range(3))
t.check(particles["points"] == 900 and cells["cells"] == 66 * 180 and cells["flagged"] == flagged_cells("void_fraction_1") and inside,
        "ParaView opens void_fraction_1/guard_failure.xmf: %d particles inside the gas grid (x-y plane, bounds %s), %d cells, %d flagged"
        % (particles["points"], ["%.4g" % b for b in cells["bounds"]], cells["cells"], cells["flagged"]))
# the same gas grid on two grids with particle cells of 3 d: the seed's method holds
out, s = ok("void_fraction_inside", jetted, fine_grid + ["-pgrid_ratio", "6,6"])
t.check(s["guard_figures"]["floor_share_max"] == 0, "two grids: no cell at the floor (share %g)" % s["guard_figures"]["floor_share_max"])
# -guard_action warn: the run goes on to its end, and says it was warned
out, p = t.run(jetted, args=fine_grid + ["-max_steps", "20", "-pgrid_ratio", "2,2", "-couple_grid", "single", "-guard_action", "warn"],
               outdir="void_fraction_warn")
s = t.summary(out)
t.check(s["status"] == "warned" and "void_fraction" in s["guard_trips"] and "WARNING: guard 'void_fraction'" in p.stdout,
        "-guard_action warn: exit 0, status %s, trips %s" % (s["status"], sorted(s["guard_trips"])))
t.check("WARNING: guards tripped and the run went on (-guard_action warn): void_fraction (first at step %d" % s["guard_trips"]["void_fraction"]
        in p.stdout, "-guard_action warn: the run's last lines name the guard again, with its first step")
# warned pressure failures are counted at the end (each guard is reported once while the run goes on)
out, p = t.run(jetted, args=["-max_steps", "20", "-fluid_p_ksp_max_it", "1", "-guard_action", "warn"], outdir="pressure_warn")
s = t.summary(out)
fails = s["guard_figures"]["pressure_failures"]
t.check(s["status"] == "warned" and fails > 1 and ("%d pressure solves did not converge" % fails) in p.stdout,
        "-guard_action warn with failing pressure solves: the last lines count them (%d)" % fails)

# Pressure: a KSP held to one iteration
stopped("pressure", jetted, ["-max_steps", "20", "-fluid_p_ksp_max_it", "1"], "pressure", ["did not converge", "-fluid_p_ksp_max_it 1"])

# Courant: the default scene's gas step doubled (-couple_substeps 2) puts the Courant number above 1 for long spells
substeps = ["-couple_substeps", "2", "-t_final", "0.05"]
out, s = stopped("courant", jetted, substeps + ["-guard_courant", "1", "-guard_courant_steps", "20"], "courant", ["-couple_substeps at most 1"])
t.check(flagged_cells(out) == 1, "courant: the snapshot flags the fastest cell (%d)" % flagged_cells(out))
out, s = ok("courant_inside", jetted, substeps)
t.check(1 < s["guard_figures"]["courant_max"] < 2, "the same run under the default limit 2: largest Courant number %.3f" % s["guard_figures"]["courant_max"])
# A DEM step twice as long (a quarter of the stiffness at the same fraction of its t_cr): no -couple_substeps helps,
# the remedy names -couple_gas_substeps, and with two gas steps per DEM step the gas keeps the default's step
soft = ["-dem_kn", "200", "-t_final", "0.05"]
out, s = stopped("courant_soft", jetted, soft + ["-guard_courant", "1", "-guard_courant_steps", "20"], "courant", ["-couple_gas_substeps at least"])
out, s = ok("courant_gas_substeps", jetted, soft + ["-couple_gas_substeps", "2"])
t.check(s["guard_figures"]["courant_max"] < 1 and s["fluid"]["steps"] == 2 * s["steps"] and s["model"]["gas_substeps"] == 2,
        "-couple_gas_substeps 2: largest Courant number %.3f, %d gas steps for %d DEM steps" % (s["guard_figures"]["courant_max"], s["fluid"]["steps"], s["steps"]))
# the particles feel the gas velocity averaged over the DEM step's gas steps: the drag they get is minus what the gas got
mon = t.table(os.path.join(out, "monitor.csv"))
scale = np.max(np.abs(mon["drag_particles_y"]))
bal = max(np.max(np.abs(mon["drag_particles_" + c] + mon["drag_gas_" + c])) for c in ("x", "y")) / scale
t.check(bal < 1e-12, "-couple_gas_substeps 2: drag on the particles + drag on the gas = 0 to %.1e of the total drag (limit 1e-12)" % bal)
