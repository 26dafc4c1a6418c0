#!/usr/bin/env bash
# Results bit for bit: runs a few short scenes with one executable into a directory, or compares two such
# directories with cmp. A restructure that must not change any result runs it before and after:
#   scripts/bitwise_check.sh run build/fluidbed /tmp/before   (on the old build)
#   scripts/bitwise_check.sh run build/fluidbed /tmp/after    (on the new build)
#   scripts/bitwise_check.sh compare /tmp/before /tmp/after
# The scenes: the default 2D jetted bed (300 steps, 1 and 2 ranks), the Muller bed (200 steps) and the coarse
# 750 um two-grid jet on 2 ranks (30 steps), each writing its particles and fluid cells as CSV.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
SCENES=(
  "jet2d_r1 1 -options_file $ROOT/examples/jetted_bed_2d.opts -max_steps 300"
  "jet2d_r2 2 -options_file $ROOT/examples/jetted_bed_2d.opts -max_steps 300"
  "muller_r1 1 -options_file $ROOT/examples/muller_bed_u060.opts -max_steps 200"
  "coarse750_r2 2 -options_file $ROOT/examples/twogrid_750_jet1_u301_wallmu050_coarse.opts -max_steps 30"
)
usage() { echo "usage: $0 run EXE DIR | compare DIR_A DIR_B" >&2; exit 2; }
[[ $# -eq 3 ]] || usage
case "$1" in
run)
  exe="$(realpath "$2")"; out="$3"; mkdir -p "$out"
  for s in "${SCENES[@]}"; do
    read -r name np opts <<<"$s"
    mpiexec --oversubscribe -n "$np" "$exe" $opts -output_particles 1 -fluid_output_cells 1 -progress_interval 0 \
      -output_dir "$out/$name" >"$out/$name.log" 2>&1 || { echo "$name: run failed (see $out/$name.log)" >&2; exit 1; }
    echo "$name: done"
  done ;;
compare)
  status=0
  for s in "${SCENES[@]}"; do
    read -r name _ <<<"$s"
    for f in particles.csv fluid_cells.csv; do
      a="$2/$name/$f"; b="$3/$name/$f"
      if [[ ! -f $a && ! -f $b ]]; then continue; fi
      if cmp -s "$a" "$b"; then echo "$name/$f: identical"; else echo "$name/$f: DIFFERENT"; status=1; fi
    done
  done
  exit $status ;;
*) usage ;;
esac
