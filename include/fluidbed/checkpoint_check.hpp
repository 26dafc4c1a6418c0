// Checks that a -restart file is a fluidbed checkpoint before any rank reads it, so that a wrong file (missing,
// empty, truncated, not HDF5, a snapshot) ends with one line naming -restart and the file, on every rank.
#pragma once

#include <petscsys.h>

namespace fluidbed {

// Root attribute that only checkpoints carry (the checkpoints output, src/app/checkpoint.cpp), with the format version
// as value.
inline constexpr const char kCheckpointMarker[] = "fluidbed_checkpoint";
inline constexpr PetscInt   kCheckpointFormat   = 1;

// Rank 0 checks the file with HDF5's error printing off and broadcasts the verdict: every rank then raises the same
// PETSC_ERR_USER_INPUT ("-restart FILE: what is wrong"), or returns 0 when the file is a checkpoint. Collective.
PetscErrorCode CheckpointValidate(MPI_Comm comm, const char *path);

} // namespace fluidbed
