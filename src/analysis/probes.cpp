#include "fluidbed/probes.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/kernels/bed_statistics.hpp"

#include <array>
#include <string>

namespace fluidbed {

namespace {

// The probes as an output: their monitor.csv columns, measured for every row.
class GasProbes final : public Output {
public:
  std::vector<PetscReal>                heights; // -probe_heights, m above the distributor
  std::vector<std::array<PetscReal, 3>> points;  // -probe_points

  const char *Name() const override { return "probes"; }
  // p_y<height in mm, '_' for the decimal point>mm_avg, then p_probe<n>
  void Columns(std::vector<MonitorColumn> *columns) const override;
  // heights first, then points (Pa)
  PetscErrorCode Values(const RunView &run, std::vector<PetscReal> *values) override;
};

PetscErrorCode SetFromOptions(MPI_Comm comm, const Domain &dom, GasProbes *pr)
{
  PetscReal h[64] = {0}, pts[3 * 64] = {0}; // -help prints the first entry as the default
  PetscInt  nh = 64, np = 3 * 64;
  PetscBool set_h, set_p;

  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "probe_", "Gas pressure probes (monitor.csv columns)", "Analysis");
  PetscCall(OptionsRealArray(PetscOptionsObject, "-heights", "Heights above the distributor of cross-section-averaged pressure", "m",
                             Closed(0.0, 100.0), h, &nh, PETSC_FALSE, &set_h));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-points", "Pressure probes x,y,z,x,y,z,... (z ignored in 2D)", "m", Closed(-100.0, 100.0),
                             pts, &np, PETSC_FALSE, &set_p));
  PetscOptionsEnd();
  if (set_h) {
    for (PetscInt k = 0; k < nh; ++k) {
      PetscCheck(h[k] >= dom.lo[1] && h[k] <= dom.hi[1], comm, PETSC_ERR_ARG_OUTOFRANGE,
                 "-probe_heights: %.6g m is outside the bed [%.6g, %.6g] m", (double)h[k], (double)dom.lo[1], (double)dom.hi[1]);
      pr->heights.push_back(h[k]);
    }
  }
  if (set_p) {
    PetscCheck(np % 3 == 0, comm, PETSC_ERR_USER_INPUT, "-probe_points takes x,y,z triples, got %d values", (int)np);
    for (PetscInt k = 0; k < np / 3; ++k) {
      for (int a = 0; a < dom.dim; ++a)
        PetscCheck(pts[3 * k + a] >= dom.lo[a] && pts[3 * k + a] <= dom.hi[a], comm, PETSC_ERR_ARG_OUTOFRANGE,
                   "-probe_points: probe %d lies outside the domain", (int)k);
      pr->points.push_back({pts[3 * k], pts[3 * k + 1], pts[3 * k + 2]});
    }
  }
  PetscFunctionReturn(0);
}

void GasProbes::Columns(std::vector<MonitorColumn> *columns) const
{
  char buf[64];
  for (PetscReal y : heights) {
    snprintf(buf, sizeof(buf), "p_y%.4gmm_avg", 1e3 * (double)y);
    for (char *c = buf; *c; ++c)
      if (*c == '.') *c = '_'; // CSV readers drop dots from column names
    columns->push_back({buf});
  }
  for (std::size_t k = 0; k < points.size(); ++k) columns->push_back({"p_probe" + std::to_string(k)});
}

// The gas pressure of the cells this rank owns, read only: its array, the owned box (a 2D grid as one layer of
// cells) and the communicator, for the profile and the point probes alike.
struct OwnedPressure {
  Vec                p = NULL;
  const PetscScalar *a = NULL;
  PetscInt           xs[3], xm[3];
  MPI_Comm           comm;
};

PetscErrorCode OwnedPressureGet(Fluid *fluid, int dim, OwnedPressure *P)
{
  DM da;

  PetscFunctionBeginUser;
  PetscCall(FluidGetCellDMs(fluid, &da, NULL));
  PetscCall(FluidGetPressure(fluid, &P->p));
  PetscCall(PetscObjectGetComm((PetscObject)da, &P->comm));
  PetscCall(DMDAGetCorners(da, &P->xs[0], &P->xs[1], &P->xs[2], &P->xm[0], &P->xm[1], &P->xm[2]));
  if (dim == 2) P->xs[2] = 0, P->xm[2] = 1;
  PetscCall(VecGetArrayRead(P->p, &P->a));
  PetscFunctionReturn(0);
}

