#!/usr/bin/env bash
# Writes the pressure systems that scripts/ksp_compare.py studies (docs/ksp.md): runs the seed's beds with
# -fluid_p_dump_* and keeps the dumps under $FLUIDBED_KSP_DIR (default bench/ksp/dumps, git-ignored), one directory
# per scene. Usage: scripts/ksp_dumps.sh SCENE... (default: every scene but the million-cell one), SCENE one of
#   jet2d        the default 2D jetted bed (examples/jetted_bed_2d.opts): steps 1-8 and 8 steps from t = 0.1 s
#   jet2d_refine the same bed on 33 x 60, 66 x 120 and 132 x 240 cells at -dem_dt_factor 0.02 (a step the finest
#                grid's jet allows), 4 steps from t = 0.04 s: mesh (in)dependence
#   muller       the Muller bed (examples/muller_bed_u060.opts): steps 1-8 and 8 steps from t = 0.3 s (bubbling)
#   frozen_a     gas-only scenes with a frozen packed bed and a rising bubble (a moving sphere of high void
#                fraction), model A and B: the 2D bed's box and the seed's 175 x 200 x 5 grid. Coupled runs are
#                model B only (the coupling implements the seed's model B), so model A's operator comes from these.
#   bubble_refine the frozen 2D bed and bubble of frozen_a, model A, on 33 x 60, 66 x 120, 132 x 240 and 264 x 480
#                cells (gas only, 4 steps each): iterations against grid size at a fixed void-fraction field, cheap
#   bed750       the 750 um two-grid bed (examples/twogrid_750_jet1_u301.opts) on its 175 x 200 x 5 grid from a
#                settled bed ($FLUIDBED_SETTLED750, a particles.csv): steps 1-8 and 301-308 (the jet entering the
#                packed bed). The full jet through the packed bed's bottom cells (45.3 m/s / eps = 105 m/s) needs a gas
#                step of 2.3e-6 s on this grid and 1.1e-6 s on the refined one: the example's 5.84e-6 s (t_cr/10) stops
#                on the Courant guard after 50 steps, so both run at -dem_dt_factor 0.015 (8.76e-7 s)
#   bed750_1m    the same bed on 350 x 400 x 7 = 980,000 cells: steps 1-4 (RANKS ranks)
#   bed750_spout the same bed on its 175 x 200 x 5 grid while it spouts: the particles of a moment of the bed spouting
#                on the coarse 105 x 150 x 3 grid ($FLUIDBED_SPOUT750, a snapshot .h5 or particles.csv of that run,
#                docs/ksp.md) with their velocities, the gas starting at rest; steps 1-4 and 301-308 (the gas through
#                the spout established) at the example's t_cr/20
# Environment: FLUIDBED_EXE (build/fluidbed), FLUIDBED_SETTLED750 and FLUIDBED_SPOUT750 (the beds above), RANKS (1;
# the million-cell scene 2), REFINE (the refinement factors of jet2d_refine, default "1 2 4"; REFINE=4 writes only
# the finest).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
EXE=${FLUIDBED_EXE:-$ROOT/build/fluidbed}
DIR=${FLUIDBED_KSP_DIR:-$ROOT/bench/ksp/dumps}
SETTLED=${FLUIDBED_SETTLED750:-$ROOT/bench/ksp/settled750/particles.csv}
SPOUT=${FLUIDBED_SPOUT750:-}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$DIR"

# run NAME RANKS fluidbed-options...: the run's output in $DIR/NAME, its dumps in $DIR/NAME/pressure_dump
run() {
  local name=$1 n=$2
  shift 2
  local cmd=("$EXE" "$@" -output_dir "$DIR/$name" -progress_interval 60 -checkpoint_interval 0 -output_interval 0)
  [[ $n -gt 1 ]] && cmd=(mpiexec -n "$n" "${cmd[@]}")
  echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): ${cmd[*]}" | tee -a "$DIR/commands.log"
  local t0=$SECONDS
  "${cmd[@]}" >"$DIR/$name.log" 2>&1
  echo "  $name: $((SECONDS - t0)) s, load after $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$DIR/commands.log"
}

scene_jet2d() {
  run jet2d "${RANKS:-1}" -options_file "$ROOT/examples/jetted_bed_2d.opts" -t_final 0.10008 -fluid_p_dump_steps 1-9 \
    -fluid_p_dump_interval 1 -fluid_p_dump_start_time 0.1 -fluid_p_dump_count 8
}

