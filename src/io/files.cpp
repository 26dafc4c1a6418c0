// Checked writes: every output of a run goes through these (include/fluidbed/io.hpp). A failed write raises
// PETSC_ERR_FILE_WRITE on every rank with one line naming the file and the reason; files that are replaced are
// written to <path>.tmp and renamed; a previous run's files are removed before a fresh run writes.
#include "fluidbed/hdf5io.hpp"
#include "fluidbed/io.hpp"
#include "fluidbed/status.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <map>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

namespace fluidbed {

namespace run_files {

std::string Snapshot(PetscInt index)
{
  char name[64];
  snprintf(name, sizeof(name), "snapshot_%05d.h5", (int)index);
  return name;
}

PetscInt SnapshotIndex(const std::string &name)
{
  const std::string prefix = "snapshot_", suffix = ".h5";
  if (name.size() < prefix.size() + 5 + suffix.size() || name.compare(0, prefix.size(), prefix) ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix))
    return -1;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return -1;
  return (PetscInt)std::stoll(digits);
}

std::string WithoutTmp(const std::string &file, bool *temporary)
{
  const std::string tmp = ".tmp";
  *temporary            = file.size() > tmp.size() && !file.compare(file.size() - tmp.size(), tmp.size(), tmp);
  return *temporary ? file.substr(0, file.size() - tmp.size()) : file;
}

bool IsRunFile(const std::string &file)
{
  bool              temporary;
  const std::string name = WithoutTmp(file, &temporary);
  for (const char *fixed :
       {monitor, track, particles, fluid_cells, summary, particles_xdmf, fluid_xdmf, averages, averages_xdmf, checkpoint, fluid_nodes})
    if (name == fixed) return true;
  return SnapshotIndex(name) >= 0 || !name.compare(0, strlen(guard_prefix), guard_prefix);
}

} // namespace run_files

namespace {

// The outcome of an operation that rank 0 did alone (path and err are known there only): every rank raises the
// same error.
PetscErrorCode RootVerdict(MPI_Comm comm, int err, const std::string &path, const char *verb)
{
  std::string what = path;
  int         len  = (int)path.size();

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  if (err) {
    PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, 0, comm));
    what.resize((std::size_t)len);
    PetscCallMPI(MPI_Bcast(what.data(), len, MPI_CHAR, 0, comm));
  }
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "cannot %s %s (%s)", verb, what.c_str(), strerror(err));
  PetscFunctionReturn(0);
}

// errno after a failed call, never 0 (a library that failed without saying why).
int Reason()
{
  return errno ? errno : EIO;
}

// Creates and removes a file in dir: 0 when that works, else the errno.
int ProbeDirectory(const std::string &dir)
{
  const std::string probe = dir + "/.fluidbed_probe." + std::to_string((long)getpid());
  const int         fd    = open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) return Reason();
  int err = write(fd, "\n", 1) == 1 ? 0 : Reason(); // a full disk takes an empty file but not its first block
  if (close(fd) && !err) err = Reason();
  unlink(probe.c_str());
  return err;
}

// The size of an open file (the bytes written so far).
long long FileSize(FILE *fp)
{
  struct stat st;
  return fstat(fileno(fp), &st) ? 0 : (long long)st.st_size;
}

// The ends of a failed write on rank 0: a replaced file leaves no temporary behind and the previous file as it was;
// a log file is cut back to its last complete row.
void Abandon(OutputFile *f)
{
  if (f->fp) fclose(f->fp); // what it still flushes is cut off below
  f->fp = nullptr;
  if (f->mode == OutputFile::REPLACE) unlink((f->path + ".tmp").c_str());
  else if (truncate(f->path.c_str(), (off_t)f->good)) {
    // nothing more can be done: the error that stops the run names the file
  }
}

// Removal of stale files on rank 0: regular files and links only, never one of the kept files (compared by
// device and inode, so another spelling of the same path is kept too).
struct Removal {
  std::vector<struct stat> kept;
  std::vector<std::string> removed; // as labelled
  std::string              failed;  // the first file that could not be removed, with its errno in err
  int                      err = 0;

