// The checked writes every output of a run goes through (src/io/files.cpp) and the flat JSON writer: the io layer's
// part that the gas and the particles use too. It includes nothing of the DEM, so that the gas module is not
// compiled against it.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

namespace fluidbed {

// ---- Checked writes (src/io/files.cpp) ----
// Every output of a run goes through these, so that a failed write (full disk, file-size limit, unwritable path)
// ends the run on every rank with PETSC_ERR_FILE_WRITE and one line naming the file and the reason (main.cpp maps
// it to exit status EXIT_OUTPUT), and a file that is replaced is written to <path>.tmp and renamed when complete:
// the previous version stays intact until the new one is whole.

// The names of the files a run writes into its output directory. The writers and the clean-up of a previous run's
// files (RemovePreviousRun) both take them from here.
namespace run_files {
inline constexpr const char *monitor = "monitor.csv", *track = "track.csv", *particles = "particles.csv", *fluid_cells = "fluid_cells.csv",
                            *summary = "summary.json", *particles_xdmf = "particles.xmf", *fluid_xdmf = "fluid.xmf",
                            *averages = "analysis.h5", *averages_xdmf = "analysis.xmf", *checkpoint = "checkpoint.h5",
                            *fluid_nodes  = "fluid_grid.h5";  // the 2D gas grid's node coordinates (the geometry of fluid.xmf)
inline constexpr const char *guard_prefix = "guard_failure."; // the diagnostic snapshot of a run stopped by a guard
inline constexpr const char *guard_h5 = "guard_failure.h5", *guard_xdmf = "guard_failure.xmf";
std::string                  Snapshot(PetscInt index);                             // snapshot_NNNNN.h5
PetscInt                     SnapshotIndex(const std::string &name);               // the index of a snapshot file name, -1 for any other
bool                         IsRunFile(const std::string &name);                   // one of the names above, or a temporary (.tmp) of one
std::string                  WithoutTmp(const std::string &name, bool *temporary); // name without a trailing .tmp (*temporary: it had one)
} // namespace run_files

// Agrees on the outcome of a write: err is an errno value on a rank that failed and 0 on the others. When any rank
// failed, every rank raises PETSC_ERR_FILE_WRITE "cannot write <path> (<strerror>)", so no rank is left waiting.
PetscErrorCode WriteAgree(MPI_Comm comm, int err, const std::string &path);

// A text file written by rank 0, checked at every write.
//   REPLACE: written to <path>.tmp, renamed onto path by OutputFileClose (a whole file: particles.csv, summary.json);
//   CREATE, APPEND: written in place, row by row (monitor.csv, track.csv); a failed row is cut off again, so the
//   file ends with the last complete row.
struct OutputFile {
  enum Mode { REPLACE, CREATE, APPEND };
  std::string path;
  Mode        mode = REPLACE;
  FILE       *fp   = nullptr; // rank 0, while open
  int         err  = 0;       // errno of the first failed write (rank 0)
  long long   good = 0;       // bytes known to be written (CREATE, APPEND)
};
PetscErrorCode OutputFileOpen(MPI_Comm comm, const std::string &path, OutputFile::Mode mode, OutputFile *f);
// fprintf on rank 0 (a no-op elsewhere and after a failure); the failure is reported by the next flush or close.
void OutputFilePrintf(OutputFile *f, const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(2, 3);
// Pushes what was written to the file and agrees on the outcome (collective): a row of a log file is complete.
PetscErrorCode OutputFileFlush(MPI_Comm comm, OutputFile *f);
// Closes (and for REPLACE commits) the file and agrees on the outcome (collective).
PetscErrorCode OutputFileClose(MPI_Comm comm, OutputFile *f);
// A whole text file written by rank 0, atomically (REPLACE); text is used on rank 0 only.
PetscErrorCode OutputWriteText(MPI_Comm comm, const std::string &path, const std::string &text);

// Atomic replacement of a file every rank wrote to: the caller has written and closed <path>.tmp; rank 0 renames
// it onto path (the .tmp is removed when the rename fails).
PetscErrorCode CommitFile(MPI_Comm comm, const std::string &path);

// -output_dir: creates the directory (and its parents) and checks that a file can be written in it (rank 0; a
// probe file is created and removed).
PetscErrorCode MakeDirectory(MPI_Comm comm, const char *dir);
// Checks that file can be written where the option puts it: its directory exists and takes a new file.
PetscErrorCode CheckFileLocation(MPI_Comm comm, const std::string &file, const char *option);

// Before a fresh run writes into dir: removes the files a previous run left there (every run_files name, its
// temporaries, the snapshots and guard diagnostics) and the paths in `also` (a checkpoint written elsewhere), never
// one of `keep` (files this run reads, such as its -insert_file), and prints one line listing what was removed.
// Nothing else in the directory is touched.
PetscErrorCode RemovePreviousRun(MPI_Comm comm, const std::string &dir, const std::vector<std::string> &also,
                                 const std::vector<std::string> &keep);
// After a restart from a checkpoint that holds `snapshots` snapshots: removes the snapshot files numbered from there
// on (written after the checkpoint by the run that is continued), never one of `keep`; *removed: how many.
PetscErrorCode RemoveSnapshotsAfter(MPI_Comm comm, const std::string &dir, PetscInt snapshots, const std::vector<std::string> &keep,
                                    PetscInt *removed);
// Removes one file of a run (rank 0) if it exists.
PetscErrorCode RemoveRunFile(MPI_Comm comm, const std::string &path);

// A flat JSON object written by rank 0; values are added in order.
struct JsonWriter {
  std::string body;
  void        Number(const char *key, double v);
  void        Integer(const char *key, long long v);
  void        String(const char *key, const std::string &v);
  void        Object(const char *key, const JsonWriter &inner);
  void        StringArray(const char *key, const std::vector<std::string> &v);
  void        Bool(const char *key, bool v);
  void        NumberArray(const char *key, const std::vector<double> &v); // non-finite entries as null
  void        IntegerArray(const char *key, const std::vector<long long> &v);
  void        BoolArray(const char *key, const std::vector<bool> &v);
  std::string Text() const;
};
PetscErrorCode JsonWrite(MPI_Comm comm, const char *path, const JsonWriter &json);

} // namespace fluidbed
