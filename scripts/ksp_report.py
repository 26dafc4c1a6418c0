#!/usr/bin/env python3
"""The tables and figures of docs/ksp.md from the results of scripts/ksp_compare.py.

Reads one or more ksp_compare.json files (each study part as ksp_compare.py wrote it: its own load averages per rank
count are kept, which --merge cannot do), and writes
- CSV tables to --csv (default docs/ksp): systems.csv (what each dumped system is: grid, model, void fraction and
  face-coefficient contrast), solvers.csv (per scene, rank count and solver: iterations from zero / previous guess /
  kept preconditioner, set-up and solve time, time per simulated second of bed, KSP's condition estimate, the load
  average of the part), spectra.csv (SLEPc and dense extreme eigenvalues of the preconditioned operators),
  matrix.csv (the matrix's largest eigenvalue, its zero and near-null modes), runs.csv (which part, when, load);
- PNG figures to --figures (default docs/figures), named ksp_*.png: convergence histories and spectra per scene (as
  ksp_compare.py draws them), iterations against grid size per family of refined scenes, condition numbers against
  the face-coefficient contrast, and the cost per simulated second per solver.

With --keep-csv the rows already in the CSVs that belong to parts not given here are kept (the parts given replace
their own rows), so a part run later, on another machine whose bench/ holds only that part, adds to the tables
instead of replacing them; the figures drawn from the tables (iterations against size, condition numbers, cost) then
use every row, and the histories and spectra are drawn for the parts given.

Usage: scripts/ksp_report.py bench/ksp/cmp_*/ksp_compare.json [--csv docs/ksp] [--figures docs/figures]
[--history SCENE,...] [--spectrum SCENE,...] [--cost SCENE,...] [--keep-csv]"""
import argparse
import csv
import json
import os
import re
import shutil
import tempfile

import numpy as np

import ksp_compare as kc  # numpy only at import
from fluidbed_tools import study


def load_parts(paths):
    parts = []
    for p in paths:
        d = json.load(open(p))
        d["_path"] = p
        d["_name"] = os.path.basename(os.path.dirname(os.path.abspath(p)))
        parts.append(d)
    return parts


