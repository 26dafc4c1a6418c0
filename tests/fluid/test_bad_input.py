"""Bad gas-phase input stops cleanly: exit status 2 (not an abort or a crash), no traceback, and one message that
names the option and what is allowed (for a slit whose edges miss the cell faces: the jet and the nearest valid
width)."""
from fluidbed_tools import testing as t

jet = t.example("fluid/jet_empty_bed.opts")
cavity = t.example("fluid/cavity_re100.opts")
small = ["-domain_dim", 2, "-grid_nx", 35, "-grid_ny", 50, "-inlet_jets", "0.0282,0.00161142857,45.3", "-max_steps", 1]
cases = [
    # (options file, arguments, words the message must contain)
    (jet, ["-inlet_jets", "0.0282,0.0016,45.3", "-max_steps", 1, "-fluid_output_cells", 0], ["-inlet_jets", "jet 1", "nearest valid width", "0.0016114286 m (5 cells)"]),
    (jet, small + ["-inlet_jets", "0.0282,0.00161142857,45.3,0.0104742857,0.0012,20"], ["-inlet_jets", "jet 2", "nearest valid width", "0.0016114286 m (1 cells)"]),
    (jet, small + ["-inlet_jets", "0.0283,0.00161142857,45.3"], ["-inlet_jets", "jet 1", "nearest valid centre"]),
    (jet, small + ["-inlet_jets", "0.0282,0.0016"], ["-inlet_jets", "multiple of 3"]),
    (jet, small + ["-inlet_jets", "0.0282,0.00161142857,45.3,0.0282,0.00483428571,10"], ["-inlet_jets", "overlap"]),
    (jet, small + ["-inlet_jets", "0.0556,0.00483428571,10"], ["-inlet_jets", "beyond the bottom"]),
    (jet, small + ["-fluid_bc_yhi", "noslip"], ["-fluid_bc_yhi", "outlet"]),
    (cavity, ["-fluid_mu", -1.8e-5], ["-fluid_mu", "out of range", "(0, 1000]"]),
    (cavity, ["-fluid_rho", 0], ["-fluid_rho", "out of range"]),
    (cavity, ["-fluid_cfl", 2], ["-fluid_cfl", "out of range", "[0.01, 1]"]),
    (cavity, ["-fluid_model", "C"], ["-fluid_model", "not one of", "B, A"]),
    (cavity, ["-fluid_limiter", "central"], ["-fluid_limiter", "not one of", "vanleer"]),
    (cavity, ["-fluid_bc_xlo", "outlet"], ["-fluid_bc_xlo", "top only"]),
    (cavity, ["-fluid_bc_yhi_velocity", "0,1,0"], ["-fluid_bc_yhi_velocity", "wall-normal"]),
    (cavity, ["-fluid_eps_sphere", "0.005,0.005,0,0.002,1.5"], ["-fluid_eps_sphere", "(0, 1]"]),
    (cavity, ["-fluid_eps", 0], ["-fluid_eps", "out of range"]),
    (cavity, ["-fluid_pc_reuse", 0], ["-fluid_pc_reuse", "out of range"]),
    (cavity, ["-fluid_dt", 1], ["-fluid_dt", "exceeds the gas time-step limit"]),
    (cavity, ["-domain_periodic_y", "-fluid_bc_ylo", "freeslip"], ["-fluid_bc_ylo", "periodic"]),
    (cavity, ["-fluid_p_pc_type", "mg", "-fluid_p_pc_mg_levels", 9], ["-fluid_p_pc_mg_levels", "cannot be coarsened"]),
    (None, ["-particles", 0, "-fluid"], ["-grid_nx", "required"]),
    (None, ["-particles", 0], ["-particles 0", "-fluid"]),
]
for n, (opts, args, words) in enumerate(cases):
    out, p = t.run(opts, args=args, outdir="bad_input_%d" % n, expect_fail=True, timeout=120)
    msg = p.stderr.strip()
    label = " ".join(str(a) for a in args)
    ok = p.returncode == 2 and all(w in msg for w in words) and "PETSC ERROR" not in p.stderr and msg.startswith("fluidbed: error:")
    t.check(ok, "%s -> status %d, %s" % (label, p.returncode, msg.splitlines()[0] if msg else "(no message)"))
