// Run outputs: the monitor CSV of global quantities, tracked particles, the final particle table and
// summary.json, and the checked writes every output goes through. Rank 0 writes the text files; the data are
// reduced or gathered first.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

#include "fluidbed/dem.hpp"

namespace fluidbed {

struct FluidStats;

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

// Global sums over the particles (monitor.csv columns).
struct ParticleTotals {
  PetscInt64 count    = 0;
  PetscReal  ke_trans = 0, ke_rot = 0, pe_grav = 0; // J
  PetscReal  momentum[3]{0, 0, 0};                  // kg m/s
  PetscReal  max_speed             = 0;             // m/s
  PetscReal  contacts_per_particle = 0;
  PetscReal  max_overlap_rel       = 0; // largest overlap / diameter since the previous row
};
PetscErrorCode ComputeParticleTotals(Dem *dem, ParticleTotals *t);

struct Monitor {
  OutputFile               csv, track; // track: open only with -monitor_track_ids
  std::vector<PetscInt64>  track_ids;
  PetscInt                 track_every = 1;
  PetscReal                interval = 0, next = 0;
  bool                     particles = true, fluid = false; // column groups, set before MonitorCreate
  std::vector<std::string> extra_columns;                   // further columns (coupling, probes), set before MonitorCreate
  PetscInt64               last_row_step = -1;              // the step of the last row written
};

// append: continue the files of a restarted run instead of starting them anew, dropping first the rows after
// last_step (the checkpoint's step: rows written after it by the run that is continued).
PetscErrorCode MonitorCreate(MPI_Comm comm, const char *dir, PetscReal t_final, PetscBool append, PetscInt64 last_step, Monitor *m);
// One row: the particle columns when m->particles, the gas columns (fluid, the last gas step) when m->fluid.
// extra: the values of m->extra_columns.
PetscErrorCode MonitorWrite(MPI_Comm comm, Monitor *m, Dem *dem, PetscInt64 step, PetscReal time, const ParticleTotals &t,
                            const FluidStats *fluid = nullptr, const std::vector<PetscReal> *extra = nullptr);
PetscErrorCode MonitorTrack(MPI_Comm comm, Monitor *m, Dem *dem, PetscInt64 step, PetscReal time);
// Closes monitor.csv and track.csv at the end of a run, checked (collective).
PetscErrorCode MonitorClose(MPI_Comm comm, Monitor *m);
PetscErrorCode MonitorDestroy(Monitor *m);

// particles.csv sorted by id: id,d,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz (readable by -insert_type file).
PetscErrorCode WriteParticlesCSV(DM swarm, const char *path);

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