def write_csv(path, rows, columns):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for r in rows:
            out = []
            for c in columns:
                v = r.get(c)
                if isinstance(v, float):
                    v = "%.6g" % v
                elif isinstance(v, (list, tuple)):
                    v = "x".join(str(x) for x in v)
                elif v is None:
                    v = ""
                out.append(v)
            w.writerow(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results", nargs="+", help="ksp_compare.json files")
    ap.add_argument("--csv", default="docs/ksp")
    ap.add_argument("--figures", default="docs/figures")
    ap.add_argument("--history", default="", help="scenes whose convergence history is drawn (default all)")
    ap.add_argument("--spectrum", default="", help="scenes whose spectra are drawn (default all)")
    ap.add_argument("--cost", default="", help="scenes in the cost figure (default all but refinement families); the main solvers only")
    ap.add_argument("--keep-csv", action="store_true", help="keep the rows of the existing CSVs that belong to other parts")
    args = ap.parse_args()
    parts = load_parts(args.results)
    new_parts = set(p["_name"] for p in parts)

    def old(table):
        return study.kept_rows(os.path.join(args.csv, table + ".csv"), lambda r: r["part"] not in new_parts) if args.keep_csv else []
    os.makedirs(args.csv, exist_ok=True)
    os.makedirs(args.figures, exist_ok=True)

    # runs: one line per part and rank count
    runs = old("runs")
    for p in parts:
        for k, v in sorted(p.get("load", {}).items()):
            runs.append(dict(part=p["_name"], date=p.get("date"), ranks=int(k), load_before=float(v[0]), load_after=float(v[1]),
                             argv=re.sub(r"\S*/(bench/|scripts/)", r"\1", " ".join(p.get("argv", [])))))  # paths from the repository root
    runs.sort(key=lambda r: (r["part"], r["ranks"]))
    write_csv(os.path.join(args.csv, "runs.csv"), runs, ["part", "date", "ranks", "load_before", "load_after", "argv"])

    # systems (one line per scene and step, smallest rank count)
    systems = old("systems")
    seen = set((s["scene"], s["step"]) for s in systems)
    for p in parts:
        for s in p["systems"]:
            key = (s["scene"], s["step"])
            if key in seen:
                continue
            seen.add(key)
            systems.append(dict(s, grid=s["n"][:s["dim"]], part=p["_name"]))
    systems.sort(key=lambda s: (s["cells"], s["scene"], s["step"]))
    write_csv(os.path.join(args.csv, "systems.csv"), systems,
              ["scene", "step", "time", "dt", "grid", "cells", "model", "implicit_drag", "eps_min", "eps_max", "eps_std", "dense_cells", "coef_min", "coef_max",
               "coef_contrast", "run_pc_type", "run_ksp_iterations", "dumped_solution_rel_residual", "reassembly_vs_dumped", "part"])

    # solvers: the summary of each part, with its load
    solvers = old("solvers")
    for p in parts:
        for r in kc.summarise(p["records"], 1e-8):
            ld = p.get("load", {}).get(str(r["ranks"]))
            solvers.append(dict(r, part=p["_name"], load_before=float(ld[0]) if ld else None, load_after=float(ld[1]) if ld else None,
                                mg_factors=";".join("x".join(str(v) for v in f) for f in r["mg_factors"]) if r.get("mg_factors") else None))
    solvers.sort(key=lambda r: (r["cells"], r["scene"], r["ranks"], r["cost_rebuild"]))
    write_csv(os.path.join(args.csv, "solvers.csv"), solvers,
              ["scene", "cells", "ranks", "solver", "systems", "its_zero", "its_prev", "its_reuse", "its_max", "converged", "worst_true_residual", "setup_s",
               "solve_s", "solve_zero_s", "solve_reuse_s", "steps_per_second", "cost_rebuild", "cost_reuse", "est_cond", "mg_factors", "load_before",
               "load_after", "part"])

    # spectra of the preconditioned operators, with the system's contrast
    contrast = {(s["scene"], s["step"]): s for s in systems}
    spectra = old("spectra")
    for p in parts:
        for s in p["spectra"]:
            c = contrast.get((s["scene"], s["step"]), {})
            spectra.append(dict(s, coef_contrast=c.get("coef_contrast"), eps_min=c.get("eps_min"), model=c.get("model"), part=p["_name"]))
    write_csv(os.path.join(args.csv, "spectra.csv"), spectra,
              ["scene", "step", "cells", "model", "eps_min", "coef_contrast", "solver", "slepc_min", "slepc_max", "slepc_cond", "slepc_min_converged",
               "slepc_max_converged", "dense_min", "dense_max", "dense_cond", "dense_method", "slepc_s", "part"])
    matrix = old("matrix")
    for p in parts:
        for s in p["matrix_spectra"]:
            c = contrast.get((s["scene"], s["step"]), {})
            lm = s["lambda_max"]
            matrix.append(dict(s, coef_contrast=c.get("coef_contrast"), eps_min=c.get("eps_min"), model=c.get("model"),
                               smallest_rel=";".join("%.3e" % (v / lm) for v in s["smallest"][:6]), part=p["_name"]))
    write_csv(os.path.join(args.csv, "matrix.csv"), matrix,
              ["scene", "step", "cells", "model", "eps_min", "coef_contrast", "lambda_max", "lambda_min_nonzero", "cond_effective", "zero_modes",
               "near_null_modes", "smallest_rel", "A_times_ones_rel", "b_dot_ones_rel", "part"])

    # figures
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    made = []
    want_h = set(x for x in args.history.split(",") if x)
    want_s = set(x for x in args.spectrum.split(",") if x)
    tmp = tempfile.mkdtemp()
    for p in parts:
        data = dict(p)
        data["histories"] = [h for h in p["histories"] if not want_h or h["scene"] in want_h]
        data["spectra"] = [s for s in p["spectra"] if not want_s or s["scene"] in want_s]
        data["summary"] = []  # the iterations-against-size figure is drawn below, over all parts
        for f in kc.plots(data, tmp):
            dst = os.path.join(args.figures, "ksp_" + re.sub(r"[^A-Za-z0-9_.-]", "_", os.path.basename(f).replace("@", "_t")))
            shutil.move(f, dst)
            made.append(dst)
    shutil.rmtree(tmp, ignore_errors=True)

    # iterations (zero guess, 1 rank) and SLEPc condition numbers against cells, per family of refined scenes
    fams = {}
    for r in solvers:
        m = re.match(r"(.*)_r(\d+)$", r["scene"])
        if m and r["ranks"] == 1 and r["its_zero"] is not None and r["converged"]:  # false convergence (BiCGStab) left out
            fams.setdefault(m.group(1), {}).setdefault(r["solver"], []).append((r["cells"], r["its_zero"]))
    if fams:
        fig, axes = plt.subplots(1, len(fams), figsize=(5.5 * len(fams), 4.5), squeeze=False)
        for ax, (fam, by) in zip(axes[0], sorted(fams.items())):
            for i, (solver, pts) in enumerate(sorted(by.items())):
                pts.sort()
                if len(pts) > 1:
                    ax.loglog([q[0] for q in pts], [q[1] for q in pts], marker="o", ms=4, lw=1.2, label=solver, **kc.style(i))
            ax.set_xlabel("cells")
            ax.set_ylabel("CG/Krylov iterations to 1e-8 (zero guess)")
            ax.set_title("%s: iterations against grid size" % fam, fontsize=9)
            ax.legend(fontsize=6, ncol=2)
        fig.tight_layout()
        dst = os.path.join(args.figures, "ksp_iterations_vs_cells.png")
        fig.savefig(dst, dpi=110)
        plt.close(fig)
        made.append(dst)

    # condition numbers against the face-coefficient contrast: the matrix (effective, nonzero spectrum) and P^-1 A
    if spectra or matrix:
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
        ax = axes[0]
        by = {}
        for s in spectra:
            cond = s.get("dense_cond") or s.get("slepc_cond")
            if cond and s.get("coef_contrast"):
                by.setdefault(s["solver"], []).append((s["coef_contrast"], cond, s["cells"]))
        for i, (solver, pts) in enumerate(sorted(by.items())):
            pts.sort()
            ax.loglog([q[0] for q in pts], [q[1] for q in pts], ls="none", ms=4, label=solver, color="C%d" % (i % 10),
                      marker="osD^v<>*Xp"[(i // 10) % 10])
        ax.set_xlabel("face-coefficient contrast max c_f / min c_f")
        ax.set_ylabel("cond(P^-1 A) (dense where small, else SLEPc)")
        ax.set_title("preconditioned operators", fontsize=9)
        ax.legend(fontsize=6, ncol=2)
        ax = axes[1]
        for i, s in enumerate(sorted(matrix, key=lambda s: s["cells"])):
            if s.get("cond_effective") and s.get("coef_contrast"):
                ax.loglog([s["coef_contrast"]], [s["cond_effective"]], "o", color="C%d" % (i % 10), label="%s (%d cells)" % (s["scene"], s["cells"]))
        ax.set_xlabel("face-coefficient contrast max c_f / min c_f")
        ax.set_ylabel("cond(A) on the complement of the constant")
        ax.set_title("the matrix itself", fontsize=9)
        ax.legend(fontsize=6)
        fig.tight_layout()
        dst = os.path.join(args.figures, "ksp_condition_vs_contrast.png")
        fig.savefig(dst, dpi=110)
        plt.close(fig)
        made.append(dst)

    # cost per simulated second (1 rank, rebuild every step, and the kept preconditioner) per scene
    scenes = sorted(set((r["cells"], r["scene"]) for r in solvers if r["ranks"] == 1))
    want_c = [x for x in args.cost.split(",") if x]
    big = [sc for sc in scenes if (sc[1] in want_c if want_c else not re.search(r"_r\d+$", sc[1]))]
    if big:
        fig, axes = plt.subplots(len(big), 1, figsize=(9, 2.2 * len(big) + 0.5), squeeze=False)
        for ax, (cells, scene) in zip(axes[:, 0], big):
            rs = sorted((r for r in solvers if r["scene"] == scene and r["ranks"] == 1 and r["converged"] and r["solver"] in kc.PRESETS["main"]),
                        key=lambda r: r["cost_rebuild"])
            y = np.arange(len(rs))
            ax.barh(y - 0.2, [r["cost_rebuild"] for r in rs], 0.4, label="PC rebuilt every step")
            ax.barh(y + 0.2, [r.get("cost_reuse") or 0 for r in rs], 0.4, label="PC kept over the dumped steps")
            ax.set_yticks(y)
            ax.set_yticklabels([r["solver"] for r in rs], fontsize=6)
            ax.set_xscale("log")
            ax.invert_yaxis()
            ax.set_title("%s (%d cells): wall s per simulated s, 1 rank" % (scene, cells), fontsize=8)
            ax.legend(fontsize=6)
        fig.tight_layout()
        dst = os.path.join(args.figures, "ksp_cost.png")
        fig.savefig(dst, dpi=100)
        plt.close(fig)
        made.append(dst)
    for f in made:
        print("wrote " + f)
    for f in ("runs", "systems", "solvers", "spectra", "matrix"):
        print("wrote " + os.path.join(args.csv, f + ".csv"))


if __name__ == "__main__":
    main()
