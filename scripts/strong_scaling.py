#!/usr/bin/env python3
"""Strong scaling: the same scene on a list of rank counts, one fluidbed run per rank count (with -log_view).

Per rank count the table has the time per step of every -log_view stage (the project's phases: Neighbour search,
Contact, Integrate, Migrate, Ghosts, Fluid, Pressure, Coupling, Output, Guards; the stage times are -log_view's mean
over ranks, the step time is the run's wall time), the speed-up and parallel efficiency against the smallest rank
count, particles and fluid cells per rank with their imbalance (max / mean), ghost particles and fluid halo cells
per rank (summary.json "decomposition", at the end of the run), the message volume per step (-log_view's message
lengths over all stages; PETSc counts a message at its send and at its receive, so the volume sent is half of it)
and the reductions per step. /proc/loadavg is recorded before and after each run (timings on a shared machine).

Runs go straight through mpiexec (--oversubscribe when the ranks exceed the cores), or with --batch slurm as sbatch
scripts (nodes, tasks and the process grid filled in), submitted with --submit and collected by a later call (or
--wait). A finished rank count is never rerun (scripts/fluidbed_tools/study.py), so the study resumes; --fresh
measures again. --model fits a cost model to the table (compute per particle and per cell, halo volume per rank
surface, pressure reduction latency) and predicts the efficiency at 64-1024 ranks (docs/scaling.md).

example:
  scripts/strong_scaling.py --scene examples/twogrid_750_jet1_u301.opts --settled bench/beds/bed750_settled.csv \\
      --ranks 1,2,4 --steps 300 --extra="-dem_dt_factor 0.015" --out bench/scaling/bed750
  scripts/strong_scaling.py --scene examples/spouted_550_jet1_u301.opts --settle-time 0.04 --ranks 1,2,4 \\
      --steps 300 --out bench/scaling/spouted550 --model
  scripts/strong_scaling.py ... --batch slurm --submit --wait     # the same through sbatch
"""
import argparse
import csv
import json
import math
import os
import re
import shlex
import subprocess
import sys
import time

from fluidbed_tools import outputs, run, study

ROOT = run.ROOT
STAGES = ["Neighbour search", "Contact", "Integrate", "Migrate", "Ghosts", "Fluid", "Pressure", "Coupling", "Output", "Guards"]
KEYS = ["neighbour", "contact", "integrate", "migrate", "ghosts", "fluid", "pressure", "coupling", "output", "guards"]
QUIET = ["-output_particles", "0", "-fluid_output_cells", "0", "-output_interval", "0", "-checkpoint_interval", "0", "-monitor_dt", "0",
         "-average", "0", "-t_final", "1e6"]


def loadavg():
    """The 1, 5 and 15 min load averages as /proc/loadavg writes them (two decimals)."""
    return ["%.2f" % x for x in os.getloadavg()]


def ncores():
    return os.cpu_count() or 1


# ---------------------------------------------------------------------------------------------------------- -log_view
def parse_log_view(path):
    """The stage table of a -log_view file: {stage: {"time": mean s over ranks, "messages": count, "msg_len": mean
    bytes, "reductions": count}} and the run's totals {"messages", "msg_bytes", "reductions"}."""
    stages, totals = {}, {}
    text = open(path).read()
    m = re.search(r"Summary of Stages:.*?\n.*?\n(.*?)\n\s*\n", text, re.S)
    if not m:
        raise ValueError("no 'Summary of Stages' in %s (was -log_view on?)" % path)
    for line in m.group(1).splitlines():
        mm = re.match(r"\s*\d+:\s*(.+?):\s+(\S+)\s+\S+%\s+(\S+)\s+\S+%\s+(\S+)\s+\S+%\s+(\S+)\s+\S+%\s+(\S+)\s+\S+%", line)
        if mm:
            name = mm.group(1).strip()
            stages[name] = {"time": float(mm.group(2)), "messages": float(mm.group(4)), "msg_len": float(mm.group(5)),
                            "reductions": float(mm.group(6))}
    tot = sum(s["messages"] for s in stages.values())
    totals["messages"] = tot
    totals["msg_bytes"] = sum(s["messages"] * s["msg_len"] for s in stages.values())
    totals["reductions"] = sum(s["reductions"] for s in stages.values())
    return stages, totals


