"""Verification 6 (short CI version): every pressure KSP/PC pair named in the issue converges on the seed's jetted
bed grid (175 x 200 x 5 cells, examples/fluid/jet_empty_bed.opts) with a frozen packed bed (eps = 0.4 below
60 mm), for the variable-coefficient operator (model A) and the constant-coefficient one (model B): one gas step
per pair, pure Neumann pressure (the seed's uniform outlet, constant null space). Iterations and time of the
solve are printed; scripts/bench_pressure.sh measures the full table for docs/performance.md. The fast Poisson PC
is the exact inverse of model B's operator without drag: one iteration there, on 1 and 2 ranks."""
from fluidbed_tools import testing as t

pairs = [("cg", "fastpoisson"), ("cg", "pfmg"), ("cg", "hypre"), ("cg", "gamg"), ("cg", "mg"), ("cg", "icc"), ("cg", "jacobi"), ("gmres", "hypre"), ("bcgs", "mg")]
runs = [(m, k, p, 1) for m in ("A", "B") for k, p in pairs] + [("A", "cg", "icc", 2), ("A", "cg", "mg", 2), ("A", "cg", "hypre", 2), ("A", "cg", "fastpoisson", 2),
                                                                ("B", "cg", "fastpoisson", 2)]
RTOL = 1e-8
h_min = 0.0564 / 175
print("%-6s %-6s %-7s %-5s %10s %12s %14s" % ("model", "ksp", "pc", "ranks", "iterations", "solve (s)", "max div/(rtol U/h)"))
for model, ksp, pc, n in runs:
    out, p = t.run(t.example("fluid/jet_empty_bed.opts"),
                   args=["-max_steps", 1, "-fluid_output_cells", 0, "-fluid_eps_packed_bed", "0.06,0.4", "-fluid_model", model, "-fluid_p_ksp_type", ksp,
                         "-fluid_p_pc_type", pc], nprocs=n, outdir="pressure_%s_%s_%s_%d" % (model, ksp, pc, n))
    s = t.summary(out)["fluid"]
    ratio = s["max_div"] / (RTOL * s["max_speed"] / h_min)
    print("%-6s %-6s %-7s %-5d %10d %12.3f %14.2e" % (model, ksp, pc, n, s["pressure_iterations_last"], s["pressure_time_last"], ratio))
    t.check(s["pressure_solves"] == 1 and s["pressure_iterations_last"] > 0 and ratio < 1.0,
            "model %s, -fluid_p_ksp_type %s -fluid_p_pc_type %s on %d rank(s): converged in %d iterations, %.3f s, max |div(eps u)| %.2e 1/s"
            % (model, ksp, pc, n, s["pressure_iterations_last"], s["pressure_time_last"], s["max_div"]))
    if pc == "fastpoisson" and model == "B":
        t.check(s["pressure_iterations_last"] == 1, "fastpoisson inverts model B's constant-coefficient operator: %d iteration(s) on %d rank(s)"
                % (s["pressure_iterations_last"], n))