  explicit Removal(const std::vector<std::string> &keep)
  {
    for (const std::string &k : keep) {
      struct stat st;
      if (!k.empty() && !stat(k.c_str(), &st)) kept.push_back(st);
    }
  }
  void Remove(const std::string &path, const std::string &label)
  {
    struct stat st, target;
    if (lstat(path.c_str(), &st) || !(S_ISREG(st.st_mode) || S_ISLNK(st.st_mode))) return;
    if (!stat(path.c_str(), &target) &&
        std::any_of(kept.begin(), kept.end(), [&](const struct stat &k) { return k.st_dev == target.st_dev && k.st_ino == target.st_ino; }))
      return;
    if (!unlink(path.c_str())) removed.push_back(label);
    else if (!err) {
      err    = Reason();
      failed = path;
    }
  }
  // The entries of dir that stale(name, arg) selects.
  void Directory(const std::string &dir, bool (*stale)(const std::string &, PetscInt), PetscInt arg)
  {
    DIR *d = opendir(dir.c_str());
    if (!d) {
      if (!err) {
        err    = Reason();
        failed = dir;
      }
      return;
    }
    for (struct dirent *e; (e = readdir(d));)
      if (stale(e->d_name, arg)) Remove(dir + "/" + e->d_name, e->d_name);
    closedir(d);
    std::sort(removed.begin(), removed.end());
  }
};

// "a, b, snapshot_00000.h5 .. snapshot_00041.h5 (42 snapshots)": the snapshots as a range, the other names in full.
std::string ListFiles(const std::vector<std::string> &names)
{
  std::vector<std::string> snapshots, others;
  for (const std::string &n : names) (run_files::SnapshotIndex(n) >= 0 ? snapshots : others).push_back(n);
  std::string text;
  for (const std::string &n : others) text += (text.empty() ? "" : ", ") + n;
  if (snapshots.size() == 1) text += (text.empty() ? "" : ", ") + snapshots[0];
  else if (!snapshots.empty())
    text +=
      (text.empty() ? "" : ", ") + snapshots.front() + " .. " + snapshots.back() + " (" + std::to_string(snapshots.size()) + " snapshots)";
  return text;
}

bool IsRunFileName(const std::string &name, PetscInt)
{
  return run_files::IsRunFile(name);
}

// A snapshot numbered `first` or later, or the temporary of any snapshot.
bool IsSnapshotFrom(const std::string &file, PetscInt first)
{
  bool           temporary;
  const PetscInt index = run_files::SnapshotIndex(run_files::WithoutTmp(file, &temporary));
  return index >= 0 && (temporary || index >= first);
}

// The first error a write raised, caught instead of printed.
struct CaughtError {
  PetscErrorCode code = 0;
  std::string    message;
};
PetscErrorCode CatchError(MPI_Comm, int, const char *, const char *, PetscErrorCode n, PetscErrorType, const char *mess, void *ctx)
{
  CaughtError *c = (CaughtError *)ctx;
  if (!c->code) {
    c->code    = n;
    c->message = mess ? mess : "";
  }
  return n;
}

bool reserve_space = true; // -output_reserve

// The largest file written so far per kind of HDF5 file (its name without digits: every snapshot_NNNNN.h5 is one
// kind), the room to make for the next one of that kind when its data size is not known in full.
std::map<std::string, long long> &LargestOfKind()
{
  static std::map<std::string, long long> sizes;
  return sizes;
}
std::string Kind(const std::string &path)
{
  std::string k;
  for (char c : path.substr(path.rfind('/') == std::string::npos ? 0 : path.rfind('/') + 1))
    if (c < '0' || c > '9') k += c;
  return k;
}

