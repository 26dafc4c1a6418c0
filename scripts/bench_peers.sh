#!/usr/bin/env bash
# DEM against LAMMPS and LIGGGHTS on the same settled particles (issue 11; docs/performance.md "DEM against LAMMPS
# and LIGGGHTS"):
#   scripts/bench_peers.sh [--steps N] [--warmup W] [--repetitions R] [--ranks 1 2] [other scripts/bench_peers.py options]
# Installs the peers from Debian when missing (lammps, liggghts: benchmark peers only, never a build or test
# dependency, so not in scripts/setup.sh), builds fluidbed (scripts/setup.sh), settles each bed once with fluidbed
# (kept in bench/peers/<bed>/settled.csv; delete it to settle again), then runs scripts/bench_peers.py: the same
# particles, contact law, time step and skin in the three codes, 1 and 2 ranks, codes interleaved, repeated.
# Writes the markdown table to stdout and bench/peers/results.md, the figures to bench/peers/results.json (and a
# dated copy). Exits nonzero when a run fails or the codes' final beds disagree.
# Environment: FLUIDBED_PEERS_BEDS (default "bed750 bed_wide", examples/dem/<bed>.opts), FLUIDBED_PEERS_DIR
# (default bench/peers).
set -euo pipefail
source "$(dirname "$0")/setup.sh"
cd "$FLUIDBED_ROOT"

peers_missing=()
command -v lmp >/dev/null || peers_missing+=(lammps)
command -v liggghts >/dev/null || peers_missing+=(liggghts)
if ((${#peers_missing[@]})); then
  echo "bench_peers: installing the benchmark peers: ${peers_missing[*]}"
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo=sudo
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y "${peers_missing[@]}"
fi

OUT=${FLUIDBED_PEERS_DIR:-$FLUIDBED_ROOT/bench/peers}
BEDS=${FLUIDBED_PEERS_BEDS:-bed750 bed_wide}
EXE=$FLUIDBED_BUILD_DIR/fluidbed
bed_args=()
for bed in $BEDS; do
  opts=examples/dem/$bed.opts
  settled=$OUT/$bed/settled.csv
  if [[ ! -f $settled ]]; then
    # settling takes minutes (0.4 s of bed time for the thin bed, 0.2 s for the wide one, 2 ranks): done once
    echo "bench_peers: settling $bed with fluidbed (once; kept in $settled)..."
    mpiexec --oversubscribe -n 2 "$EXE" -options_file "$opts" -output_dir "$OUT/$bed/settle" -progress_interval 60
    cp "$OUT/$bed/settle/particles.csv" "$settled"
  fi
  bed_args+=(--bed "$bed:$opts:$settled")
done

echo "bench_peers: load before: $(uptime)"
status=0
/usr/bin/python3 scripts/bench_peers.py "${bed_args[@]}" --exe "$EXE" --out "$OUT" --command "scripts/bench_peers.sh $*" "$@" || status=$?
echo "bench_peers: load after: $(uptime)"
exit $status
