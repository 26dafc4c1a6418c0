// HDF5 snapshots with their XDMF series, checkpoints written atomically, and restart.
#include "fluidbed/options.hpp"
#include "fluidbed/simulation.hpp"

#include <cstdio>

namespace fluidbed {

namespace {
// 64-bit counters as HDF5 attributes: PETSc 3.18 writes no 64-bit integer attributes, doubles are exact below 2^53.
PetscErrorCode WriteCount(PetscViewer viewer, const char *name, PetscInt64 value)
{
  const PetscReal v = (PetscReal)value;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", name, PETSC_REAL, &v));
  PetscFunctionReturn(0);
}
PetscErrorCode ReadCount(PetscViewer viewer, const char *name, PetscInt64 *value)
{
  PetscReal v;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", name, PETSC_REAL, NULL, &v));
  *value = (PetscInt64)v;
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode OutputScheduleSetFromOptions(Simulation *sim)
{
  OutputSchedule &o       = sim->output;
  PetscBool       reserve = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(sim->comm, "", "HDF5 output, checkpoints and restart", "Output");
  PetscCall(OptionsReal(PetscOptionsObject, "-output_interval",
                        "Simulated time between HDF5 snapshots (snapshot_NNNNN.h5 + particles.xmf for ParaView; 0: none)", "s",
                        NonNegative(), &o.interval, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-checkpoint_interval",
                        "Simulated time between checkpoints (0: none); the last step is always checkpointed when set", "s", NonNegative(),
                        &o.checkpoint_interval, NULL));
  PetscCall(PetscOptionsString(
    "-checkpoint_file", "Checkpoint path (default <output_dir>/checkpoint.h5; its directory must exist); written to .tmp, then renamed", "",
    o.checkpoint_file, o.checkpoint_file, sizeof(o.checkpoint_file), NULL));
  PetscCall(PetscOptionsString("-restart", "Continue from this checkpoint (any number of ranks); the scene's options must match it", "",
                               o.restart, o.restart, sizeof(o.restart), NULL));
  PetscBool reserve = PETSC_TRUE;
  PetscCall(
    PetscOptionsBool("-output_reserve",
                     "Reserve each HDF5 file's space before writing it, so that a full disk or a file-size limit stops the run cleanly "
                     "on every rank (off: a failure inside parallel HDF5 aborts the job, still with exit status 3)",
                     "", reserve, &reserve, NULL));
  PetscOptionsEnd();
  OutputSetReserve(reserve);
  if (!o.checkpoint_file[0])
    PetscCall(PetscSNPrintf(o.checkpoint_file, sizeof(o.checkpoint_file), "%s/%s", sim->run.output_dir, run_files::checkpoint));
  o.next            = 0.0; // the initial state is the first snapshot
  o.next_checkpoint = o.checkpoint_interval;
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationWriteSeriesXdmf(Simulation *sim)
{
  const std::vector<SnapshotRecord> &series = sim->output.series;

  PetscFunctionBeginUser;
  if (sim->swarm) PetscCall(XdmfWriteParticles(sim->comm, sim->run.output_dir, sim->domain.dim, series));
  if (sim->fluid) PetscCall(XdmfWriteFluid(sim->comm, sim->run.output_dir, sim->domain, sim->grids.fluid, series));
  PetscFunctionReturn(0);
}

namespace {
// The particle and gas data of a snapshot or (full) a checkpoint, the bulk of the file.
PetscErrorCode SimulationHDF5Bytes(Simulation *sim, PetscBool full, PetscInt64 *bytes)
{
  PetscInt64 part = 0, gas = 0;

  PetscFunctionBeginUser;
  if (sim->swarm) PetscCall(ParticlesHDF5Bytes(sim->swarm, full, &part));
  if (sim->fluid) PetscCall(FluidHDF5Bytes(sim->fluid, full, &gas));
  *bytes = part + gas;
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode SimulationWriteSnapshot(Simulation *sim)
{
  OutputSchedule   &o    = sim->output;
  const std::string name = run_files::Snapshot((PetscInt)o.series.size()), path = std::string(sim->run.output_dir) + "/" + name;
  PetscInt64        n = 0, bytes;

  PetscFunctionBeginUser;
  if (sim->swarm) PetscCall(ParticlesGlobalCount(sim->swarm, &n));
  PetscCall(SimulationHDF5Bytes(sim, PETSC_FALSE, &bytes));
  // the XDMF series lists a snapshot only once its file is complete
  PetscCall(WriteHDF5File(sim->comm, path, bytes, [&](PetscViewer viewer) {
    PetscFunctionBeginUser;
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time", PETSC_REAL, &sim->time));
    if (sim->swarm) PetscCall(ParticlesWriteHDF5(sim->swarm, viewer, PETSC_FALSE));
    if (sim->fluid) PetscCall(FluidWriteHDF5(sim->fluid, viewer, PETSC_FALSE));
    PetscFunctionReturn(0);
  }));
  o.series.push_back({sim->time, name, n});
  PetscCall(SimulationWriteSeriesXdmf(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationWriteCheckpoint(Simulation *sim)
{
  OutputSchedule &o = sim->output;
  PetscMPIInt     rank, size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(sim->comm, &rank));
  PetscCallMPI(MPI_Comm_size(sim->comm, &size));
  // Migration, contact-history sync and neighbour lists now, as a restart does when it loads the checkpoint: both
  // runs then continue from the same ownership of particles by ranks (the coupling's cell sums depend on it).
  if (sim->dem) PetscCall(DemRebuild(sim->dem));
  // the snapshot series, so that particles.xmf continues after a restart
  const PetscInt         ns = rank ? 0 : (PetscInt)o.series.size();
  std::vector<PetscReal> rows(2 * (std::size_t)ns);
  for (PetscInt k = 0; k < ns; ++k) {
    rows[2 * (std::size_t)k]     = o.series[(std::size_t)k].time;
    rows[2 * (std::size_t)k + 1] = (PetscReal)o.series[(std::size_t)k].particles;
  }
  const PetscInt total = (PetscInt)o.series.size();
  PetscInt64     bytes;
  PetscCall(SimulationHDF5Bytes(sim, PETSC_TRUE, &bytes));
  PetscCall(WriteHDF5File(sim->comm, o.checkpoint_file, bytes, [&](PetscViewer viewer) {
    PetscFunctionBeginUser;
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time", PETSC_REAL, &sim->time));
    PetscCall(WriteCount(viewer, "step", sim->step));
    if (sim->dem) PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "dt", PETSC_REAL, &sim->dem->par.dt));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "dim", PETSC_INT, &sim->domain.dim));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "ranks", PETSC_INT, &size));
    if (sim->dem) PetscCall(WriteCount(viewer, "particles_outlet", sim->dem->stats.outlet_removed));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "monitor_next", PETSC_REAL, &sim->monitor.next));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "snapshot_next", PETSC_REAL, &o.next));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "checkpoint_next", PETSC_REAL, &o.next_checkpoint));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "snapshots", PETSC_INT, &total));
    if (total) {
      Vec v;
      PetscCall(VecCreateMPIWithArray(sim->comm, 2, 2 * ns, PETSC_DECIDE, rows.data(), &v));
      PetscCall(PetscObjectSetName((PetscObject)v, "snapshot_series"));
      PetscCall(VecView(v, viewer));
      PetscCall(VecDestroy(&v));
    }
    if (sim->swarm) PetscCall(ParticlesWriteHDF5(sim->swarm, viewer, PETSC_TRUE));
    if (sim->fluid) PetscCall(FluidWriteHDF5(sim->fluid, viewer, PETSC_TRUE));
    if (sim->coupling) PetscCall(CouplingWriteHDF5(sim->coupling, viewer));
    PetscCall(BedAveragesWriteHDF5(sim->averages, viewer));
    PetscFunctionReturn(0);
  }));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationReadCheckpoint(Simulation *sim)
{
  OutputSchedule &o = sim->output;
  PetscViewer     viewer;
  PetscInt        dim, total = 0;
  PetscReal       dt;
  PetscBool       exists;

  PetscFunctionBeginUser;
  PetscCall(PetscTestFile(o.restart, 'r', &exists));
  PetscCheck(exists, sim->comm, PETSC_ERR_FILE_OPEN, "-restart: cannot read %s", o.restart);
  PetscCall(PetscViewerHDF5Open(sim->comm, o.restart, FILE_MODE_READ, &viewer));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "dim", PETSC_INT, NULL, &dim));
  PetscCheck(dim == sim->domain.dim, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds a %dD run; -domain_dim is %d", o.restart, (int)dim,
             (int)sim->domain.dim);
  if (sim->dem) {
    PetscBool has_dt;
    PetscCall(PetscViewerHDF5HasAttribute(viewer, "/", "dt", &has_dt));
    PetscCheck(has_dt, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds no particles; the options turn them on", o.restart);
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "dt", PETSC_REAL, NULL, &dt));
    PetscCheck(PetscAbsReal(dt - sim->dem->par.dt) <= 1e-12 * dt, sim->comm, PETSC_ERR_USER_INPUT,
               "-restart %s was run with dt = %.10g s, the options give %.10g s: restart with the same particle and contact options",
               o.restart, (double)dt, (double)sim->dem->par.dt);
    PetscCall(ReadCount(viewer, "particles_outlet", &sim->dem->stats.outlet_removed));
  }
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "time", PETSC_REAL, NULL, &sim->time));
  PetscCall(ReadCount(viewer, "step", &sim->step));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "monitor_next", PETSC_REAL, NULL, &sim->monitor.next));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "snapshot_next", PETSC_REAL, NULL, &o.next));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "checkpoint_next", PETSC_REAL, NULL, &o.next_checkpoint));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "snapshots", PETSC_INT, NULL, &total));
  o.series.clear();
  if (total) {
    Vec                v;
    const PetscScalar *a;
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2 * total, &v)); // every rank keeps the (short) series
    PetscCall(PetscObjectSetName((PetscObject)v, "snapshot_series"));
    PetscCall(VecSetBlockSize(v, 2));
    {
      PetscViewer self;
      PetscCall(PetscViewerHDF5Open(PETSC_COMM_SELF, o.restart, FILE_MODE_READ, &self));
      PetscCall(VecLoad(v, self));
      PetscCall(PetscViewerDestroy(&self));
    }
    PetscCall(VecGetArrayRead(v, &a));
    for (PetscInt k = 0; k < total; ++k) o.series.push_back({a[2 * k], run_files::Snapshot(k), (PetscInt64)a[2 * k + 1]});
    PetscCall(VecRestoreArrayRead(v, &a));
    PetscCall(VecDestroy(&v));
  }
  if (sim->swarm) {
    PetscCall(ParticlesReadHDF5(sim->swarm, viewer, sim->domain, sim->grids.particle));
    PetscCall(ParticlesGlobalCount(sim->swarm, &sim->inserted.count));
  }
  if (sim->fluid) {
    PetscBool has;
    PetscCall(PetscViewerHDF5HasGroup(viewer, "/fluid", &has));
    PetscCheck(has, sim->comm, PETSC_ERR_USER_INPUT, "-restart %s holds no gas state; the options turn the gas on", o.restart);
    PetscCall(FluidReadHDF5(sim->fluid, viewer));
  }
  if (sim->coupling) PetscCall(CouplingReadHDF5(sim->coupling, viewer));
  PetscCall(BedAveragesReadHDF5(sim->averages, viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationRemoveStaleOutput(Simulation *sim)
{
  const OutputSchedule &o   = sim->output;
  const std::string     dir = sim->run.output_dir;

  PetscFunctionBeginUser;
  if (!o.restart[0]) {
    std::vector<std::string> also; // this run's checkpoint, wherever -checkpoint_file keeps it
    if (o.checkpoint_interval > 0) also.push_back(o.checkpoint_file);
    PetscCall(RemovePreviousRun(sim->comm, dir, also, {sim->inserted.file}));
  } else {
    PetscInt removed;
    PetscCall(RemoveSnapshotsAfter(sim->comm, dir, (PetscInt)o.series.size(), {o.restart}, &removed));
    if (removed && !o.series.empty()) PetscCall(SimulationWriteSeriesXdmf(sim)); // the XDMF files listed the removed snapshots
    else if (removed)
      for (const char *name : {run_files::particles_xdmf, run_files::fluid_xdmf}) PetscCall(RemoveRunFile(sim->comm, dir + "/" + name));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationOutputStep(Simulation *sim, PetscBool last)
{
  OutputSchedule &o  = sim->output;
  const PetscReal dt = sim->dem ? sim->dem->par.dt : FluidGetStats(sim->fluid).dt, eps = 0.5 * dt;

  PetscFunctionBeginUser;
  PetscCall(BedAveragesStep(sim->averages)); // before this step's checkpoint, which then holds its sample
  if (o.interval > 0 && sim->time >= o.next - eps) {
    PetscCall(SimulationWriteSnapshot(sim));
    while (o.next <= sim->time + eps) o.next += o.interval;
  }
  const PetscBool checkpoint_due = (PetscBool)(o.checkpoint_interval > 0 && (sim->dem ? sim->step >= StepAtTime(o.next_checkpoint, dt)
                                                                                      : sim->time >= o.next_checkpoint - eps));
  if (o.checkpoint_interval > 0 && (checkpoint_due || last)) {
    while (o.next_checkpoint <= sim->time + eps) o.next_checkpoint += o.checkpoint_interval;
    PetscCall(SimulationWriteCheckpoint(sim));
  }
  PetscFunctionReturn(0);
}

} // namespace fluidbed
