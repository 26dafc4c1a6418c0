#include "fluidbed/io.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/kernels/verlet.hpp"

#include <algorithm>
#include <fstream>
#include <string>
#include <utility>

namespace fluidbed {

PetscErrorCode ComputeParticleTotals(Dem *dem, ParticleTotals *t)
{
  ParticleArrays p;
  PetscReal      loc[7] = {0, 0, 0, 0, 0, 0, 0}, glob[7], mx[2], gmx[2]; // KE, KE_rot, PE, momentum, contacts
  const Domain  &dom    = DemGetDomain(dem);
  MPI_Comm       comm   = PetscObjectComm((PetscObject)DemGetSwarm(dem));

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(DemGetSwarm(dem), &p));
  PetscReal vmax2 = 0;
  for (PetscInt i = 0; i < p.n; ++i) {
    const PetscReal  m = DemGetProps(dem).Mass(p.d[i]), I = kernels::sphere_inertia(m, p.d[i]);
    const PetscReal *v = &p.v[3 * i], *w = &p.w[3 * i];
    const PetscReal  v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    loc[0] += 0.5 * m * v2;
    loc[1] += 0.5 * I * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    PetscReal gx = 0;
    for (PetscInt a = 0; a < p.dim; ++a) gx += dom.gravity[a] * (p.x[p.dim * i + a] - dom.lo[a]);
    loc[2] -= m * gx;
    for (int a = 0; a < 3; ++a) loc[3 + a] += m * v[a];
    vmax2 = PetscMax(vmax2, v2);
  }
  loc[6] = (PetscReal)DemGetStats(dem)->contacts;
  PetscCall(ParticleArraysRestore(DemGetSwarm(dem), &p));
  PetscCallMPI(MPI_Allreduce(loc, glob, 7, MPIU_REAL, MPI_SUM, comm));
  mx[0] = PetscSqrtReal(vmax2);
  mx[1] = DemGetStats(dem)->max_overlap_rel;
  PetscCallMPI(MPI_Allreduce(mx, gmx, 2, MPIU_REAL, MPI_MAX, comm));
  PetscCall(ParticlesGlobalCount(DemGetSwarm(dem), &t->count));
  t->ke_trans = glob[0];
  t->ke_rot   = glob[1];
  t->pe_grav  = glob[2];
  for (int a = 0; a < 3; ++a) t->momentum[a] = glob[3 + a];
  t->contacts_per_particle          = t->count ? glob[6] / (PetscReal)t->count : 0.0;
  t->max_speed                      = gmx[0];
  t->max_overlap_rel                = gmx[1];
  DemGetStats(dem)->max_overlap_rel = 0.0; // the next row reports the maximum over its own interval
  PetscFunctionReturn(0);
}

