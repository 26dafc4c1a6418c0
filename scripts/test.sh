#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (unit, scene, MPI and input tests) with ctest.
# Extra arguments go to ctest, e.g. scripts/test.sh -L unit or scripts/test.sh -R mpi.
set -euo pipefail
FLUIDBED_WITH_TEST_PACKAGES=1 # also what the tests alone need (ParaView for tests/io/test_paraview.py)
source "$(dirname "$0")/setup.sh"
cd "$FLUIDBED_BUILD_DIR"
exec ctest --output-on-failure -j "$FLUIDBED_JOBS" "$@"
