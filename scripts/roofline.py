#!/usr/bin/env python3
"""Roofline of fluidbed's stages: floating-point operations and memory traffic per particle-step (or per gas cell)
against what one core of this machine can do.

    scripts/roofline.py peaks [--out peaks.json]
        Measures one core's ceilings with small C kernels built here (gcc): the scalar double-precision rate of the
        code as fluidbed is built (SSE2 scalar, -O3 without -march), the AVX-512 FMA peak, and the triad bandwidth
        from main memory and from the core's L2.
    scripts/roofline.py profile --name NAME --per N [--exe build/fluidbed] -- FLUIDBED OPTIONS...
        Runs fluidbed natively (the loop's CPU time: the run's less that of the same run with -max_steps 0, so that a
        busy machine's other processes do not count; best of --repeat) and once under callgrind
        (--dump-instr=yes, a cache simulation whose last level is the core's own L2, collecting SimulationRun
        only), and counts per stage: instructions, double-precision flops (executed SSE/AVX arithmetic
        instructions read from objdump of each object: add/sub/mul/div/sqrt/min/max count 1 per lane, an FMA 2),
        and the bytes that leave the L2 (its simulated misses x 64 B, an upper bound of the memory traffic: the
        shared L3 holds more). N is what one step is counted per (particles, for "per particle-step"). Writes
        NAME.json.
    scripts/roofline.py plot PEAKS.json PROFILE.json... --out roofline.png [--table roofline.md]

Stages are grouped from the function names (contact, neighbour lists, integration and ghosts, drag, gas predictor,
pressure solve, output); a library function counts where its name says (hypre and KSP/PC/Mat in the pressure
solve, DMSwarm in the particles' exchange). The figures are of the instructions as executed, not of a model.
"""
import argparse
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections import defaultdict

from fluidbed_tools.run import ENV, machine, point_command

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# ---------------------------------------------------------------------------------------------------------------
# ceilings of one core

PEAK_C = r"""
#include <immintrin.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
#ifdef FMA512
/* 12 independent chains of 8-lane FMAs: 16 flops each */
static double run(long n) {
  __m512d a[12], x = _mm512_set1_pd(1.0000001), y = _mm512_set1_pd(0.9999999);
  for (int k = 0; k < 12; ++k) a[k] = _mm512_set1_pd(k);
  double t = now();
  for (long i = 0; i < n; ++i)
    for (int k = 0; k < 12; ++k) a[k] = _mm512_fmadd_pd(a[k], x, y);
  t = now() - t;
  double s = 0; for (int k = 0; k < 12; ++k) s += _mm512_reduce_add_pd(a[k]);
  fprintf(stderr, "%g\n", s);
  return 12.0 * 16.0 * n / t;
}
#else
/* 8 independent chains of scalar multiply-adds (two flops, no FMA: the code as fluidbed is built) */
static double run(long n) {
  volatile double seed = 1.0000001;
  double a[8], x = seed, y = 0.9999999 * seed;
  for (int k = 0; k < 8; ++k) a[k] = k;
  double t = now();
  for (long i = 0; i < n; ++i) {
    for (int k = 0; k < 8; ++k) a[k] = a[k] * x + y;
  }
  t = now() - t;
  double s = 0; for (int k = 0; k < 8; ++k) s += a[k];
  fprintf(stderr, "%g\n", s);
  return 8.0 * 2.0 * n / t;
}
#endif
int main(int argc, char **argv) {
  long n = atol(argv[1]); double best = 0;
  for (int r = 0; r < 5; ++r) { double f = run(n); if (f > best) best = f; }
  printf("%.6e\n", best);
  return 0;
}
"""