# ------------------------------------------------------------------------------------------------------------ points
def scene_options(args, settled):
    o = ["-options_file", os.path.abspath(args.scene)] + QUIET
    if settled:
        o += ["-insert_type", "file", "-insert_file", os.path.abspath(settled)]
    o += shlex.split(args.extra or "")
    return o


def point_options(args, settled, ranks, outdir):
    o = scene_options(args, settled) + ["-max_steps", str(args.steps), "-log_view", "ascii:" + os.path.join(outdir, "log_view.txt")]
    if args.layout:
        o += ["-pgrid_layout", args.layout]
    procs = procs_for(args, ranks)
    if procs:
        o += ["-pgrid_processors", procs]
    return o


def procs_for(args, ranks):
    """The -pgrid_processors value for this rank count from --procs (e.g. "2:2,1,1;4:4,1,1"), or None (the layout)."""
    for item in (args.procs or "").split(";"):
        if ":" in item:
            r, p = item.split(":", 1)
            if int(r) == ranks:
                return p
    return None


def settle(args):
    """The settled bed the windows start from: --settled, or one --settle-time run of the scene made once (cached)."""
    if args.settled:
        return args.settled
    if not args.settle_time:
        return None
    outdir = os.path.join(os.path.abspath(args.out), "settle")
    o = ["-options_file", os.path.abspath(args.scene)] + QUIET[:-2] + ["-output_particles", "1", "-t_final", str(args.settle_time)]
    o += shlex.split(args.settle_extra or "")
    ranks = min(args.settle_ranks, ncores())
    if not run.done(o, outdir, ranks, args.exe):
        study.log("settling: %s" % " ".join(run.point_command(o, outdir, ranks, args.exe)))
    s, status, wall, reused = study.run(o, outdir, ranks, args.exe, timeout=args.timeout)
    path = os.path.join(outdir, "particles.csv")
    if status != 0 or not os.path.isfile(path):
        sys.exit("strong_scaling.py: the settling run failed (exit %d), see %s/stdout.txt" % (status, outdir))
    study.log("settled bed: %s (%.0f s%s)" % (path, wall, ", reused" if reused else ""))
    return path


def run_direct(args, settled, ranks):
    outdir = os.path.join(os.path.abspath(args.out), "np%d" % ranks)
    o = point_options(args, settled, ranks, outdir)
    if not args.fresh and run.done(o, outdir, ranks, args.exe):
        study.log("%d ranks: finished run in %s (reused)" % (ranks, outdir))
        return outdir
    before = loadavg()
    study.log("%d ranks%s: load %s" % (ranks, " (oversubscribed)" if ranks > ncores() else "", " ".join(before)))
    s, status, wall, _ = study.run(o, outdir, ranks, args.exe, timeout=args.timeout, fresh=args.fresh)
    after = loadavg()
    with open(os.path.join(outdir, "load.json"), "w") as f:
        json.dump({"before": before, "after": after, "cores": ncores(), "oversubscribed": ranks > ncores()}, f)
    study.log("  %d ranks: exit %d, %.1f s, load after %s" % (ranks, status, wall, " ".join(after)))
    return outdir


# -------------------------------------------------------------------------------------------------------------- SLURM
SBATCH = """#!/bin/bash
#SBATCH --job-name=fbscale_np{ranks}
#SBATCH --nodes={nodes}
#SBATCH --ntasks={ranks}
#SBATCH --ntasks-per-node={per_node}
#SBATCH --cpus-per-task=1
#SBATCH --output={outdir}/slurm_%j.txt
#SBATCH --time={minutes}
{partition}# fluidbed strong-scaling point written by scripts/strong_scaling.py: {ranks} ranks, process grid {procs}
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd {outdir}
cat /proc/loadavg > load_before.txt
t0=$(date +%s.%N)
{launcher} {cmd} > stdout.txt 2>&1
status=$?
t1=$(date +%s.%N)
cat /proc/loadavg > load_after.txt
# the record scripts/fluidbed_tools/study.py keeps of a finished point (a later call collects it and never runs it again)
{python} -c 'import json, sys; a = sys.argv; json.dump({{"args": a[5:], "ranks": int(a[1]), "exit_status": int(a[2]), "wall_s": float(a[4]) - float(a[3])}}, open("command.json", "w"))' {ranks} $status $t0 $t1 {cmd}
exit $status
"""


