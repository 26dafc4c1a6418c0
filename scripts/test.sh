#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (unit, scene, MPI and input tests) with ctest.
# Extra arguments go to ctest, e.g. scripts/test.sh -L unit or scripts/test.sh -R mpi.
set -euo pipefail
source "$(dirname "$0")/setup.sh"
cd "$FLUIDBED_BUILD_DIR"
exec ctest --output-on-failure -j "$FLUIDBED_JOBS" "$@"