TRIAD_C = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
int main(int argc, char **argv) {
  long n = atol(argv[1]); int reps = atoi(argv[2]);
  double *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double)), *c = malloc(n * sizeof(double));
  for (long i = 0; i < n; ++i) { a[i] = 0; b[i] = i; c[i] = 1; }
  double best = 0;
  for (int r = 0; r < reps; ++r) {
    double t = now();
    for (long i = 0; i < n; ++i) a[i] = b[i] + 1.5 * c[i];
    t = now() - t;
    double bw = 32.0 * n / t; /* b, c read; a written and read for ownership */
    if (bw > best) best = bw;
  }
  fprintf(stderr, "%g\n", a[n / 2]);
  printf("%.6e\n", best);
  return 0;
}
"""


def build_and_run(src, flags, args):
    d = tempfile.mkdtemp(prefix="roofline_")
    try:
        c, exe = os.path.join(d, "k.c"), os.path.join(d, "k")
        open(c, "w").write(src)
        subprocess.run(["gcc", "-O3"] + flags + [c, "-o", exe], check=True)
        out = subprocess.run([exe] + [str(a) for a in args], check=True, capture_output=True, text=True).stdout
        return float(out.split()[0])
    finally:
        shutil.rmtree(d, ignore_errors=True)


def machine_text():
    m = machine()
    return "%s, %s cores" % (m["cpu"], m["cores"])


def cmd_peaks(a):
    peaks = {"machine": machine_text(), "date": time.strftime("%Y-%m-%d")}
    peaks["scalar_flops"] = build_and_run(PEAK_C, ["-fno-tree-vectorize"], [200000000])
    try:
        peaks["avx512_fma_flops"] = build_and_run(PEAK_C, ["-DFMA512", "-mavx512f", "-mfma"], [100000000])
    except (subprocess.CalledProcessError, OSError):
        peaks["avx512_fma_flops"] = None  # a core without AVX-512
    peaks["dram_bytes_per_s"] = build_and_run(TRIAD_C, [], [1 << 26, 5])  # 3 x 512 MiB
    peaks["l2_bytes_per_s"] = build_and_run(TRIAD_C, [], [1 << 14, 20000])  # 3 x 128 KiB: in L2, beyond L1
    json.dump(peaks, open(a.out, "w"), indent=1)
    print(json.dumps(peaks, indent=1))


# ---------------------------------------------------------------------------------------------------------------
# executed instructions, flops and traffic from callgrind

FP_RE = re.compile(r"^v?(add|sub|mul|div|sqrt|min|max)(s|p)(d|s)$")
FMA_RE = re.compile(r"^vf(n?m)(add|sub)(sub|add)?\d{3}(s|p)(d|s)$")


def flops_of(mnemonic, operands):
    """Double-precision (and single) flops of one instruction, 0 when it is not floating-point arithmetic."""
    m = mnemonic.split(".")[0]
    width = 8 if "%zmm" in operands else 4 if "%ymm" in operands else 2
    g = FP_RE.match(m)
    if g:
        lanes = 1 if g.group(2) == "s" else width if g.group(3) == "d" else 2 * width
        return lanes
    g = FMA_RE.match(m)
    if g:
        lanes = 1 if g.group(4) == "s" else width if g.group(5) == "d" else 2 * width
        return 2 * lanes
    return 0


def disassemble(path):
    """{address: flops} of the object's floating-point instructions (objdump -d)."""
    out = {}
    p = subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-w", path], capture_output=True, text=True)
    for line in p.stdout.splitlines():
        parts = line.split("\t")
        if len(parts) < 2 or not parts[0].strip().endswith(":"):
            continue
        try:
            addr = int(parts[0].strip()[:-1], 16)
        except ValueError:
            continue
        ins = parts[1].split(None, 1)
        if not ins:
            continue
        f = flops_of(ins[0], ins[1] if len(ins) > 1 else "")
        if f:
            out[addr] = f
    return out


# Stages as the inclusive costs of the functions that do them (first match of the demangled name); the gas
# predictor is the gas step less its pressure solve, and "other" is the rest of the loop.
STAGES = [
    ("contact", [r"::LsdForces\(", r"ContactModel\w*Forces"]),
    ("neighbour lists", [r"fluidbed::DemNeighbourBuild\("]),
    ("particles' exchange", [r"fluidbed::ParticlesMigrate\(", r"fluidbed::ParticlesSortLocal\(", r"fluidbed::ParticlesGhostsBuild\(",
                             r"fluidbed::ParticlesGhostsUpdate\(", r"fluidbed::ParticlesPackBodies\(", r"fluidbed::DemSyncPairHistory\("]),
    ("integration", [r"fluidbed::ParticlesKickDrift\(", r"fluidbed::ParticlesKick\("]),
    ("drag and coupling sums", [r"::ParticleDrag\(", r"fluidbed::CouplingBeforeFluidStep\(", r"fluidbed::CouplingAfterFluidStep\("]),
    ("pressure solve", [r"fluidbed::FluidPressureSolve\("]),
    ("gas step less the pressure solve", [r"fluidbed::FluidStep\("]),
]
LOOP = r"fluidbed::SimulationRun\("
EVENTS = ("Ir", "D1mr", "D1mw", "DLmr", "DLmw")