def write_sbatch(args, settled, ranks):
    """Writes <out>/np<R>/job.sbatch; returns (outdir, path, finished)."""
    outdir = os.path.join(os.path.abspath(args.out), "np%d" % ranks)
    o = point_options(args, settled, ranks, outdir)
    cmd = run.point_command(o, outdir, 1, args.exe)  # the executable and its options; the launcher starts the ranks
    if not args.fresh and run.finished_run(outdir, cmd):
        return outdir, None, True
    os.makedirs(outdir, exist_ok=True)
    for name in ("summary.json", "command.json", "log_view.txt"):
        if os.path.exists(os.path.join(outdir, name)):
            os.remove(os.path.join(outdir, name))
    per_node = args.tasks_per_node or ranks
    nodes = max(1, math.ceil(ranks / per_node))
    procs = procs_for(args, ranks) or ("-pgrid_layout %s" % (args.layout or "horizontal"))
    if args.launcher == "mpiexec":  # Open MPI inside the allocation (one node)
        launcher = " ".join(run.launcher(ranks))
    else:
        launcher = args.launcher or "srun --mpi=pmix"
    text = SBATCH.format(ranks=ranks, nodes=nodes, per_node=min(per_node, ranks), outdir=outdir, minutes=args.minutes,
                         partition=("#SBATCH --partition=%s\n" % args.partition) if args.partition else "", procs=procs,
                         launcher=launcher, cmd=" ".join(shlex.quote(c) for c in cmd), python=shlex.quote(sys.executable))
    path = os.path.join(outdir, "job.sbatch")
    with open(path, "w") as f:
        f.write(text)
    return outdir, path, False


def submit(path):
    p = subprocess.run(["sbatch", "--parsable", path], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("strong_scaling.py: sbatch %s failed: %s" % (path, p.stderr.strip()))
    return p.stdout.strip().split(";")[0]


def wait_jobs(jobs, timeout):
    t0 = time.time()
    while jobs and time.time() - t0 < timeout:
        p = subprocess.run(["squeue", "-h", "-o", "%i", "-j", ",".join(jobs)], capture_output=True, text=True)
        left = set(p.stdout.split()) if p.returncode == 0 else set()
        jobs = [j for j in jobs if j in left]
        if jobs:
            time.sleep(1)
    return not jobs


# ------------------------------------------------------------------------------------------------------------- table
def row(outdir, ranks):
    """The table row of one finished run, or None."""
    try:
        s = outputs.summary(outdir)
        stages, tot = parse_log_view(os.path.join(outdir, "log_view.txt"))
    except (OSError, ValueError) as e:
        study.log("  %d ranks: no result in %s (%s)" % (ranks, outdir, e))
        return None
    steps = max(1, int(s.get("steps_this_run", s.get("steps", 1))))
    d = s.get("decomposition", {})
    r = {"ranks": ranks, "process_grid": "x".join(str(p) for p in d.get("process_grid", [])), "layout": d.get("layout", ""),
         "steps": steps, "step_s": s["wall_time_run"] / steps}
    for name, key in zip(STAGES, KEYS):
        r["%s_s" % key] = stages.get(name, {}).get("time", 0.0) / steps
    for key, col in (("particles", "particles_per_rank"), ("fluid_cells", "fluid_cells_per_rank"), ("ghosts", "ghost_particles_per_rank"),
                     ("halo_cells", "halo_cells_per_rank")):
        v = d.get(col, [0])
        mean = sum(v) / max(1, len(v))
        r["%s_max" % key] = max(v) if v else 0
        r["%s_mean" % key] = mean
        if key in ("particles", "fluid_cells"):
            r["%s_imbalance" % key] = max(v) / mean if mean > 0 else 1.0
    r["msg_per_step"] = tot["messages"] / 2 / steps
    r["msg_bytes_per_step"] = tot["msg_bytes"] / 2 / steps
    r["reductions_per_step"] = tot["reductions"] / steps
    p_it = s.get("fluid", {}).get("pressure_iterations_per_solve", float("nan"))
    r["p_iterations"] = p_it
    load = {}
    for name in ("load.json",):
        try:
            load = json.load(open(os.path.join(outdir, name)))
        except (OSError, ValueError):
            pass
    if not load:
        try:
            load = {"before": open(os.path.join(outdir, "load_before.txt")).read().split()[:3],
                    "after": open(os.path.join(outdir, "load_after.txt")).read().split()[:3]}
        except OSError:
            load = {"before": ["nan"] * 3, "after": ["nan"] * 3}
    r["load_before"] = load["before"][0]
    r["load_after"] = load["after"][0]
    r["oversubscribed"] = int(ranks > ncores())
    return r


def finish_table(rows):
    rows = sorted(rows, key=lambda r: r["ranks"])
    if rows:
        base = rows[0]
        for r in rows:
            r["speedup"] = base["step_s"] / r["step_s"] if r["step_s"] > 0 else float("nan")
            r["efficiency"] = r["speedup"] * base["ranks"] / r["ranks"]
    return rows


COLUMNS = (["ranks", "process_grid", "layout", "steps", "step_s", "speedup", "efficiency"] + ["%s_s" % k for k in KEYS] +
           ["particles_max", "particles_mean", "particles_imbalance", "fluid_cells_max", "fluid_cells_mean", "fluid_cells_imbalance",
            "ghosts_max", "ghosts_mean", "halo_cells_max", "halo_cells_mean", "msg_per_step", "msg_bytes_per_step", "reductions_per_step",
            "p_iterations", "load_before", "load_after", "oversubscribed"])


def fmt(v):
    if isinstance(v, float):
        return "%.4g" % v
    return str(v)


def write_tables(rows, csv_path, md_path):
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: fmt(r.get(k, "")) for k in COLUMNS})
    used = [k for k in KEYS if any(r.get("%s_s" % k, 0) > 0 for r in rows)]
    head = (["ranks", "grid", "ms/step", "speed-up", "eff."] + ["%s ms" % k for k in used] +
            ["particles/rank max (imb.)", "cells/rank max (imb.)", "ghosts/rank max", "halo cells/rank max", "msgs/step", "kB/step", "load"])
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = ["%d%s" % (r["ranks"], "*" if r["oversubscribed"] else ""), r["process_grid"], "%.2f" % (1e3 * r["step_s"]),
                 "%.2f" % r["speedup"], "%.2f" % r["efficiency"]]
        cells += ["%.2f" % (1e3 * r["%s_s" % k]) for k in used]
        cells += ["%d (%.2f)" % (r["particles_max"], r["particles_imbalance"]), "%d (%.2f)" % (r["fluid_cells_max"], r["fluid_cells_imbalance"]),
                  "%d" % r["ghosts_max"], "%d" % r["halo_cells_max"], "%.0f" % r["msg_per_step"], "%.1f" % (r["msg_bytes_per_step"] / 1e3),
                  "%s-%s" % (r["load_before"], r["load_after"])]
        lines.append("| " + " | ".join(cells) + " |")
    with open(md_path, "w") as f:
        f.write("\n".join(lines) + "\n\n(* oversubscribed: more ranks than the %d cores; ms per step, stage times are -log_view's mean over "
                "ranks; load: /proc/loadavg (1 min) before-after)\n" % ncores())
    return "\n".join(lines)


