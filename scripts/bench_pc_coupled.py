#!/usr/bin/env python3
"""The pressure preconditioners on coupled beds (docs/ksp.md, "The fast Poisson preconditioner"): each bed runs the
same steps from the same start with each PC, on each number of ranks, the runs interleaved and repeated; the table
gives the step's wall time, the pressure solve's iterations and time, the pressure phase's share of the step and the
coupled particle-steps per second per core (summary.json).

Beds: jet2d (examples/jetted_bed_2d.opts from its lattice, 900 beads, 33 x 60 cells), coarse750 (the 750 um single
jet at 3 U_mf on the coarse 105 x 150 x 3 grid, examples/twogrid_750_jet1_u301_wallmu050_coarse.opts, from a settled
bed, closed top, skin 0.4 d, as the validation run), fine750 (the same jet on the seed's 175 x 200 x 5 grid at t_cr/20,
examples/twogrid_750_jet1_u301.opts). The 750 beds need a settled particles.csv of examples/dem/bed750.opts (--settled).
PFMG is skipped on 2D beds (PETSc 3.18's structured matrix is 3D only). The executable is $FLUIDBED_EXE (default
build/fluidbed).

  scripts/bench_pc_coupled.py --settled bench/beds/bed750_settled.csv [--beds jet2d,coarse750,fine750]
                              [--pcs fastpoisson,pfmg,hypre] [--ranks 1,2] [--repeat 2] [--out bench/pc_coupled]"""
import argparse
import csv
import json
import os
import sys

from fluidbed_tools import run as fr

BEDS = {
    "jet2d": ("jetted_bed_2d.opts", 2000, False, []),
    # the uniform 0.4 d skin of the figures since 2026-12-02 (the scene's own adaptive skin came on 2026-12-07)
    "coarse750": ("twogrid_750_jet1_u301_wallmu050_coarse.opts", 300, True, ["-domain_top_outlet", 0, "-dem_skin", 0.4, "-dem_skin_adaptive", 0]),
    "fine750": ("twogrid_750_jet1_u301.opts", 150, True, ["-domain_top_outlet", 0]),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--beds", default="jet2d,coarse750,fine750")
    ap.add_argument("--pcs", default="fastpoisson,pfmg,hypre")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--steps", type=int, help="steps per run (default: the bed's)")
    ap.add_argument("--settled", help="a settled particles.csv of examples/dem/bed750.opts (the 750 beds)")
    ap.add_argument("--out", default=os.path.join(fr.ROOT, "bench", "pc_coupled"))
    args = ap.parse_args()
    beds = args.beds.split(",")
    for b in beds:
        if b not in BEDS:
            sys.exit("bench_pc_coupled.py: --beds %s: no bed %s (one of %s)" % (args.beds, b, ", ".join(BEDS)))
        if BEDS[b][2] and not (args.settled and os.path.isfile(args.settled)):
            sys.exit("bench_pc_coupled.py: the bed %s needs --settled, a particles.csv of examples/dem/bed750.opts" % b)
    ranks = [int(r) for r in args.ranks.split(",")]
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for rep in range(args.repeat):
        for bed in beds:
            opts, steps, settled, extra = BEDS[bed]
            for n in ranks:
                for pc in args.pcs.split(","):
                    if pc == "pfmg" and bed == "jet2d":
                        continue
                    out = os.path.join(args.out, "%s_%s_np%d_r%d" % (bed, pc, n, rep))
                    a = ["-max_steps", args.steps or steps, "-output_particles", 0, "-output_interval", 0, "-checkpoint_interval", 0,
                         "-fluid_output_cells", 0, "-fluid_p_pc_type", pc] + extra
                    if settled:
                        a += ["-insert_type", "file", "-insert_file", os.path.abspath(args.settled)]
                    _, p, cmd = fr.execute(fr.example(opts), args=a, nprocs=n, outdir=out, env=fr.ENV)
                    if p.returncode != 0:
                        sys.exit("bench_pc_coupled.py: %s failed (exit %d): %s\n%s" % (out, p.returncode, " ".join(cmd), p.stderr[-2000:]))
                    s = json.load(open(os.path.join(out, "summary.json")))
                    g, ph, wall = s["fluid"], s["wall_time_phase_max_over_ranks"], s["wall_time_run"]
                    row = {"bed": bed, "ranks": n, "pc": pc, "repeat": rep, "steps": s["steps_this_run"], "particles": s["particles"],
                           "step_ms": 1e3 * wall / s["steps_this_run"], "its_per_solve": g["pressure_iterations_per_solve"],
                           "solve_ms": 1e3 * g["pressure_time_per_solve"], "pressure_share": ph["pressure"] / wall,
                           "fluid_share": ph["fluid"] / wall, "contact_share": ph["contact"] / wall,
                           "psteps_per_s_per_core": s["particle_steps_per_second_per_rank"]}
                    rows.append(row)
                    print("%-9s np%d %-11s rep %d: %.1f ms/step, %.1f its, %.2f ms/solve, pressure %.0f%%" %
                          (bed, n, pc, rep, row["step_ms"], row["its_per_solve"], row["solve_ms"], 100 * row["pressure_share"]), flush=True)
    with open(os.path.join(args.out, "pc_coupled.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    m = fr.machine()
    lines = ["Machine: %s, %s cores; %s" % (m["cpu"], m["cores"], " ".join(sys.argv)), "",
             "| bed | ranks | PC | iterations per solve | ms per solve | ms per step | pressure share | gas predictor share | contact share | particle-steps/s/core |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    keys = []
    for r in rows:
        if (r["bed"], r["ranks"], r["pc"]) not in keys:
            keys.append((r["bed"], r["ranks"], r["pc"]))
    for bed, n, pc in keys:
        rs = [r for r in rows if (r["bed"], r["ranks"], r["pc"]) == (bed, n, pc)]
        span = lambda k, fmt: "/".join(fmt % r[k] for r in rs)
        lines.append("| %s | %d | %s | %.1f | %s | %s | %s | %s | %s | %s |" %
                     (bed, n, pc, rs[0]["its_per_solve"], span("solve_ms", "%.2f"), span("step_ms", "%.1f"),
                      "/".join("%.0f%%" % (100 * r["pressure_share"]) for r in rs), "/".join("%.0f%%" % (100 * r["fluid_share"]) for r in rs),
                      "/".join("%.0f%%" % (100 * r["contact_share"]) for r in rs), "/".join("%.2fM" % (r["psteps_per_s_per_core"] / 1e6) for r in rs)))
    open(os.path.join(args.out, "pc_coupled.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