scene_jet2d_refine() {
  local r
  for r in ${REFINE:-1 2 4}; do
    run "jet2d_r$r" "${RANKS:-1}" -options_file "$ROOT/examples/jetted_bed_2d.opts" -grid_nx $((33 * r)) -grid_ny $((60 * r)) \
      -pgrid_ratio $((3 * r)),$((2 * r)) -dem_dt_factor 0.02 -t_final 0.04001 -fluid_p_dump_interval 1 -fluid_p_dump_start_time 0.04 \
      -fluid_p_dump_count 4
  done
}

scene_muller() {
  run muller "${RANKS:-1}" -options_file "$ROOT/examples/muller_bed_u060.opts" -t_final 0.3001 -fluid_p_dump_steps 1-9 \
    -fluid_p_dump_interval 1 -fluid_p_dump_start_time 0.3 -fluid_p_dump_count 8 -output_particles 1
}

scene_frozen_a() {
  local m
  for m in A B; do
    run "frozen2d_$m" "${RANKS:-1}" -options_file "$ROOT/examples/jetted_bed_2d.opts" -particles 0 -fluid_model "$m" \
      -fluid_eps_packed_bed 0.06,0.42 -fluid_eps_sphere 0.0165,0.03,0,0.006,0.9 -fluid_eps_sphere_velocity 0,0.3,0 \
      -max_steps 8 -fluid_p_dump_steps 1-9
    run "frozen3d_$m" "${RANKS:-1}" -options_file "$ROOT/examples/fluid/jet_empty_bed.opts" -fluid_model "$m" \
      -fluid_eps_packed_bed 0.06,0.4 -fluid_eps_sphere 0.0282,0.03,0.002475,0.008,0.9 -fluid_eps_sphere_velocity 0,0.3,0 \
      -max_steps 6 -fluid_p_dump_steps 1-7
  done
}

scene_bubble_refine() {
  local r
  for r in 1 2 4 8; do
    run "bubble2d_r$r" "${RANKS:-1}" -options_file "$ROOT/examples/jetted_bed_2d.opts" -particles 0 -fluid_model A \
      -grid_nx $((33 * r)) -grid_ny $((60 * r)) -pgrid_ratio $((3 * r)),$((2 * r)) -fluid_eps_packed_bed 0.06,0.42 \
      -fluid_eps_sphere 0.0165,0.03,0,0.006,0.9 -fluid_eps_sphere_velocity 0,0.3,0 -max_steps 4 -fluid_p_dump_steps 1-5
  done
}

scene_bed750() {
  [[ -f $SETTLED ]] || { echo "no settled bed at $SETTLED (FLUIDBED_SETTLED750)" >&2; return 1; }
  run bed750 "${RANKS:-1}" -options_file "$ROOT/examples/twogrid_750_jet1_u301.opts" -insert_type file -insert_file "$SETTLED" \
    -dem_dt_factor 0.015 -max_steps 308 -fluid_p_dump_steps 1-9,301-309
}

scene_bed750_1m() {
  [[ -f $SETTLED ]] || { echo "no settled bed at $SETTLED (FLUIDBED_SETTLED750)" >&2; return 1; }
  run bed750_1m "${RANKS:-2}" -options_file "$ROOT/examples/twogrid_750_jet1_u301.opts" -insert_type file -insert_file "$SETTLED" \
    -dem_dt_factor 0.015 -grid_nx 350 -grid_ny 400 -grid_nz 7 -pgrid_ratio 14,4,7 -max_steps 4 -fluid_p_dump_steps 1-5 -fluid_output_cells 0
}

scene_bed750_spout() {
  [[ -n $SPOUT && -f $SPOUT ]] || { echo "no spouting bed at '$SPOUT' (FLUIDBED_SPOUT750: a snapshot of the coarse-grid run, docs/ksp.md)" >&2; return 1; }
  run bed750_spout "${RANKS:-1}" -options_file "$ROOT/examples/twogrid_750_jet1_u301.opts" -insert_type file -insert_file "$SPOUT" \
    -domain_top_outlet 0 -max_steps 308 -fluid_p_dump_steps 1-5,301-309
}

scenes=("$@")
[[ ${#scenes[@]} -gt 0 ]] || scenes=(jet2d jet2d_refine muller frozen_a bed750)
for s in "${scenes[@]}"; do "scene_$s"; done
