// HDF5 snapshots with their XDMF series, checkpoints written atomically, and restart.
#include "fluidbed/checkpoint_check.hpp"
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
  OutputSchedule &o = sim->output;

  PetscFunctionBeginUser;
  PetscOptionsBegin(sim->comm, "", "HDF5 output, checkpoints and restart", "Output");
  PetscCall(OptionsReal(PetscOptionsObject, "-output_interval",
                        "Simulated time between HDF5 snapshots (snapshot_NNNNN.h5 + particles.xmf for ParaView; 0: none)", "s",
                        NonNegative(), &o.interval, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-checkpoint_interval",
                        "Simulated time between checkpoints (0: none); the last step is always checkpointed when set", "s", NonNegative(),
                        &o.checkpoint_interval, NULL));
  PetscCall(OptionsString(PetscOptionsObject, "-checkpoint_file",
                          "Checkpoint path (default <output_dir>/checkpoint.h5); written to .tmp, then renamed", "a file path",
                          o.checkpoint_file, sizeof(o.checkpoint_file), NULL));
  PetscCall(OptionsString(PetscOptionsObject, "-restart",
                          "Continue from this checkpoint (any number of ranks); the scene's options must match it",
                          "a checkpoint file (checkpoint.h5)", o.restart, sizeof(o.restart), NULL));
  PetscOptionsEnd();
  if (!o.checkpoint_file[0])
    PetscCall(PetscSNPrintf(o.checkpoint_file, sizeof(o.checkpoint_file), "%s/checkpoint.h5", sim->run.output_dir));
  o.next            = 0.0; // the initial state is the first snapshot
  o.next_checkpoint = o.checkpoint_interval;
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationWriteSnapshot(Simulation *sim)
{
  OutputSchedule &o = sim->output;
  PetscViewer     viewer;
  char            name[64];
  PetscInt64      n;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(name, sizeof(name), "snapshot_%05d.h5", (int)o.series.size()));
  const std::string path = std::string(sim->run.output_dir) + "/" + name;
  n                      = 0;
  if (sim->swarm) PetscCall(ParticlesGlobalCount(sim->swarm, &n));
  PetscCall(PetscViewerHDF5Open(sim->comm, path.c_str(), FILE_MODE_WRITE, &viewer));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time", PETSC_REAL, &sim->time));
  if (sim->swarm) PetscCall(ParticlesWriteHDF5(sim->swarm, viewer, PETSC_FALSE));
  if (sim->fluid) PetscCall(FluidWriteHDF5(sim->fluid, viewer, PETSC_FALSE));
  PetscCall(PetscViewerDestroy(&viewer));
  o.series.push_back({sim->time, name, n});
  if (sim->swarm) PetscCall(XdmfWriteParticles(sim->comm, sim->run.output_dir, sim->domain.dim, o.series));
  if (sim->fluid) PetscCall(XdmfWriteFluid(sim->comm, sim->run.output_dir, sim->domain, sim->grids.fluid, o.series));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationWriteCheckpoint(Simulation *sim)
{
  OutputSchedule   &o    = sim->output;
  const std::string path = o.checkpoint_file;
  PetscViewer       viewer;
  PetscMPIInt       size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(sim->comm, &size));
  // Migration, contact-history sync and neighbour lists now, as a restart does when it loads the checkpoint: both
  // runs then continue from the same ownership of particles by ranks (the coupling's cell sums depend on it).
  if (sim->dem) PetscCall(DemRebuild(sim->dem));
  PetscCall(PetscViewerHDF5Open(sim->comm, (path + ".tmp").c_str(), FILE_MODE_WRITE, &viewer));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", kCheckpointMarker, PETSC_INT, &kCheckpointFormat)); // snapshots have none
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time", PETSC_REAL, &sim->time));
  PetscCall(WriteCount(viewer, "step", sim->step));
  if (sim->dem) PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "dt", PETSC_REAL, &sim->dem->par.dt));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "dim", PETSC_INT, &sim->domain.dim));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "ranks", PETSC_INT, &size));
  if (sim->dem) PetscCall(WriteCount(viewer, "particles_outlet", sim->dem->stats.outlet_removed));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "monitor_next", PETSC_REAL, &sim->monitor.next));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "snapshot_next", PETSC_REAL, &o.next));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "checkpoint_next", PETSC_REAL, &o.next_checkpoint));
  {
    // the snapshot series, so that particles.xmf continues after a restart
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(sim->comm, &rank));
    const PetscInt         ns = rank ? 0 : (PetscInt)o.series.size();
    std::vector<PetscReal> rows(2 * (std::size_t)ns);
    for (PetscInt k = 0; k < ns; ++k) {
      rows[2 * (std::size_t)k]     = o.series[(std::size_t)k].time;
      rows[2 * (std::size_t)k + 1] = (PetscReal)o.series[(std::size_t)k].particles;
    }
    PetscInt total = (PetscInt)o.series.size();
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "snapshots", PETSC_INT, &total));
    if (total) {
      Vec v;
      PetscCall(VecCreateMPIWithArray(sim->comm, 2, 2 * ns, PETSC_DECIDE, rows.data(), &v));
      PetscCall(PetscObjectSetName((PetscObject)v, "snapshot_series"));
      PetscCall(VecView(v, viewer));
      PetscCall(VecDestroy(&v));
    }
  }
  if (sim->swarm) PetscCall(ParticlesWriteHDF5(sim->swarm, viewer, PETSC_TRUE));
  if (sim->fluid) PetscCall(FluidWriteHDF5(sim->fluid, viewer, PETSC_TRUE));
  if (sim->coupling) PetscCall(CouplingWriteHDF5(sim->coupling, viewer));
  PetscCall(BedAveragesWriteHDF5(sim->averages, viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscCall(CommitFile(sim->comm, path));
  PetscFunctionReturn(0);
}

PetscErrorCode SimulationReadCheckpoint(Simulation *sim)
{
  OutputSchedule &o = sim->output;
  PetscViewer     viewer;
  PetscInt        dim, total = 0;
  PetscReal       dt;

  PetscFunctionBeginUser;
  PetscCall(CheckpointValidate(sim->comm, o.restart)); // a wrong file gives one line, not HDF5's error stack
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
    for (PetscInt k = 0; k < total; ++k) {
      char name[64];
      PetscCall(PetscSNPrintf(name, sizeof(name), "snapshot_%05d.h5", (int)k));
      o.series.push_back({a[2 * k], name, (PetscInt64)a[2 * k + 1]});
    }
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