def parse_callgrind(path):
    """Per function: self events, self flops (given a flop table per object later), and its calls.
    Returns (events, funcs) with funcs[(ob, fn)] = {"self": [...], "addr": {address: Ir}, "calls": [(callee, [...])]}."""
    events, funcs = None, {}
    names = {"ob": {}, "fn": {}}
    ob = fn = cob = cfn = None
    last = 0
    call_pending = False

    def name(kind, val):
        m = re.match(r"\((\d+)\)(?: (.*))?$", val)
        if not m:
            return val
        if m.group(2) is not None:
            names[kind][m.group(1)] = m.group(2)
        return names[kind].get(m.group(1), val)

    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("events:"):
                events = line.split()[1:]
                continue
            if not line or line[0] == "#":
                continue
            if line[0].isalpha():
                key, _, val = line.partition("=")
                if key == "ob":
                    ob = name("ob", val)
                elif key == "fn":
                    fn = name("fn", val)
                    cob = None
                elif key == "cob":
                    cob = name("ob", val)
                elif key == "cfn":
                    cfn = name("fn", val)
                elif key == "calls":
                    call_pending = True
                continue
            parts = line.split()
            pos = parts[0]
            if pos.startswith("0x"):
                last = int(pos, 16)
            elif pos.startswith("+"):
                last += int(pos[1:])
            elif pos.startswith("-"):
                last -= int(pos[1:])
            vals = [int(x) for x in parts[1:]] + [0] * (len(events) - len(parts) + 1)
            e = funcs.setdefault((ob, fn), {"self": [0] * len(events), "addr": defaultdict(int), "calls": []})
            if call_pending:  # the call's inclusive cost
                call_pending = False
                e["calls"].append(((cob or ob, cfn), vals))
                cob = None
                continue
            for i, v in enumerate(vals):
                e["self"][i] += v
            e["addr"][last] += vals[0]
    return events, funcs


def inclusive(events, funcs, fp):
    """Inclusive events (from the call records) and flops (a callee's flops shared among its callers in proportion to
    the instructions each call took) of every function."""
    ix = events.index("Ir")
    self_flops = {}
    for k, e in funcs.items():
        table = fp.get(k[0])
        self_flops[k] = sum(n * table.get(a, 0) for a, n in e["addr"].items()) if table else 0
    incl = {}
    for k, e in funcs.items():
        tot = list(e["self"])
        for _, v in e["calls"]:
            for i, x in enumerate(v):
                tot[i] += x
        incl[k] = tot
    memo, busy = {}, set()

    def flops(k):
        if k in memo:
            return memo[k]
        if k in busy or k not in funcs:
            return 0.0
        busy.add(k)
        f = self_flops[k]
        for callee, v in funcs[k]["calls"]:
            if callee in funcs and callee != k and incl[callee][ix] > 0:
                f += flops(callee) * min(1.0, v[ix] / incl[callee][ix])
        busy.discard(k)
        memo[k] = f
        return f

    sys.setrecursionlimit(100000)
    return {k: (incl[k], flops(k)) for k in funcs}


def stage_costs(events, funcs, fp):
    inc = inclusive(events, funcs, fp)
    sel = [events.index(e) for e in EVENTS]

    def total(patterns):
        ev, fl = [0] * len(EVENTS), 0.0
        for (ob, fn), (v, f) in inc.items():
            if fn and any(re.search(p, fn) for p in patterns):
                for i, j in enumerate(sel):
                    ev[i] += v[j]
                fl += f
        return ev, fl

    def as_dict(ev, fl):
        d = dict(zip(EVENTS, ev))
        return {"instructions": d["Ir"], "flops": fl, "l1_miss_bytes": 64 * (d["D1mr"] + d["D1mw"]),
                "l2_miss_bytes": 64 * (d["DLmr"] + d["DLmw"])}

    out = {}
    for stage, pats in STAGES:
        ev, fl = total(pats)
        out[stage] = [ev, fl]
    gas, pressure = out["gas step less the pressure solve"], out["pressure solve"]
    gas[0] = [a - b for a, b in zip(gas[0], pressure[0])]
    gas[1] -= pressure[1]
    loop_ev, loop_fl = total([LOOP])
    rest = [a - sum(v[0][i] for v in out.values()) for i, a in enumerate(loop_ev)]
    out["other (output, monitor, guards, loop)"] = [rest, loop_fl - sum(v[1] for v in out.values())]
    return {k: as_dict(*v) for k, v in out.items() if v[0][0] > 0}