def plot(rows, png, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    n = [r["ranks"] for r in rows]
    bottom = [0.0] * len(rows)
    for k in KEYS:
        v = [1e3 * r["%s_s" % k] for r in rows]
        if max(v) <= 0:
            continue
        a1.bar([str(x) for x in n], v, bottom=bottom, label=k)
        bottom = [b + x for b, x in zip(bottom, v)]
    a1.plot([str(x) for x in n], [1e3 * r["step_s"] for r in rows], "k_", markersize=30, label="wall per step")
    a1.set_xlabel("ranks")
    a1.set_ylabel("ms per step (stage: mean over ranks)")
    a1.legend(fontsize=7)
    a2.plot(n, [r["speedup"] for r in rows], "o-", label="speed-up")
    a2.plot(n, [r["efficiency"] for r in rows], "s-", label="efficiency")
    a2.plot(n, [x / n[0] for x in n], "k:", label="ideal speed-up")
    a2.set_xlabel("ranks")
    a2.set_xscale("log", base=2)
    a2.legend(fontsize=8)
    a2.grid(alpha=0.3)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


# ------------------------------------------------------------------------------------------------------------- model
# Cost per step on P ranks, one rank per core (docs/scaling.md):
#   T(P) = c_p N/P + c_c M/P                       compute per particle (neighbour, contact, integrate, coupling) and per
#                                                  gas cell (fluid, pressure), fitted on the 1-rank run
#        + c_g G(P) + c_h H(P)                     ghost particles and gas halo cells of a rank (its subdomain surface),
#                                                  fitted on the growth of the ghost+migrate and gas stages from 1 to 2 ranks
#        + alpha (n_nb m_p + k_it L(P) 6 n_it)     messages: the particle exchanges to n_nb neighbours (m_p per neighbour and
#                                                  step, measured), and per pressure iteration k_it = 4 halo exchanges on each
#                                                  of the L(P) multigrid levels with 6 neighbours
#        + R alpha_r log2(P)                       R reductions per step (measured: the CG's and the guards'), each a
#                                                  log2(P)-deep tree
# Assumed for a cluster interconnect (InfiniBand-class): alpha = 2 us per message, alpha_r = 2 us per reduction tree
# level (an 8-byte allreduce on 1024 ranks = 20 us), B = 5 GB/s per rank for the bytes.
ALPHA, ALPHA_R, BANDWIDTH = 2e-6, 2e-6, 5e9
GHOST_BYTES, HALO_BYTES = 88, 8  # a ghost body (11 reals) per step; one real per halo cell and exchange


def fit_model(rows, particles, cells, iterations):
    r1 = rows[0]
    n1 = r1["ranks"]
    part = sum(r1["%s_s" % k] for k in ("neighbour", "contact", "integrate", "coupling")) * n1
    gas = sum(r1["%s_s" % k] for k in ("fluid", "pressure")) * n1
    m = {"c_particle": part / max(1, particles), "c_cell": gas / max(1, cells), "c_ghost": 0.0, "c_halo": 0.0,
         "reductions_per_step": max(r["reductions_per_step"] for r in rows), "pressure_iterations": iterations,
         "msgs_per_neighbour": 0.0, "fitted_on": [n1]}
    multi = [r for r in rows if r["ranks"] > n1 and not r["oversubscribed"]]
    if multi:
        r2 = multi[0]
        f = n1 / r2["ranks"]
        dg = (r2["ghosts_s"] + r2["migrate_s"]) - (r1["ghosts_s"] + r1["migrate_s"]) * f
        dh = (r2["fluid_s"] + r2["pressure_s"]) - (r1["fluid_s"] + r1["pressure_s"]) * f
        # the growth from 1 to 2 ranks also holds the waiting of a loaded machine (docs/scaling.md): an upper bound. A ghost is
        # handled like a local particle (its contacts, its body sent each step), a halo cell like a cell: the costs used are
        # the fits capped at those.
        m["c_ghost_fit"] = max(0.0, dg) / max(1.0, r2["ghosts_max"])
        m["c_halo_fit"] = max(0.0, dh) / max(1.0, r2["halo_cells_max"])
        m["c_ghost"] = min(m["c_ghost_fit"], m["c_particle"])
        m["c_halo"] = min(m["c_halo_fit"], m["c_cell"])
        m["msgs_per_neighbour"] = r2["msg_per_step"] / r2["ranks"]  # two ranks: one neighbour each
        m["fitted_on"].append(r2["ranks"])
    return m


def bed_geometry(particles, cells, d, phi=0.6, aspect=1.0, box=5.0):
    """A square 3D bed of `particles` spheres of diameter d at solid fraction phi, as high as `aspect` times its width,
    in a box `box` times the bed height, under `cells` gas cells: (width, bed height, box height, gas cell size)."""
    volume = particles * math.pi / 6 * d ** 3 / phi
    width = (volume / aspect) ** (1.0 / 3.0)
    height = aspect * width
    h = (width * width * box * height / cells) ** (1.0 / 3.0)
    return width, height, box * height, h


def predict(m, particles, cells, ranks, d, layout="horizontal", phi=0.6):
    """(efficiency, stage times) on `ranks` ranks. horizontal: P columns of the whole box height (fluidbed's default);
    cubes: cubes of the bed (split y inside the bed as well), the gas above the bed on the top layer of ranks."""
    width, hb, hbox, h = bed_geometry(particles, cells, d, phi)
    n_vol = particles / (width * width * hb)
    w = 1.1 * d  # ghost layer: 2 r_max + skin of 0.1 d
    if layout == "horizontal":
        a = width / math.sqrt(ranks)
        own_p, own_c = particles / ranks, cells / ranks
        ghosts = n_vol * hb * ((a + 2 * w) ** 2 - a * a)
        halo = 4 * (a / h) * (hbox / h)
        nb = 8
    else:
        a = (width * width * hb / ranks) ** (1.0 / 3.0)
        own_p = particles / ranks
        layers = max(1, round(hb / a))
        cols = ranks / layers
        own_c = max(cells * (hb / hbox) / ranks, cells * (1 - hb / hbox) / cols)  # the top layer holds the freeboard
        ghosts = n_vol * ((a + 2 * w) ** 3 - a ** 3)
        halo = 6 * (a / h) ** 2
        nb = 26
    ideal = (m["c_particle"] * particles + m["c_cell"] * cells) / ranks
    t = {"particles": m["c_particle"] * own_p, "gas": m["c_cell"] * own_c}
    if ranks > 1:
        levels = max(1, math.log2(max(2.0, (cells ** (1.0 / 3.0)))))
        t["ghosts"] = m["c_ghost"] * ghosts + m["c_halo"] * halo
        t["messages"] = ALPHA * (nb * m["msgs_per_neighbour"] + 4 * levels * 6 * m["pressure_iterations"]) + \
            (GHOST_BYTES * ghosts + HALO_BYTES * halo * (10 + 4 * m["pressure_iterations"])) / BANDWIDTH
        t["reductions"] = m["reductions_per_step"] * ALPHA_R * math.log2(ranks)
    else:
        t.update(ghosts=0.0, messages=0.0, reductions=0.0)
    t["ghosts_per_rank"], t["halo_per_rank"], t["particles_per_rank"] = ghosts, halo, own_p
    total = sum(t[k] for k in ("particles", "gas", "ghosts", "messages", "reductions"))
    return ideal / total, t


BEDS = (("the seed's 3D bed, 2.9 million particles", 2.9e6), ("10 million particles", 1e7))


def model_report(rows, particles, cells, iterations, d):
    m = fit_model(rows, particles, cells, iterations)
    lines = ["Fitted on ranks %s: %.3g s per particle-step, %.3g s per gas cell-step, %.3g s per ghost particle, %.3g s per halo cell "
             "(per step; fits %.3g and %.3g capped at the particle and cell costs); %.0f reductions and %.1f pressure iterations per step, %.1f messages per neighbour per step. Assumed: "
             "alpha = %.0f us per message, %.0f us per reduction tree level, %.0f GB/s per rank. Beds: square, as high as wide, "
             "solid fraction 0.6, d = %.3g mm, box 5 bed heights tall, gas cells in the measured proportion (%.2f per particle)."
             % (m["fitted_on"], m["c_particle"], m["c_cell"], m["c_ghost"], m["c_halo"], m.get("c_ghost_fit", 0), m.get("c_halo_fit", 0),
                m["reductions_per_step"], iterations,
                m["msgs_per_neighbour"], 1e6 * ALPHA, 1e6 * ALPHA_R, BANDWIDTH / 1e9, 1e3 * d, cells / max(1, particles))]
    out = {"model": m, "assumed": {"alpha": ALPHA, "alpha_r": ALPHA_R, "bandwidth": BANDWIDTH}, "beds": {}}
    for name, n_p in BEDS:
        cells_b = n_p * cells / max(1, particles)
        for layout in ("horizontal", "cubes"):
            lines.append("")
            lines.append("%s, %.3g gas cells, %s subdomains:" % (name, cells_b, "column (x, z split)" if layout == "horizontal" else "cube (x, y, z split in the bed)"))
            lines.append("| ranks | efficiency | particles ms | gas ms | ghosts+halo ms | messages ms | reductions ms | ghosts/rank | largest overhead |")
            lines.append("|---|---|---|---|---|---|---|---|---|")
            bed = []
            for P in (64, 128, 256, 512, 1024):
                e, t = predict(m, n_p, cells_b, P, d, layout)
                worst = max(("ghosts", "messages", "reductions"), key=lambda k: t[k])
                lines.append("| %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %s |" % (
                    P, e, 1e3 * t["particles"], 1e3 * t["gas"], 1e3 * t["ghosts"], 1e3 * t["messages"], 1e3 * t["reductions"],
                    t["ghosts_per_rank"], worst))
                bed.append(dict(ranks=P, efficiency=e, **t))
            below = [b["ranks"] for b in bed if b["efficiency"] < 0.5]
            lines.append("efficiency below 0.5 from %s ranks" % (below[0] if below else "beyond 1024"))
            out["beds"]["%s, %s" % (name, layout)] = bed
    return "\n".join(lines), out


# -------------------------------------------------------------------------------------------------------------- main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=None, help="options file of the scene (default: the built-in 2D jetted bed)")
    ap.add_argument("--ranks", default="1,2", help="rank counts, comma separated")
    ap.add_argument("--steps", type=int, default=200, help="steps per run (the measured window)")
    ap.add_argument("--settled", help="particles.csv of a settled bed to start every run from")
    ap.add_argument("--settle-time", type=float, default=0.0, help="else settle the scene once for this long (s) first")
    ap.add_argument("--settle-extra", default="", help="options of the settling run only (e.g. -fluid 0)")
    ap.add_argument("--settle-ranks", type=int, default=2)
    ap.add_argument("--extra", default="", help="further fluidbed options of every run")
    ap.add_argument("--layout", choices=["horizontal", "petsc"], help="-pgrid_layout of every run (default: fluidbed's)")
    ap.add_argument("--procs", default="", help="process grids per rank count, e.g. '2:1,2,1;4:2,2,1'")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "scaling"))
    ap.add_argument("--exe", default=run.EXE)
    ap.add_argument("--timeout", type=float, default=None)
    ap.add_argument("--fresh", action="store_true", help="run every rank count again")
    ap.add_argument("--batch", choices=["slurm"], help="write sbatch scripts instead of running")
    ap.add_argument("--submit", action="store_true", help="submit the sbatch scripts")
    ap.add_argument("--wait", type=float, default=0, help="wait up to this many seconds for the submitted jobs, then collect")
    ap.add_argument("--tasks-per-node", type=int, default=0, help="SLURM tasks per node (default: all on one node)")
    ap.add_argument("--partition", default="")
    ap.add_argument("--minutes", type=int, default=30, help="SLURM time limit per job")
    ap.add_argument("--launcher", default="", help="launcher in the batch script: srun (default, 'srun --mpi=pmix') or mpiexec")
    ap.add_argument("--model", action="store_true", help="fit the cost model and predict 64-1024 ranks")
    ap.add_argument("--model-d", type=float, default=7.5e-4, help="particle diameter of the modelled beds (m)")
    ap.add_argument("--title", default="")
    args = ap.parse_args(argv)
    if args.scene is None:
        args.scene = os.path.join(ROOT, "examples", "jetted_bed_2d.opts")
    if args.launcher == "srun":
        args.launcher = "srun --mpi=pmix"
    ranks = [int(x) for x in args.ranks.split(",") if x]
    os.makedirs(args.out, exist_ok=True)
    settled = settle(args)

    if args.batch == "slurm":
        jobs = []
        for r in ranks:
            outdir, path, finished = write_sbatch(args, settled, r)
            if finished:
                study.log("%d ranks: finished run in %s (reused)" % (r, outdir))
                continue
            study.log("%d ranks: %s" % (r, path))
            if args.submit:
                jobs.append(submit(path))
                study.log("  submitted as job %s" % jobs[-1])
        if jobs and args.wait > 0 and not wait_jobs(jobs, args.wait):
            sys.exit("strong_scaling.py: jobs %s still queued or running after %.0f s" % (",".join(jobs), args.wait))
        if jobs and args.wait <= 0:
            study.log("submitted; call again (without --submit) to collect the table")
            return 0
    else:
        for r in ranks:
            run_direct(args, settled, r)

    rows = [x for x in (row(os.path.join(os.path.abspath(args.out), "np%d" % r), r) for r in ranks) if x]
    rows = finish_table(rows)
    if not rows:
        sys.exit("strong_scaling.py: no finished run to tabulate")
    md = write_tables(rows, os.path.join(args.out, "scaling.csv"), os.path.join(args.out, "scaling.md"))
    print(md)
    try:
        plot(rows, os.path.join(args.out, "scaling.png"), args.title or os.path.basename(args.scene))
    except ImportError as e:
        study.log("no plot: %s" % e)
    if args.model:
        s = outputs.summary(os.path.join(os.path.abspath(args.out), "np%d" % rows[0]["ranks"]))
        d = s.get("decomposition", {})
        it = s.get("fluid", {}).get("pressure_iterations_per_solve", 0.0)
        text, out = model_report(rows, sum(d.get("particles_per_rank", [0])), sum(d.get("fluid_cells_per_rank", [0])), it, args.model_d)
        print(text)
        with open(os.path.join(args.out, "model.md"), "w") as f:
            f.write(text + "\n")
        with open(os.path.join(args.out, "model.json"), "w") as f:
            json.dump(out, f, indent=1)
    return 0 if len(rows) == len(ranks) else 1


if __name__ == "__main__":
    sys.exit(main())
