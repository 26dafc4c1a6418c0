#include "fluidbed/checkpoint_check.hpp"

#include <hdf5.h>

#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace fluidbed {

namespace {

// HDF5's error stack: did opening fail because the file is shorter than its superblock says?
herr_t FindTruncated(unsigned, const H5E_error2_t *err, void *found)
{
  if (err->min_num == H5E_TRUNCATED) *(bool *)found = true;
  return 0;
}

// What is wrong with the file as a checkpoint ("" when nothing is). Rank 0 only, HDF5 error printing off.
std::string Diagnose(const char *path)
{
  struct stat st;
  if (stat(path, &st) != 0) return "no such file";
  if (S_ISDIR(st.st_mode)) return "a directory, not a checkpoint file";
  if (access(path, R_OK) != 0) return "not readable (permissions)";
  if (st.st_size == 0) return "empty file (0 bytes)";
  if (H5Fis_hdf5(path) <= 0) return "not an HDF5 file (" + std::to_string((long long)st.st_size) + " bytes of something else)";
  const hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) {
    bool truncated = false;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, FindTruncated, &truncated);
    return truncated ? "truncated HDF5 file (" + std::to_string((long long)st.st_size) +
                         " bytes, shorter than its header says): an interrupted write or copy"
                     : "damaged HDF5 file (HDF5 cannot open it)";
  }
  std::string why;
  if (H5Aexists_by_name(file, "/", kCheckpointMarker, H5P_DEFAULT) > 0) {
    int         version = -1;
    const hid_t attr    = H5Aopen_by_name(file, "/", kCheckpointMarker, H5P_DEFAULT, H5P_DEFAULT);
    if (attr < 0 || H5Aread(attr, H5T_NATIVE_INT, &version) < 0) why = "damaged checkpoint (its marker attribute cannot be read)";
    else if (version != (int)kCheckpointFormat)
      why = "checkpoint of format " + std::to_string(version) + "; this fluidbed reads format " + std::to_string((int)kCheckpointFormat);
    if (attr >= 0) H5Aclose(attr);
  } else if (H5Aexists_by_name(file, "/", "step", H5P_DEFAULT) > 0 && H5Aexists_by_name(file, "/", "checkpoint_next", H5P_DEFAULT) > 0) {
    // written before checkpoints carried the marker: the same layout, accepted
  } else if (H5Lexists(file, "/measures", H5P_DEFAULT) > 0 && H5Lexists(file, "/series", H5P_DEFAULT) > 0) {
    why = "time averages (analysis.h5), not a checkpoint";
  } else if (H5Aexists_by_name(file, "/", "time", H5P_DEFAULT) > 0 &&
             (H5Lexists(file, "/particles", H5P_DEFAULT) > 0 || H5Lexists(file, "/fluid", H5P_DEFAULT) > 0)) {
    why = "a snapshot (snapshot_NNNNN.h5, for ParaView), not a checkpoint: restart from the checkpoint.h5 that -checkpoint_interval "
          "writes";
  } else {
    why = std::string("an HDF5 file but not a fluidbed checkpoint (no /") + kCheckpointMarker + " attribute)";
  }
  H5Fclose(file);
  return why;
}

} // namespace

PetscErrorCode CheckpointValidate(MPI_Comm comm, const char *path)
{
  PetscMPIInt rank;
  char        why[512] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    // HDF5 would print its error stack for each failed call: the verdict below says what is wrong instead
    H5E_auto2_t func;
    void       *data;
    H5Eget_auto2(H5E_DEFAULT, &func, &data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    const std::string w = Diagnose(path);
    H5Eclear2(H5E_DEFAULT);
    H5Eset_auto2(H5E_DEFAULT, func, data);
    PetscCall(PetscStrncpy(why, w.c_str(), sizeof(why)));
  }
  PetscCallMPI(MPI_Bcast(why, (PetscMPIInt)sizeof(why), MPI_CHAR, 0, comm));
  PetscCheck(!why[0], comm, PETSC_ERR_USER_INPUT, "-restart %s: %s", path, why);
  PetscFunctionReturn(0);
}

} // namespace fluidbed
