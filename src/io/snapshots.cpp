// The snapshot series: snapshot_NNNNN.h5 every -output_interval with particles.xmf and fluid.xmf for ParaView, an
// output of the run (include/fluidbed/outputs.hpp) whose series travels in checkpoints.
#include "fluidbed/fluid.hpp"
#include "fluidbed/hdf5io.hpp"

#include <string>
#include <vector>

namespace fluidbed {

PetscErrorCode StateHDF5Bytes(DM swarm, Fluid *fluid, PetscBool full, PetscInt64 *bytes)
{
  PetscInt64 part = 0, gas = 0;

  PetscFunctionBeginUser;
  if (swarm) PetscCall(ParticlesHDF5Bytes(swarm, full, &part));
  if (fluid) PetscCall(FluidHDF5Bytes(fluid, full, &gas));
  *bytes = part + gas;
  PetscFunctionReturn(0);
}

namespace {

class SnapshotSeries final : public Output {
public:
  explicit SnapshotSeries(PetscReal interval) : interval_(interval) {}
  const char *Name() const override { return "snapshots"; }

  PetscErrorCode Step(const RunView &run) override
  {
    const PetscReal eps = 0.5 * run.dt;

    PetscFunctionBeginUser;
    if (interval_ > 0 && run.time >= next_ - eps) {
      PetscCall(Write(run));
      while (next_ <= run.time + eps) next_ += interval_;
    }
    PetscFunctionReturn(0);
  }

  // The series, so that particles.xmf continues after a restart, and the time of the next snapshot.
  PetscErrorCode CheckpointWrite(const RunView &run, PetscViewer viewer) override
  {
    PetscMPIInt rank;

    PetscFunctionBeginUser;
    PetscCallMPI(MPI_Comm_rank(run.comm, &rank));
    const PetscInt         ns = rank ? 0 : (PetscInt)series_.size();
    std::vector<PetscReal> rows(2 * (std::size_t)ns);
    for (PetscInt k = 0; k < ns; ++k) {
      rows[2 * (std::size_t)k]     = series_[(std::size_t)k].time;
      rows[2 * (std::size_t)k + 1] = (PetscReal)series_[(std::size_t)k].particles;
    }
    const PetscInt total = (PetscInt)series_.size();
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "snapshot_next", PETSC_REAL, &next_));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "snapshots", PETSC_INT, &total));
    if (total) {
      Vec v;
      PetscCall(VecCreateMPIWithArray(run.comm, 2, 2 * ns, PETSC_DECIDE, rows.data(), &v));
      PetscCall(PetscObjectSetName((PetscObject)v, "snapshot_series"));
      PetscCall(VecView(v, viewer));
      PetscCall(VecDestroy(&v));
    }
    PetscFunctionReturn(0);
  }

  PetscErrorCode CheckpointRead(const RunView &run, PetscViewer viewer) override
  {
    PetscInt total = 0;

    PetscFunctionBeginUser;
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "snapshot_next", PETSC_REAL, NULL, &next_));
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "snapshots", PETSC_INT, NULL, &total));
    series_.clear();
    if (total) {
      Vec                v;
      const PetscScalar *a;
      PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2 * total, &v)); // every rank keeps the (short) series
      PetscCall(PetscObjectSetName((PetscObject)v, "snapshot_series"));
      PetscCall(VecSetBlockSize(v, 2));
      {
        PetscViewer self;
        PetscCall(PetscViewerHDF5Open(PETSC_COMM_SELF, run.restart, FILE_MODE_READ, &self));
        PetscCall(VecLoad(v, self));
        PetscCall(PetscViewerDestroy(&self));
      }
      PetscCall(VecGetArrayRead(v, &a));
      for (PetscInt k = 0; k < total; ++k) series_.push_back({a[2 * k], run_files::Snapshot(k), (PetscInt64)a[2 * k + 1]});
      PetscCall(VecRestoreArrayRead(v, &a));
      PetscCall(VecDestroy(&v));
    }
    PetscFunctionReturn(0);
  }

  // The snapshots numbered from the checkpoint's series on, and the XDMF files that listed them.
  PetscErrorCode RemoveStale(const RunView &run) override
  {
    const std::string dir = run.output_dir;
    PetscInt          removed;

    PetscFunctionBeginUser;
    PetscCall(RemoveSnapshotsAfter(run.comm, dir, (PetscInt)series_.size(), {run.restart}, &removed));
    if (removed && !series_.empty()) PetscCall(WriteXdmf(run));
    else if (removed)
      for (const char *name : {run_files::particles_xdmf, run_files::fluid_xdmf}) PetscCall(RemoveRunFile(run.comm, dir + "/" + name));
    PetscFunctionReturn(0);
  }

private:
  PetscErrorCode Write(const RunView &run)
  {
    const std::string name = run_files::Snapshot((PetscInt)series_.size()), path = std::string(run.output_dir) + "/" + name;
    PetscInt64        n = 0, bytes;

    PetscFunctionBeginUser;
    if (run.swarm) PetscCall(ParticlesGlobalCount(run.swarm, &n));
    PetscCall(StateHDF5Bytes(run.swarm, run.fluid, PETSC_FALSE, &bytes));
    // the XDMF series lists a snapshot only once its file is complete
    PetscCall(WriteHDF5File(run.comm, path, bytes, [&](PetscViewer viewer) {
      PetscFunctionBeginUser;
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "time", PETSC_REAL, &run.time));
      if (run.swarm) PetscCall(ParticlesWriteHDF5(run.swarm, viewer, PETSC_FALSE));
      if (run.fluid) PetscCall(FluidWriteHDF5(run.fluid, viewer, PETSC_FALSE));
      PetscFunctionReturn(0);
    }));
    series_.push_back({run.time, name, n});
    PetscCall(WriteXdmf(run));
    PetscFunctionReturn(0);
  }

  // Rewrites particles.xmf and fluid.xmf for the series.
  PetscErrorCode WriteXdmf(const RunView &run)
  {
    PetscFunctionBeginUser;
    if (run.swarm) PetscCall(XdmfWriteParticles(run.comm, run.output_dir, run.domain.dim, series_));
    if (run.fluid && !fluid_nodes_written_) { // the 2D gas grid's node coordinates, once per run
      PetscCall(XdmfWriteFluidNodes(run.comm, run.output_dir, run.domain, run.grids.fluid));
      fluid_nodes_written_ = true;
    }
    if (run.fluid) PetscCall(XdmfWriteFluid(run.comm, run.output_dir, run.domain, run.grids.fluid, series_));
    PetscFunctionReturn(0);
  }

  PetscReal                   interval_; // s (0: none)
  PetscReal                   next_ = 0; // the initial state is the first snapshot
  std::vector<SnapshotRecord> series_;
  bool                        fluid_nodes_written_ = false; // fluid_grid.h5 of this run (2D gas), before its first fluid.xmf
};

} // namespace

PetscErrorCode SnapshotSeriesCreate(PetscReal interval, std::unique_ptr<Output> *out)
{
  PetscFunctionBeginUser;
  *out = std::make_unique<SnapshotSeries>(interval);
  PetscFunctionReturn(0);
}

} // namespace fluidbed
