#!/usr/bin/env bash
# A validation run of one of the seed's scenes (docs/validation.md): runs examples/<scene>.opts to its -t_final on
# [ranks] ranks (default 1) with -log_view, then draws the run's plots (void fraction, particle velocity, profiles,
# pressure) into its plots/ folder. These are long runs (minutes to hours of wall time), not tests.
#   scripts/validate.sh <scene> [ranks] [more fluidbed options]
#   scripts/validate.sh muller_bed_u060 2
#   scripts/validate.sh tsuji_jet 1 -t_final 10
# Output: $FLUIDBED_VALIDATION_DIR/<scene> (default bench/validation/<scene>). FLUIDBED_EXE runs another executable
# (a copy kept aside while the sources change) and skips the build. FLUIDBED_CONTINUE=1 continues the run in that
# folder from its newest checkpoint (copied to restart.h5 first, since the run rewrites checkpoint.h5) with the same
# command, appending to its command.txt and stdout.txt: a run longer than one sitting is the same command again.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [[ -z ${FLUIDBED_EXE:-} ]]; then
  source "$here/setup.sh"
  FLUIDBED_EXE=$FLUIDBED_BUILD_DIR/fluidbed
else
  FLUIDBED_ROOT=$(cd "$here/.." && pwd)
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
fi
[[ $# -ge 1 ]] || { sed -n '2,9p' "$0"; exit 2; }
scene=$1
ranks=${2:-1}
shift $(($# >= 2 ? 2 : 1))
opts=$FLUIDBED_ROOT/examples/$scene.opts
[[ -f $opts ]] || { echo "validate.sh: no scene $opts" >&2; exit 2; }
out=${FLUIDBED_VALIDATION_DIR:-$FLUIDBED_ROOT/bench/validation}/$scene
mkdir -p "$out/plots"
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(env -u OMP_NUM_THREADS nproc) cores; $ranks rank(s)" | tee "$out/machine.txt"
restart=()
append=()
if [[ ${FLUIDBED_CONTINUE:-0} == 1 ]]; then
  [[ -f $out/checkpoint.h5 ]] || { echo "validate.sh: FLUIDBED_CONTINUE=1 but $out has no checkpoint.h5 to continue from" >&2; exit 2; }
  cp "$out/checkpoint.h5" "$out/restart.h5"
  restart=(-restart "$out/restart.h5")
  append=(-a)
fi
# --bind-to none: Open MPI binds each job's rank 0 to core 0, so two long runs started side by side would share one
# core while the other idles (each at half speed); unbound, the kernel gives each its own core.
cmd=(mpiexec --oversubscribe --bind-to none -n "$ranks" "$FLUIDBED_EXE" -options_file "$opts" -output_dir "$out" -progress_interval 300
     -log_view ascii:"$out/log_view.txt" "$@" "${restart[@]}")
echo "${cmd[*]}" | tee "${append[@]}" "$out/command.txt"
set +e
"${cmd[@]}" 2>&1 | tee "${append[@]}" "$out/stdout.txt"
rc=${PIPESTATUS[0]}
set -e
[[ $rc == 0 ]] || { echo "validate.sh: fluidbed exited with status $rc (see $out/stdout.txt)" >&2; exit "$rc"; }

py=/usr/bin/python3
[[ -x $py ]] || py=python3
plot() { "$py" "$FLUIDBED_ROOT/scripts/$1" "${@:2}" || echo "validate.sh: $1 drew nothing for this run"; }
plot plot_pressure.py "$out" "$out/plots/pressure.png"
plot plot_snapshots.py "$out" "$out/plots/snapshots.png"
if [[ -f $out/analysis.h5 ]]; then
  plot plot_void_fraction.py "$out" "$out/plots/void_fraction.png"
  plot plot_velocity.py "$out" "$out/plots/velocity.png"
  plot plot_profiles.py "$out" "$out/plots/profiles.png"
fi
echo "validate.sh: results in $out (summary.json, analysis.h5, monitor.csv, plots/)"
