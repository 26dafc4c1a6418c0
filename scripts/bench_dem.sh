#!/usr/bin/env bash
# DEM throughput on a settled bed: the seed's 750 um glass bed (examples/dem/bed750.opts: 50,000 particles,
# k_n 800 N/m, e 0.9, friction 0.1, dt = t_cr/10, about 5 contacts per particle).
#   scripts/bench_dem.sh [steps]
# The bed is settled once (0.4 s of bed time on 2 ranks, about 10 minutes) and kept in build/bench/settled.csv;
# then 2000 steps (or [steps]) run from it on 1 and on 2 ranks. Prints particle-steps per second per rank and the
# time per phase, and leaves -log_view in build/bench/np<N>/log_view.txt.
set -euo pipefail
source "$(dirname "$0")/setup.sh"
cd "$FLUIDBED_ROOT"
STEPS=${1:-2000}
BENCH=$FLUIDBED_BUILD_DIR/bench
EXE=$FLUIDBED_BUILD_DIR/fluidbed
SCENE=examples/dem/bed750.opts
mkdir -p "$BENCH"
if [[ ! -f $BENCH/settled.csv ]]; then
  echo "settling the bed (once)..."
  mpiexec --oversubscribe -n 2 "$EXE" -options_file $SCENE -output_dir "$BENCH/settle" -progress_interval 60
  cp "$BENCH/settle/particles.csv" "$BENCH/settled.csv"
fi
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(env -u OMP_NUM_THREADS nproc) cores"
printf "%-6s %-10s %-8s %-12s %-26s %s\n" ranks particles steps wall_s particle-steps/s/rank "contact / integrate / ghosts / neighbour+migrate (s)"
for np in 1 2; do
  out=$BENCH/np$np
  mpiexec --oversubscribe -n $np "$EXE" -options_file $SCENE -insert_type file -insert_file "$BENCH/settled.csv" -max_steps "$STEPS" \
    -output_dir "$out" -progress_interval 0 -log_view ascii:"$out/log_view.txt" >/dev/null
  /usr/bin/python3 - "$out/summary.json" "$np" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
ph = s["wall_time_phase_max_over_ranks"]
print("%-6s %-10d %-8d %-12.2f %-26.3e %.2f / %.2f / %.2f / %.2f" % (sys.argv[2], s["particles"], s["steps"], s["wall_time_run"],
      s["particle_steps_per_second_per_rank"], ph["contact"], ph["integrate"], ph["ghosts"], ph["neighbour"] + ph["migrate"]))
PY
done
