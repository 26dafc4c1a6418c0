#!/usr/bin/env bash
# Shared set-up for scripts/run.sh and scripts/test.sh: installs the Debian packages fluidbed needs when any is
# missing, then configures and builds in build/ (or $FLUIDBED_BUILD_DIR). Sourced, not run.
set -euo pipefail

FLUIDBED_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
FLUIDBED_BUILD_DIR=${FLUIDBED_BUILD_DIR:-$FLUIDBED_ROOT/build}
# Cores for make and ctest: nproc counts OMP_NUM_THREADS (set to 1 below for hypre), so ask it without.
FLUIDBED_JOBS=${FLUIDBED_JOBS:-$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)}
FLUIDBED_PACKAGES=(petsc-dev slepc-dev libhypre-dev libhdf5-openmpi-dev libfftw3-dev openmpi-bin googletest python3-matplotlib python3-h5py python3-numpy
                   cmake make g++ pkg-config)
# What only the tests need: ParaView's pvbatch (python3-paraview holds its Python module, a recommendation that
# --no-install-recommends skips) in a virtual X server, for tests/io/test_paraview.py; petsc4py and slepc4py for
# scripts/ksp_compare.py and tests/studies/test_ksp_compare.py. scripts/test.sh sets FLUIDBED_WITH_TEST_PACKAGES=1
# before sourcing this file.
FLUIDBED_TEST_PACKAGES=(paraview python3-paraview xvfb xauth python3-petsc4py python3-slepc4py slurm-wlm munge)
if [[ ${FLUIDBED_WITH_TEST_PACKAGES:-0} == 1 ]]; then
  FLUIDBED_PACKAGES+=("${FLUIDBED_TEST_PACKAGES[@]}")
fi

fluidbed_install_packages() {
  local missing=()
  for p in "${FLUIDBED_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    echo "fluidbed: installing Debian packages: ${missing[*]}"
    local sudo=""
    [[ $(id -u) -ne 0 ]] && sudo=sudo
    $sudo apt-get update
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
  fi
}

fluidbed_build() {
  cmake -S "$FLUIDBED_ROOT" -B "$FLUIDBED_BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$FLUIDBED_BUILD_DIR" -j "$FLUIDBED_JOBS"
}

# Open MPI refuses to run as root without these; CI machines and containers often are root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# hypre (the default pressure preconditioner) is built with OpenMP: one thread per MPI rank on small machines.
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}

fluidbed_install_packages
fluidbed_build