// Makes room for a file of `bytes` at path (rank 0): the file is created and its blocks allocated, so that a full
// disk (ENOSPC) or a file-size limit (EFBIG) shows here, where rank 0 alone decides, and not inside parallel HDF5,
// whose ranks cannot recover from a failed write together. HDF5 then truncates the file and writes it anew. A file
// system that cannot allocate ahead (EOPNOTSUPP) is written without this check.
int Reserve(const std::string &path, long long bytes)
{
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return Reason();
  int err = bytes > 0 && fallocate(fd, 0, 0, (off_t)bytes) ? Reason() : 0;
  if (err == EOPNOTSUPP || err == ENOSYS) err = 0;
  if (close(fd) && !err) err = Reason();
  return err;
}

// Why HDF5 failed to write file (HDF5 does not keep the errno): a file-size limit the file reaches, or a full disk;
// 0 when neither explains it.
int WhyWriteFailed(const std::string &file, long long bytes)
{
  constexpr long long slack = 1 << 20;
  struct rlimit       limit;
  struct stat         st;
  struct statvfs      fs;
  const std::size_t   slash = file.rfind('/');
  const long long     size  = stat(file.c_str(), &st) ? 0 : (long long)st.st_size;
  if (!getrlimit(RLIMIT_FSIZE, &limit) && limit.rlim_cur != RLIM_INFINITY && (long long)limit.rlim_cur <= std::max(size, bytes) + slack)
    return EFBIG;
  if (!statvfs(slash == std::string::npos ? "." : file.substr(0, slash).c_str(), &fs) && (long long)(fs.f_bavail * fs.f_frsize) < slack)
    return ENOSPC;
  return 0;
}

// After a failed write on a single rank: closes what PETSc left open in the file, then the file, so that HDF5's
// own clean-up at MPI_Finalize does not meet a half-closed file. False when the file would not close (its last
// flush failed too, as when the file-size limit is reached inside HDF5): HDF5 keeps it open and its clean-up at
// MPI_Finalize would crash on it.
bool CloseAfterFailure(PetscViewer viewer)
{
  hid_t file;
  if (PetscViewerHDF5GetFileId(viewer, &file) || file < 0) return true;
  const unsigned     types = H5F_OBJ_DATASET | H5F_OBJ_GROUP | H5F_OBJ_DATATYPE | H5F_OBJ_ATTR | H5F_OBJ_LOCAL;
  const ssize_t      n     = H5Fget_obj_count(file, types);
  std::vector<hid_t> ids(n > 0 ? (std::size_t)n : 0);
  if (n > 0 && H5Fget_obj_ids(file, types, ids.size(), ids.data()) >= 0)
    for (hid_t id : ids) H5Iget_type(id) == H5I_ATTR ? H5Aclose(id) : H5Oclose(id);
  return H5Fclose(file) >= 0;
}

} // namespace

PetscErrorCode WriteAgree(MPI_Comm comm, int err, const std::string &path)
{
  int any;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&err, &any, 1, MPI_INT, MPI_MAX, comm));
  PetscCheck(!any, comm, PETSC_ERR_FILE_WRITE, "cannot write %s (%s)", path.c_str(), strerror(any));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputFileOpen(MPI_Comm comm, const std::string &path, OutputFile::Mode mode, OutputFile *f)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  *f      = OutputFile();
  f->path = path;
  f->mode = mode;
  if (!rank) {
    const std::string name = mode == OutputFile::REPLACE ? path + ".tmp" : path;
    f->fp                  = fopen(name.c_str(), mode == OutputFile::APPEND ? "a" : "w");
    if (!f->fp) f->err = Reason();
    else f->good = FileSize(f->fp);
  }
  PetscCall(WriteAgree(comm, f->err, path));
  PetscFunctionReturn(0);
}

void OutputFilePrintf(OutputFile *f, const char *fmt, ...)
{
  va_list args;
  if (!f->fp || f->err) return;
  va_start(args, fmt);
  if (vfprintf(f->fp, fmt, args) < 0) f->err = Reason();
  va_end(args);
}

