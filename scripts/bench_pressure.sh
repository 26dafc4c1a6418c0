#!/usr/bin/env bash
# Pressure-solver benchmark for docs/performance.md: every KSP/PC pair on the seed's jetted bed grid
# (175 x 200 x 5 cells, examples/fluid/jet_empty_bed.opts) with a frozen packed bed (eps = 0.4 below 60 mm), for
# the variable-coefficient (model A) and constant-coefficient (model B) pressure operators. Each run takes
# FLUIDBED_BENCH_STEPS gas steps (default 10) and reports iterations per solve, the first solve's time (with the
# preconditioner set-up) and the mean time of the later solves. Ranks: FLUIDBED_BENCH_RANKS (default "1 2").
# Writes a markdown table to stdout and to $FLUIDBED_BENCH_DIR/pressure.md (default bench/).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
EXE=${FLUIDBED_EXE:-$ROOT/build/fluidbed}
STEPS=${FLUIDBED_BENCH_STEPS:-10}
RANKS=${FLUIDBED_BENCH_RANKS:-"1 2"}
DIR=${FLUIDBED_BENCH_DIR:-$ROOT/bench}
PY=/usr/bin/python3
[[ -x $PY ]] || PY=python3
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# FLUIDBED_BENCH_PAIRS: "ksp pc" pairs separated by commas (default: the catalogue below)
IFS=, read -r -a PAIRS <<<"${FLUIDBED_BENCH_PAIRS:-cg fastpoisson,cg pfmg,cg hypre,cg gamg,cg mg,cg icc,cg jacobi,gmres hypre,bcgs mg}"
mkdir -p "$DIR"
runs=()
for model in A B; do
  for n in $RANKS; do
    for pair in "${PAIRS[@]}"; do
      read -r ksp pc <<<"$pair"
      out="$DIR/pressure_${model}_${ksp}_${pc}_${n}"
      cmd=("$EXE" -options_file "$ROOT/examples/fluid/jet_empty_bed.opts" -max_steps "$STEPS" -fluid_output_cells 0 -fluid_eps_packed_bed 0.06,0.4
           -fluid_model "$model" -fluid_p_ksp_type "$ksp" -fluid_p_pc_type "$pc" -monitor_dt 0 -progress_interval 0 -output_dir "$out")
      [[ $n -gt 1 ]] && cmd=(mpiexec -n "$n" "${cmd[@]}")
      echo "${cmd[*]}" >&2
      "${cmd[@]}" >"$out.log" 2>&1
      runs+=("$model $n $ksp $pc $out")
    done
  done
done
{
  echo "Machine: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(getconf _NPROCESSORS_ONLN) cores; $(date -u +%Y-%m-%d); OMP_NUM_THREADS=$OMP_NUM_THREADS"
  echo "Command: $ROOT/scripts/bench_pressure.sh (FLUIDBED_BENCH_STEPS=$STEPS, ranks: $RANKS), each run:"
  echo "fluidbed -options_file examples/fluid/jet_empty_bed.opts -max_steps $STEPS -fluid_eps_packed_bed 0.06,0.4 -fluid_model M -fluid_p_ksp_type K -fluid_p_pc_type P"
  echo
  printf '%s\n' "${runs[@]}" | $PY -c '
import csv, json, sys
print("| model | ranks | KSP | PC | iterations per solve | first solve (s, with PC set-up) | later solves (s, mean) |")
print("|---|---|---|---|---|---|---|")
for line in sys.stdin:
    model, n, ksp, pc, out = line.split()
    rows = list(csv.DictReader(open(out + "/monitor.csv")))[1:]
    its = [int(r["ksp_its"]) for r in rows]
    tt = [float(r["ksp_time"]) for r in rows]
    later = sum(tt[1:]) / max(len(tt) - 1, 1)
    print("| %s | %s | %s | %s | %.1f | %.3f | %.3f |" % (model, n, ksp, pc, sum(its) / len(its), tt[0], later))
'
} | tee "$DIR/pressure.md"
