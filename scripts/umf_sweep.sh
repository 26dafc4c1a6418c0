#!/usr/bin/env bash
# Minimum fluidization velocity of the Muller particles from a rising and falling pressure-drop sweep (issue: coupling
# verification 7; docs/validation.md). Builds, runs the sweep (about 25 minutes on one core) and writes the curve to
# docs/validation/umf_sweep.png and the figures to docs/validation/umf_sweep.json.
#   scripts/umf_sweep.sh [scripts/umf_sweep.py options, e.g. --np 2 --step 0.3]
set -euo pipefail
source "$(dirname "$0")/setup.sh"
mkdir -p "$FLUIDBED_ROOT/docs/validation"
py=/usr/bin/python3
[[ -x $py ]] || py=python3
exec "$py" "$FLUIDBED_ROOT/scripts/umf_sweep.py" --exe "${FLUIDBED_EXE:-$FLUIDBED_BUILD_DIR/fluidbed}" --out "$FLUIDBED_BUILD_DIR/umf_sweep" \
  --plot "$FLUIDBED_ROOT/docs/validation/umf_sweep.png" --json "$FLUIDBED_ROOT/docs/validation/umf_sweep.json" "$@"
