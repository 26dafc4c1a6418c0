#!/usr/bin/env bash
# Installs what is missing, builds, and runs the default scene (or the options given, e.g.
# scripts/run.sh -options_file examples/dem/settle_box.opts). With FLUIDBED_NP=N it runs on N ranks.
set -euo pipefail
source "$(dirname "$0")/setup.sh"
cd "$FLUIDBED_ROOT"
if [[ ${FLUIDBED_NP:-1} -gt 1 ]]; then
  exec mpiexec --oversubscribe -n "$FLUIDBED_NP" "$FLUIDBED_BUILD_DIR/fluidbed" "$@"
fi
exec "$FLUIDBED_BUILD_DIR/fluidbed" "$@"