namespace {

// Opens a log file of rows keyed by their first column, the step: a fresh file with its header, or on a restart the
// file continued after last_step, rows written after it (by the run that is continued, past the checkpoint) dropped.
PetscErrorCode OpenLog(MPI_Comm comm, const std::string &path, PetscBool append, PetscInt64 last_step, const std::string &header,
                       OutputFile *f)
{
  PetscMPIInt rank;
  int         exists = 0, dropped = 0;
  std::string kept;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank && append) {
    std::ifstream in(path);
    exists = in.good();
    for (std::string line; exists && std::getline(in, line);) {
      const bool row = !line.empty() && line[0] >= '0' && line[0] <= '9'; // the header starts with a letter
      if (row && std::stoll(line) > (long long)last_step) ++dropped;
      else kept += line + "\n";
    }
  }
  PetscCallMPI(MPI_Bcast(&exists, 1, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(&dropped, 1, MPI_INT, 0, comm));
  if (dropped) {
    PetscCall(OutputWriteText(comm, path, kept));
    PetscCall(PetscPrintf(comm, "Output: dropped %d row(s) after step %lld (written after the checkpoint) from %s\n", dropped,
                          (long long)last_step, path.c_str()));
  }
  PetscCall(OutputFileOpen(comm, path, exists ? OutputFile::APPEND : OutputFile::CREATE, f));
  if (!exists) OutputFilePrintf(f, "%s\n", header.c_str());
  PetscCall(OutputFileFlush(comm, f));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode MonitorCreate(MPI_Comm comm, const char *dir, PetscReal t_final, PetscBool append, PetscInt64 last_step, Monitor *m)
{
  PetscFunctionBeginUser;
  m->interval = t_final / 200.0;
  PetscOptionsBegin(comm, "monitor_", "Monitor: global quantities (monitor.csv)", "Output");
  PetscCall(OptionsReal(PetscOptionsObject, "-dt", "Simulated time between rows of monitor.csv (default t_final / 200; 0: every step)", "s",
                        NonNegative(), &m->interval, NULL));
  PetscOptionsEnd();
  std::string header = "step,time";
  for (const MonitorColumn &c : m->columns) header += "," + c.name;
  PetscCall(OpenLog(comm, std::string(dir) + "/" + run_files::monitor, append, last_step, header, &m->csv));
  PetscFunctionReturn(0);
}

PetscErrorCode MonitorWrite(MPI_Comm comm, Monitor *m, PetscInt64 step, PetscReal time, const std::vector<PetscReal> &values)
{
  OutputFile *f = &m->csv;

  PetscFunctionBeginUser;
  PetscCheck(values.size() == m->columns.size(), comm, PETSC_ERR_PLIB, "monitor.csv: %d values for %d columns", (int)values.size(),
             (int)m->columns.size());
  m->last_row_step = step;
  OutputFilePrintf(f, "%lld,%.10e", (long long)step, (double)time);
  for (std::size_t k = 0; k < values.size(); ++k) {
    OutputFilePrintf(f, ",");
    if (m->columns[k].format) OutputFilePrintf(f, m->columns[k].format, (double)values[k]);
    else OutputFilePrintf(f, "%lld", (long long)values[k]); // a count, exact in a double
  }
  OutputFilePrintf(f, "\n");
  PetscCall(OutputFileFlush(comm, f));
  PetscFunctionReturn(0);
}

namespace {

// track.csv: the state of each particle of -monitor_track_ids present in the system, every -monitor_track_every steps.
class ParticleTrack final : public Output {
public:
  ParticleTrack(std::vector<PetscInt64> ids, PetscInt every) : ids_(std::move(ids)), every_(every) {}
  const char *Name() const override { return "track"; }

  // A fresh file with its header, or on a restart the file continued after the checkpoint's step.
  PetscErrorCode Start(const RunView &run) override
  {
    PetscFunctionBeginUser;
    PetscCall(OpenLog(run.comm, std::string(run.output_dir) + "/" + run_files::track, run.restart[0] ? PETSC_TRUE : PETSC_FALSE, run.step,
                      "step,time,id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz", &file_));
    PetscFunctionReturn(0);
  }

  PetscErrorCode Step(const RunView &run) override
  {
    PetscFunctionBeginUser;
    stepped_ = true;
    PetscCall(Write(run));
    PetscFunctionReturn(0);
  }

  // Closed, checked, at the end of a run no guard stopped (a stopped run's rows are flushed; Destroy closes it).
  PetscErrorCode Finalize(const RunView &run) override
  {
    PetscFunctionBeginUser;
    PetscCall(OutputFileClose(run.comm, &file_));
    PetscFunctionReturn(0);
  }

  // A fresh run stopped at its initial state, before any Step: the row of that state, as the run writes its monitor row
  // before the guards' verdict there (after a step, the state that failed has no row).
  PetscErrorCode Stopped(const RunView &run) override
  {
    PetscFunctionBeginUser;
    if (!stepped_ && !run.restart[0]) PetscCall(Write(run));
    PetscFunctionReturn(0);
  }

  PetscErrorCode Destroy() override
  {
    PetscFunctionBeginUser;
    if (file_.fp) fclose(file_.fp); // left open only by a run that stopped early: its rows are flushed
    file_ = OutputFile();
    PetscFunctionReturn(0);
  }

private:
  // The rows of run.step, every -monitor_track_every steps (collective).
  PetscErrorCode Write(const RunView &run)
  {
    const std::size_t      nt = ids_.size();
    std::vector<PetscReal> loc(nt * 13, 0.0), glob(nt * 13);
    ParticleArrays         p;

    PetscFunctionBeginUser;
    if (!run.swarm || run.step % every_) PetscFunctionReturn(0);
    PetscCall(ParticleArraysGet(run.swarm, &p));
    for (PetscInt i = 0; i < p.n; ++i) {
      const auto it = std::find(ids_.begin(), ids_.end(), p.id[i]);
      if (it == ids_.end()) continue;
      PetscReal *row = &loc[13 * (std::size_t)(it - ids_.begin())];
      row[0]         = 1.0; // found
      for (PetscInt a = 0; a < p.dim; ++a) row[1 + a] = p.x[p.dim * i + a];
      for (int a = 0; a < 3; ++a) {
        row[4 + a]  = p.v[3 * i + a];
        row[7 + a]  = p.w[3 * i + a];
        row[10 + a] = p.f[3 * i + a];
      }
    }
    PetscCall(ParticleArraysRestore(run.swarm, &p));
    PetscCallMPI(MPI_Reduce(loc.data(), glob.data(), (int)loc.size(), MPIU_REAL, MPI_SUM, 0, run.comm));
    if (file_.fp) {
      for (std::size_t k = 0; k < nt; ++k) {
        const PetscReal *r = &glob[13 * k];
        if (r[0] == 0.0) continue; // not (or no longer) in the system
        OutputFilePrintf(&file_, "%lld,%.12e,%lld,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e\n",
                         (long long)run.step, (double)run.time, (long long)ids_[k], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9],
                         r[10], r[11], r[12]);
      }
    }
    PetscCall(OutputFileFlush(run.comm, &file_));
    PetscFunctionReturn(0);
  }

  std::vector<PetscInt64> ids_;
  PetscInt                every_;
  OutputFile              file_;
  bool                    stepped_ = false; // a Step came (the initial state's row is written there)
};

} // namespace

PetscErrorCode ParticleTrackCreate(const RunView &run, std::unique_ptr<Output> *out)
{
  PetscInt  ids[256] = {0}, nids = 256, every = 1; // -help prints the first entry as the default
  PetscBool set = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(run.comm, "monitor_", "Tracked particles (track.csv)", "Output");
  PetscCall(OptionsIntArray(PetscOptionsObject, "-track_ids", "Particle ids whose state goes to track.csv", PETSC_MIN_INT, PETSC_MAX_INT,
                            ids, &nids, &set));
  PetscCall(OptionsInt(PetscOptionsObject, "-track_every", "Steps between rows of track.csv", 1, PETSC_MAX_INT, &every, NULL));
  PetscOptionsEnd();
  out->reset();
  if (set && nids > 0) *out = std::make_unique<ParticleTrack>(std::vector<PetscInt64>(ids, ids + nids), every);
  PetscFunctionReturn(0);
}

PetscErrorCode MonitorClose(MPI_Comm comm, Monitor *m)
{
  PetscFunctionBeginUser;
  PetscCall(OutputFileClose(comm, &m->csv));
  PetscFunctionReturn(0);
}

PetscErrorCode MonitorDestroy(Monitor *m)
{
  PetscFunctionBeginUser;
  if (m->csv.fp) fclose(m->csv.fp); // left open only by a run that stopped early: its rows are flushed
  m->csv = OutputFile();
  PetscFunctionReturn(0);
}

} // namespace fluidbed