def cmd_profile(a):
    opts = a.options[1:] if a.options and a.options[0] == "--" else a.options
    work = tempfile.mkdtemp(prefix="roofline_run_")
    # a copy: the instructions are read back from the binary that ran, even if the build changes meanwhile
    exe = os.path.join(work, "fluidbed")
    shutil.copy2(os.path.abspath(a.exe), exe)
    try:
        # native: the CPU time of the loop, that of the run less that of the same run with no steps (best of
        # --repeat), so that other processes on the machine do not count; and the loop's wall time
        def cpu_of(extra):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            out = os.path.join(work, "native")
            subprocess.run(point_command(opts + extra, out, 1, exe), check=True, env=ENV, stdout=subprocess.DEVNULL)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), json.load(open(os.path.join(out, "summary.json")))

        cpu = wall = None
        for r in range(a.repeat):
            c_run, s = cpu_of([])
            c_setup, _ = cpu_of(["-max_steps", "0"])
            steps = s["steps_this_run"]
            cpu = c_run - c_setup if cpu is None else min(cpu, c_run - c_setup)
            wall = s["wall_time_run"] if wall is None else min(wall, s["wall_time_run"])
        cg = os.path.join(work, "callgrind.out")
        subprocess.run(["valgrind", "--tool=callgrind", "--dump-instr=yes", "--dump-line=no", "--cache-sim=yes",
                        "--LL=%d,16,64" % a.l2_bytes, "--collect-atstart=no", "--toggle-collect=fluidbed::SimulationRun*",
                        "--callgrind-out-file=" + cg] + point_command(opts, os.path.join(work, "cg"), 1, exe),
                       check=True, env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        events, funcs = parse_callgrind(cg)
        ix = events.index("Ir")
        # disassemble the objects that carry at least 0.05% of the instructions
        per_ob = defaultdict(int)
        for (ob, _), e in funcs.items():
            per_ob[ob] += e["self"][ix]
        total_ir = sum(per_ob.values())
        fp = {ob: disassemble(ob) for ob, ir in per_ob.items() if ir > 5e-4 * total_ir and ob and os.path.exists(ob)}
        stages = stage_costs(events, funcs, fp)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    result = {
        "name": a.name, "command": " ".join([os.path.relpath(os.path.abspath(a.exe), ROOT)] + opts), "machine": machine_text(),
        "date": time.strftime("%Y-%m-%d"), "steps": steps, "per": a.per, "per_label": a.per_label, "cpu_time_run": cpu, "wall_time_run": wall,
        "l2_bytes": a.l2_bytes, "stages": dict(stages),
    }
    json.dump(result, open(a.name + ".json", "w"), indent=1)
    print(format_table([result]))


def per_unit(r, st):
    units = r["steps"] * r["per"]
    return st["instructions"] / units, st["flops"] / units, st["l2_miss_bytes"] / units, st["l1_miss_bytes"] / units


def format_table(results):
    lines = []
    for r in results:
        tot = {k: sum(s[k] for s in r["stages"].values()) for k in ("instructions", "flops", "l2_miss_bytes", "l1_miss_bytes")}
        secs = r.get("cpu_time_run", r["wall_time_run"])
        lines.append("%s (%s; %d steps, %.3f s of CPU time, %.3f s wall): per %s" % (r["name"], r["command"], r["steps"], secs,
                                                                                      r["wall_time_run"], r["per_label"]))
        lines.append("| stage | share of instructions | instructions | flops | bytes beyond L1 | bytes beyond L2 | flops / L2 byte | GFLOP/s | GB/s beyond L2 |")
        lines.append("|---|---|---|---|---|---|---|---|---|")
        order = sorted(r["stages"].items(), key=lambda kv: -kv[1]["instructions"])
        for name, st in order + [("whole step", tot)]:
            ins, fl, b2, b1 = per_unit(r, st)
            share = st["instructions"] / tot["instructions"]
            t = secs * share  # the stage's wall time, by its share of the instructions
            if share < 0.005 and name != "whole step":
                continue
            lines.append("| %s | %.1f%% | %.0f | %.0f | %.0f | %.0f | %s | %.2f | %.2f |" % (
                name, 100 * share, ins, fl, b1, b2, "%.2f" % (fl / b2) if b2 else "-", st["flops"] / t / 1e9 if t else 0,
                st["l2_miss_bytes"] / t / 1e9 if t else 0))
        lines.append("")
    return "\n".join(lines)


def cmd_plot(a):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    peaks = json.load(open(a.peaks))
    results = [json.load(open(p)) for p in a.profiles]
    fig, ax = plt.subplots(figsize=(10, 5.5))
    xs = [2.0 ** (k / 8.0) for k in range(-64, 49)]
    for key, label, style in (("avx512_fma_flops", "AVX-512 FMA peak", "k-"), ("scalar_flops", "scalar SSE2 (as built)", "k--")):
        if peaks.get(key):
            for bw, bl in ((peaks["dram_bytes_per_s"], "memory"), (peaks["l2_bytes_per_s"], "L2")):
                ax.plot(xs, [min(peaks[key], bw * x) / 1e9 for x in xs], style, lw=1 if bl == "L2" else 1.8, alpha=0.5 if bl == "L2" else 1)
            ax.text(xs[-1], peaks[key] / 1e9 * 1.08, label, ha="right", fontsize=8)
    ax.text(xs[0] * 1.1, peaks["dram_bytes_per_s"] * xs[0] * 1.3 / 1e9, "memory %.0f GB/s" % (peaks["dram_bytes_per_s"] / 1e9), fontsize=8, rotation=28)
    ax.text(xs[0] * 1.1, peaks["l2_bytes_per_s"] * xs[0] * 1.3 / 1e9, "L2 %.0f GB/s" % (peaks["l2_bytes_per_s"] / 1e9), fontsize=8, rotation=28)
    markers = "osD^v<>"
    for i, r in enumerate(results):
        secs = r.get("cpu_time_run", r["wall_time_run"])
        tot_ins = sum(s["instructions"] for s in r["stages"].values())
        for name, st in r["stages"].items():
            share = st["instructions"] / tot_ins
            if share < 0.05 or not st["l2_miss_bytes"] or not st["flops"] or name.startswith("other"):
                continue
            ai = st["flops"] / st["l2_miss_bytes"]
            gf = st["flops"] / (secs * share) / 1e9
            ax.loglog([ai], [gf], markers[i % len(markers)], ms=7, label="%s: %s (%.0f%%)" % (r["name"], name, 100 * share))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("flops per byte beyond the core's L2 (callgrind)")
    ax.set_ylabel("GFLOP/s (one core)")
    ax.set_title("Roofline, one core: %s" % peaks["machine"], fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(True, which="both", alpha=0.2)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    if a.table:
        open(a.table, "w").write(format_table(results))
    print("wrote", a.out)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("peaks")
    s.add_argument("--out", default="peaks.json")
    s = sub.add_parser("profile")
    s.add_argument("--name", required=True)
    s.add_argument("--per", type=float, required=True, help="what one step is counted per (the particle count)")
    s.add_argument("--per-label", default="particle-step")
    s.add_argument("--exe", default=os.path.join(ROOT, "build", "fluidbed"))
    s.add_argument("--repeat", type=int, default=3, help="native runs (the best wall time)")
    s.add_argument("--l2-bytes", type=int, default=2 * 1024 * 1024, help="the core's own L2, the simulated last level")
    s.add_argument("options", nargs=argparse.REMAINDER)
    s = sub.add_parser("plot")
    s.add_argument("peaks")
    s.add_argument("profiles", nargs="+")
    s.add_argument("--out", required=True)
    s.add_argument("--table")
    a = p.parse_args()
    {"peaks": cmd_peaks, "profile": cmd_profile, "plot": cmd_plot}[a.cmd](a)


if __name__ == "__main__":
    sys.exit(main())