PetscErrorCode OutputFileFlush(MPI_Comm comm, OutputFile *f)
{
  PetscFunctionBeginUser;
  if (f->fp && !f->err) {
    if (fflush(f->fp) || ferror(f->fp)) f->err = Reason();
    else f->good = FileSize(f->fp);
  }
  if (f->err) Abandon(f);
  PetscCall(WriteAgree(comm, f->err, f->path));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputFileClose(MPI_Comm comm, OutputFile *f)
{
  PetscFunctionBeginUser;
  if (f->fp && !f->err) {
    if (fflush(f->fp) || ferror(f->fp)) f->err = Reason();
    else f->good = FileSize(f->fp);
  }
  if (f->fp && !f->err) {
    FILE *fp = f->fp;
    f->fp    = nullptr;
    if (fclose(fp)) f->err = Reason();
    else if (f->mode == OutputFile::REPLACE && rename((f->path + ".tmp").c_str(), f->path.c_str())) f->err = Reason();
  }
  if (f->err) Abandon(f);
  PetscCall(WriteAgree(comm, f->err, f->path));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputWriteText(MPI_Comm comm, const std::string &path, const std::string &text)
{
  OutputFile f;

  PetscFunctionBeginUser;
  PetscCall(OutputFileOpen(comm, path, OutputFile::REPLACE, &f));
  if (f.fp && fwrite(text.data(), 1, text.size(), f.fp) != text.size()) f.err = Reason();
  PetscCall(OutputFileClose(comm, &f));
  PetscFunctionReturn(0);
}

PetscErrorCode CommitFile(MPI_Comm comm, const std::string &path)
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Barrier(comm)); // every rank has closed the file
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank && rename((path + ".tmp").c_str(), path.c_str())) {
    err = Reason();
    unlink((path + ".tmp").c_str());
  }
  PetscCall(RootVerdict(comm, err, path, "write"));
  PetscFunctionReturn(0);
}

void OutputSetReserve(PetscBool reserve)
{
  reserve_space = reserve;
}