PetscErrorCode OwnedPressureRestore(OwnedPressure *P)
{
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArrayRead(P->p, &P->a));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode GasPressureProfile(Fluid *fluid, const Domain &dom, const FluidGrid &grid, std::vector<PetscReal> *profile)
{
  OwnedPressure P;

  PetscFunctionBeginUser;
  PetscCall(OwnedPressureGet(fluid, (int)dom.dim, &P));
  std::vector<PetscReal> loc((std::size_t)grid.n[1], 0.0);
  for (PetscInt k = 0; k < P.xm[2]; ++k)
    for (PetscInt j = 0; j < P.xm[1]; ++j)
      for (PetscInt i = 0; i < P.xm[0]; ++i) loc[(std::size_t)(P.xs[1] + j)] += P.a[(k * P.xm[1] + j) * P.xm[0] + i];
  PetscCall(OwnedPressureRestore(&P));
  profile->assign((std::size_t)grid.n[1], 0.0);
  PetscCallMPI(MPI_Allreduce(loc.data(), profile->data(), (int)grid.n[1], MPIU_REAL, MPI_SUM, P.comm));
  const PetscReal per_layer = (PetscReal)(grid.n[0] * (dom.dim == 3 ? grid.n[2] : 1));
  for (auto &v : *profile) v /= per_layer;
  PetscFunctionReturn(0);
}

PetscErrorCode GasProbes::Values(const RunView &run, std::vector<PetscReal> *values)
{
  const Domain           &dom   = run.domain;
  const FluidGrid        &grid  = run.grids.fluid;
  Fluid                  *fluid = run.fluid;
  const int               dim   = (int)dom.dim;
  const kernels::CellGrid g     = GridsCellGrid(dom, grid.n);

  PetscFunctionBeginUser;
  // cross-section-averaged profile, interpolated between layer centres (the same heights on every rank)
  if (!heights.empty()) {
    std::vector<PetscReal> prof;
    PetscCall(GasPressureProfile(fluid, dom, grid, &prof));
    for (PetscReal y : heights) values->push_back(kernels::interpolate_profile(g, prof, y - dom.lo[1]));
  }
  if (points.empty()) PetscFunctionReturn(0);

  // point probes: the value of the cell holding the point, from its owner
  OwnedPressure P;
  PetscCall(OwnedPressureGet(fluid, dim, &P));
  const PetscInt        *xs = P.xs, *xm = P.xm;
  std::vector<PetscReal> pl(points.size(), 0.0), pg(points.size());
  for (std::size_t q = 0; q < points.size(); ++q) {
    PetscInt c[3] = {0, 0, 0};
    for (int d = 0; d < dim; ++d) c[d] = kernels::axis_cell(g, d, points[q][d]);
    if (c[0] >= xs[0] && c[0] < xs[0] + xm[0] && c[1] >= xs[1] && c[1] < xs[1] + xm[1] && c[2] >= xs[2] && c[2] < xs[2] + xm[2])
      pl[q] = P.a[((c[2] - xs[2]) * xm[1] + (c[1] - xs[1])) * xm[0] + (c[0] - xs[0])];
  }
  PetscCall(OwnedPressureRestore(&P));
  PetscCallMPI(MPI_Allreduce(pl.data(), pg.data(), (int)pl.size(), MPIU_REAL, MPI_SUM, P.comm));
  values->insert(values->end(), pg.begin(), pg.end());
  PetscFunctionReturn(0);
}

PetscErrorCode GasProbesCreate(const RunView &run, std::unique_ptr<Output> *out)
{
  std::unique_ptr<GasProbes> pr = std::make_unique<GasProbes>();

  PetscFunctionBeginUser;
  out->reset();
  if (!run.fluid) PetscFunctionReturn(0);
  PetscCall(SetFromOptions(run.comm, run.domain, pr.get()));
  if (!pr->heights.empty() || !pr->points.empty()) *out = std::move(pr);
  PetscFunctionReturn(0);
}

} // namespace fluidbed