PetscErrorCode WriteHDF5File(MPI_Comm comm, const std::string &path, PetscInt64 bytes,
                             const std::function<PetscErrorCode(PetscViewer)> &write)
{
  const std::string tmp    = path + ".tmp";
  PetscViewer       viewer = nullptr;
  CaughtError       caught;
  H5E_auto2_t       h5_report;
  void             *h5_data;
  PetscMPIInt       rank, size;
  int               err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (!rank && reserve_space) {
    // the data, HDF5's headers (a few kB per dataset), and never less than the largest file of this kind so far
    const long long room = std::max((long long)bytes + (long long)bytes / 32 + (128 << 10), LargestOfKind()[Kind(path)]);
    err                  = Reserve(tmp, room);
    if (err) unlink(tmp.c_str());
  }
  PetscCall(RootVerdict(comm, err, path, "write"));

  // HDF5 would print its own error stack: PETSc's error is caught instead and becomes one line naming the file.
  PetscCheck(H5Eget_auto2(H5E_DEFAULT, &h5_report, &h5_data) >= 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "H5Eget_auto2 failed");
  PetscCheck(H5Eset_auto2(H5E_DEFAULT, NULL, NULL) >= 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "H5Eset_auto2 failed");
  PetscCall(PetscPushErrorHandler(CatchError, &caught));
  PetscErrorCode ierr = PetscViewerHDF5Open(comm, tmp.c_str(), FILE_MODE_WRITE, &viewer);
  if (!ierr) ierr = write(viewer);
  if (!ierr) ierr = PetscViewerDestroy(&viewer);
  bool closed = true;
  if (ierr && viewer && size == 1) closed = CloseAfterFailure(viewer);
  PetscCall(PetscPopErrorHandler());
  PetscCheck(H5Eset_auto2(H5E_DEFAULT, h5_report, h5_data) >= 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "H5Eset_auto2 failed");
  if (ierr) {
    const int         found = WhyWriteFailed(tmp, bytes);
    const std::string why   = found ? strerror(found) : "HDF5: " + caught.message;
    unlink(tmp.c_str());
    if (size > 1 || !closed) {
      // The other ranks may be waiting inside a collective HDF5 call that this rank left, or HDF5 holds a file it
      // cannot close and would crash on at MPI_Finalize: only ending the job now can release them. The previous
      // file of this name is untouched.
      fprintf(stderr, "fluidbed: error: cannot write %s (%s)\n", path.c_str(), why.c_str());
      fflush(stderr);
      MPI_Abort(comm, EXIT_OUTPUT);
    }
    SETERRQ(comm, PETSC_ERR_FILE_WRITE, "cannot write %s (%s)", path.c_str(), why.c_str());
  }
  PetscCall(CommitFile(comm, path));
  if (!rank) {
    struct stat st;
    if (!stat(path.c_str(), &st)) LargestOfKind()[Kind(path)] = std::max(LargestOfKind()[Kind(path)], (long long)st.st_size);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MakeDirectory(MPI_Comm comm, const char *dir)
{
  PetscMPIInt rank;
  int         err[2] = {0, 0}; // creating the directory, writing in it

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    std::string path;
    for (const char *c = dir; *c && !err[0]; ++c) {
      path += *c;
      if ((*c == '/' || !c[1]) && mkdir(path.c_str(), 0775) && errno != EEXIST) err[0] = errno;
    }
    if (!err[0]) err[1] = ProbeDirectory(dir);
  }
  PetscCallMPI(MPI_Bcast(err, 2, MPI_INT, 0, comm));
  PetscCheck(!err[0], comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot create the directory (%s)", dir, strerror(err[0]));
  PetscCheck(!err[1], comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot write a file in the directory (%s)", dir, strerror(err[1]));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckFileLocation(MPI_Comm comm, const std::string &file, const char *option)
{
  const std::size_t slash = file.rfind('/');
  const std::string dir   = slash == std::string::npos ? "." : slash == 0 ? "/" : file.substr(0, slash);
  PetscMPIInt       rank;
  int               err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) err = ProbeDirectory(dir);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "%s %s: cannot write a file in %s (%s)", option, file.c_str(), dir.c_str(), strerror(err));
  PetscFunctionReturn(0);
}

PetscErrorCode RemovePreviousRun(MPI_Comm comm, const std::string &dir, const std::vector<std::string> &also,
                                 const std::vector<std::string> &keep)
{
  PetscMPIInt              rank;
  int                      err = 0;
  std::vector<std::string> removed;
  std::string              failed;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    Removal r(keep);
    r.Directory(dir, IsRunFileName, 0);
    for (const std::string &path : also) { // a file of this run kept outside dir (-checkpoint_file) and its temporary
      r.Remove(path, path);
      r.Remove(path + ".tmp", path + ".tmp");
    }
    err     = r.err;
    failed  = r.failed;
    removed = r.removed;
  }
  PetscCall(RootVerdict(comm, err, failed, "remove"));
  if (!rank && !removed.empty())
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "Output: removed %d file(s) of a previous run from %s: %s\n", (int)removed.size(), dir.c_str(),
                          ListFiles(removed).c_str()));
  PetscFunctionReturn(0);
}

PetscErrorCode RemoveSnapshotsAfter(MPI_Comm comm, const std::string &dir, PetscInt snapshots, const std::vector<std::string> &keep,
                                    PetscInt *count)
{
  PetscMPIInt              rank;
  int                      err = 0, n = 0;
  std::vector<std::string> removed;
  std::string              failed;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    Removal r(keep);
    r.Directory(dir, IsSnapshotFrom, snapshots);
    err     = r.err;
    failed  = r.failed;
    removed = r.removed;
    n       = (int)removed.size();
  }
  PetscCall(RootVerdict(comm, err, failed, "remove"));
  PetscCallMPI(MPI_Bcast(&n, 1, MPI_INT, 0, comm));
  *count = n;
  if (!rank && n)
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "Output: removed %d snapshot file(s) written after the checkpoint from %s: %s\n", n, dir.c_str(),
                          ListFiles(removed).c_str()));
  PetscFunctionReturn(0);
}

PetscErrorCode RemoveRunFile(MPI_Comm comm, const std::string &path)
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank && unlink(path.c_str()) && errno != ENOENT) err = Reason();
  PetscCall(RootVerdict(comm, err, path, "remove"));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
