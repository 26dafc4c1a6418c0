#include "fluidbed/hdf5io.hpp"
#include "fluidbed/fluid.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace fluidbed {

namespace {

// A dataset of n rows of bs reals from this rank's block of a field array.
PetscErrorCode WriteRows(PetscViewer viewer, MPI_Comm comm, const char *name, PetscInt bs, PetscInt n, const PetscReal *data)
{
  Vec v;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPIWithArray(comm, bs, n * bs, PETSC_DECIDE, data, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(VecView(v, viewer));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

// Integer fields go to HDF5 as doubles (exact below 2^53).
PetscErrorCode WriteRowsInt64(PetscViewer viewer, MPI_Comm comm, const char *name, PetscInt bs, PetscInt n, const PetscInt64 *data)
{
  std::vector<PetscReal> tmp((std::size_t)(n * bs));

  PetscFunctionBeginUser;
  for (std::size_t k = 0; k < tmp.size(); ++k) tmp[k] = (PetscReal)data[k];
  PetscCall(WriteRows(viewer, comm, name, bs, n, tmp.data()));
  PetscFunctionReturn(0);
}

// Loads a dataset of rows of bs reals in PETSc's default row distribution.
PetscErrorCode ReadRows(PetscViewer viewer, MPI_Comm comm, const char *name, PetscInt bs, Vec *v)
{
  PetscFunctionBeginUser;
  PetscCall(VecCreate(comm, v));
  PetscCall(PetscObjectSetName((PetscObject)*v, name));
  PetscCall(VecSetBlockSize(*v, bs));
  PetscCall(VecLoad(*v, viewer));
  PetscFunctionReturn(0);
}

} // namespace

namespace {

// The datasets of /particles: snapshots write the first five, checkpoints all (ParticlesWriteHDF5, ParticlesHDF5Bytes).
struct ParticleDataset {
  const char       *name;
  PetscInt          bs;
  const PetscReal  *real;    // or
  const PetscInt64 *integer; // (written as doubles)
  bool              checkpoint_only;
};
std::vector<ParticleDataset> ParticleDatasets(const ParticleArrays &p)
{
  return {{"position", p.dim, p.x, nullptr, false},
          {"velocity", 3, p.v, nullptr, false},
          {"omega", 3, p.w, nullptr, false},
          {"diameter", 1, p.d, nullptr, false},
          {"id", 1, nullptr, p.id, false},
          {"force", 3, p.f, nullptr, true},
          {"torque", 3, p.t, nullptr, true},
          {"contact_key", p.K, nullptr, p.ckey, true},
          {"contact_hist", p.hs * p.K, p.chist, nullptr, true},
          {"drag_coef", 1, p.dcoef, nullptr, true},
          {"drag_ref", 3, p.dref, nullptr, true},
          {"drag_cell", 1, nullptr, p.dcell, true}};
}

} // namespace

PetscErrorCode ParticlesWriteHDF5(DM sw, PetscViewer viewer, PetscBool full)
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)sw);
  ParticleArrays p;

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(sw, &p));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  for (const ParticleDataset &s : ParticleDatasets(p)) {
    if (s.checkpoint_only && !full) continue;
    if (s.real) PetscCall(WriteRows(viewer, comm, s.name, s.bs, p.n, s.real));
    else PetscCall(WriteRowsInt64(viewer, comm, s.name, s.bs, p.n, s.integer));
  }
  if (full) {
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/particles", "max_contacts", PETSC_INT, &p.K));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/particles", "contact_history_size", PETSC_INT, &p.hs));
  }
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(ParticleArraysRestore(sw, &p));
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesWriteFlagHDF5(DM sw, PetscViewer viewer, const char *name, const std::vector<PetscInt64> &ids)
{
  MPI_Comm               comm = PetscObjectComm((PetscObject)sw);
  ParticleArrays         p;
  std::vector<PetscReal> flag;

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(sw, &p));
  flag.assign((std::size_t)p.n, 0.0);
  for (PetscInt i = 0; i < p.n; ++i)
    if (std::find(ids.begin(), ids.end(), p.id[i]) != ids.end()) flag[(std::size_t)i] = 1.0;
  PetscCall(ParticleArraysRestore(sw, &p));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  PetscCall(WriteRows(viewer, comm, name, 1, (PetscInt)flag.size(), flag.data()));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesHDF5Bytes(DM sw, PetscBool full, PetscInt64 *bytes)
{
  ParticleArrays p;
  PetscInt64     n, width = 0;

  PetscFunctionBeginUser;
  PetscCall(ParticlesGlobalCount(sw, &n));
  PetscCall(ParticleArraysGet(sw, &p));
  for (const ParticleDataset &s : ParticleDatasets(p))
    if (full || !s.checkpoint_only) width += s.bs;
  PetscCall(ParticleArraysRestore(sw, &p));
  *bytes = n * width * (PetscInt64)sizeof(PetscReal);
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesReadHDF5(DM sw, PetscViewer viewer, const Domain &dom, const ParticleGrid &pg)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)sw);
  const int   dim  = (int)dom.dim;
  PetscInt    Kf   = 0, K, hs, hbs, hsf;
  PetscBool   has_hs;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/particles", "max_contacts", PETSC_INT, NULL, &Kf));
  PetscCall(DMSwarmGetField(sw, field::contact_key, &K, NULL, NULL));
  PetscCall(DMSwarmRestoreField(sw, field::contact_key, &K, NULL, NULL));
  PetscCall(DMSwarmGetField(sw, field::contact_hist, &hbs, NULL, NULL));
  PetscCall(DMSwarmRestoreField(sw, field::contact_hist, &hbs, NULL, NULL));
  hs = hsf = hbs / K;
  // checkpoints from before the contact-model seam do not say: they hold the linear spring-dashpot's histories,
  // the only model then
  PetscCall(PetscViewerHDF5HasAttribute(viewer, "/particles", "contact_history_size", &has_hs));
  if (has_hs) PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/particles", "contact_history_size", PETSC_INT, NULL, &hsf));
  PetscCheck(hsf == hs, comm, PETSC_ERR_USER_INPUT,
             "-restart: the checkpoint's contacts keep %d history reals each, this run's contact model (-dem_contact_model) %d: "
             "restart with the model that wrote it",
             (int)hsf, (int)hs);

  // Each rank reads a block of rows of every dataset.
  struct Dataset {
    const char *name;
    PetscInt    bs;
    Vec         v;
  } sets[] = {{"position", dim, NULL}, {"velocity", 3, NULL},     {"omega", 3, NULL},
              {"force", 3, NULL},      {"torque", 3, NULL},       {"diameter", 1, NULL},
              {"id", 1, NULL},         {"contact_key", Kf, NULL}, {"contact_hist", hs * Kf, NULL},
              {"drag_coef", 1, NULL},  {"drag_ref", 3, NULL},     {"drag_cell", 1, NULL}};
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  for (auto &s : sets) PetscCall(ReadRows(viewer, comm, s.name, s.bs, &s.v));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscInt nrows, width = 0;
  PetscCall(VecGetLocalSize(sets[0].v, &nrows));
  nrows /= dim;
  for (auto &s : sets) width += s.bs;

  // Pack the rows, send each to the owner of its particle cell through a BASIC swarm, unpack into the PIC swarm.
  DM rows;
  PetscCall(DMCreate(comm, &rows));
  PetscCall(DMSetType(rows, DMSWARM));
  PetscCall(DMSwarmSetType(rows, DMSWARM_BASIC));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rows, "row", width, PETSC_REAL));
  PetscCall(DMSwarmFinalizeFieldRegister(rows));
  PetscCall(DMSwarmSetLocalSizes(rows, nrows, 16));
  {
    PetscReal *buf;
    PetscInt  *dest;
    PetscCall(DMSwarmGetField(rows, "row", NULL, NULL, (void **)&buf));
    PetscCall(DMSwarmGetField(rows, DMSwarmField_rank, NULL, NULL, (void **)&dest));
    PetscInt off = 0;
    for (auto &s : sets) {
      const PetscScalar *a;
      PetscCall(VecGetArrayRead(s.v, &a));
      for (PetscInt r = 0; r < nrows; ++r)
        for (PetscInt c = 0; c < s.bs; ++c) buf[width * r + off + c] = a[s.bs * r + c];
      PetscCall(VecRestoreArrayRead(s.v, &a));
      off += s.bs;
    }
    for (PetscInt r = 0; r < nrows; ++r) {
      PetscInt q[3] = {0, 0, 0};
      for (int a = 0; a < dim; ++a) {
        PetscInt cell = (PetscInt)PetscFloorReal((buf[width * r + a] - dom.lo[a]) / pg.h[a]);
        cell          = PetscMin(PetscMax(cell, 0), pg.n[a] - 1);
        while (!(cell >= pg.start[a][q[a]] && cell < pg.start[a][q[a] + 1])) ++q[a];
      }
      dest[r] = pg.RankAt(q);
    }
    PetscCall(DMSwarmRestoreField(rows, DMSwarmField_rank, NULL, NULL, (void **)&dest));
    PetscCall(DMSwarmRestoreField(rows, "row", NULL, NULL, (void **)&buf));
  }
  for (auto &s : sets) PetscCall(VecDestroy(&s.v));
  PetscCall(DMSwarmMigrate(rows, PETSC_TRUE));

  PetscInt n;
  PetscCall(DMSwarmGetLocalSize(rows, &n));
  PetscCall(DMSwarmSetLocalSizes(sw, n, 1024));
  {
    PetscReal     *buf;
    ParticleArrays p;
    PetscCall(DMSwarmGetField(rows, "row", NULL, NULL, (void **)&buf));
    PetscCall(ParticleArraysGet(sw, &p));
    for (PetscInt i = 0; i < n; ++i) {
      const PetscReal *r = &buf[width * i];
      PetscInt         o = 0;
      for (int a = 0; a < dim; ++a) p.x[dim * i + a] = r[o + a];
      o += dim;
      for (int c = 0; c < 3; ++c) p.v[3 * i + c] = r[o + c];
      o += 3;
      for (int c = 0; c < 3; ++c) p.w[3 * i + c] = r[o + c];
      o += 3;
      for (int c = 0; c < 3; ++c) p.f[3 * i + c] = r[o + c];
      o += 3;
      for (int c = 0; c < 3; ++c) p.t[3 * i + c] = r[o + c];
      o += 3;
      p.d[i]  = r[o++];
      p.id[i] = (PetscInt64)r[o++];
      for (PetscInt s = 0; s < K; ++s) {
        p.ckey[K * i + s] = kFreeSlot;
        for (PetscInt c = 0; c < hs; ++c) p.chist[hs * (K * i + s) + c] = 0.0;
      }
      for (PetscInt s = 0; s < Kf; ++s) {
        const PetscInt64 key = (PetscInt64)r[o + s];
        if (key == kFreeSlot) continue;
        PetscCheck(s < K, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                   "-restart: particle %lld holds %d contacts in the checkpoint; raise -dem_max_contacts to at least %d",
                   (long long)p.id[i], (int)(s + 1), (int)Kf);
        p.ckey[K * i + s] = key;
        for (PetscInt c = 0; c < hs; ++c) p.chist[hs * (K * i + s) + c] = r[o + Kf + hs * s + c];
      }
      o += Kf + hs * Kf;
      p.dcoef[i] = r[o++];
      for (int c = 0; c < 3; ++c) p.dref[3 * i + c] = r[o + c];
      o += 3;
      p.dcell[i] = (PetscInt64)r[o];
    }
    PetscCall(ParticleArraysRestore(sw, &p));
    PetscCall(DMSwarmRestoreField(rows, "row", NULL, NULL, (void **)&buf));
  }
  PetscCall(DMDestroy(&rows));
  PetscFunctionReturn(0);
}

std::string XdmfDocument(const std::string &grids, const char *collection)
{
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
  if (collection) x << "  <Grid Name=\"" << collection << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  x << grids;
  if (collection) x << "  </Grid>\n";
  x << " </Domain>\n</Xdmf>\n";
  return x.str();
}

PetscErrorCode XdmfWriteFile(MPI_Comm comm, const std::string &path, const std::string &text)
{
  PetscFunctionBeginUser;
  PetscCall(OutputWriteText(comm, path, text));
  PetscFunctionReturn(0);
}

std::string XdmfCellGrid(const char *name, PetscInt dim, const PetscInt n[3], const PetscReal lo[3], const PetscReal h[3],
                         const std::string &file, const std::vector<XdmfCellField> &fields, const PetscReal *time, const std::string &nodes)
{
  std::ostringstream cells, points;
  // XDMF orders axes slowest first: (z,) y, x
  for (int a = (int)dim - 1; a >= 0; --a) {
    cells << n[a] << (a ? " " : "");
    points << n[a] + 1 << (a ? " " : "");
  }
  auto heavy = [&](const std::string &dataset, int comps) {
    std::ostringstream d;
    d << "<DataItem Dimensions=\"" << cells.str() << (comps > 1 ? " " + std::to_string(comps) : "")
      << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << file << ":" << dataset << "</DataItem>";
    return d.str();
  };
  std::ostringstream x;
  x << std::setprecision(15); // times and coordinates to double precision (the default 6 digits lose both)
  x << "   <Grid Name=\"" << name << "\" GridType=\"Uniform\">\n";
  if (time) x << "    <Time Value=\"" << *time << "\"/>\n";
  if (dim == 3) {
    x << "    <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"" << points.str() << "\"/>\n";
    x << "    <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
    x << "     <DataItem Dimensions=\"3\" Format=\"XML\">" << lo[2] << " " << lo[1] << " " << lo[0] << "</DataItem>\n";
    x << "     <DataItem Dimensions=\"3\" Format=\"XML\">" << h[2] << " " << h[1] << " " << h[0] << "</DataItem>\n    </Geometry>\n";
  } else {
    // A 2D grid with the coordinates of its nodes. ParaView 5.11 lays a 2DCoRectMesh in the y-z plane (it reads
    // the two axes as z, y), away from the particles in x-y. Each uniform alternative fails in one of its readers:
    // a 3DCoRectMesh one node thick loads no cell field in the XDMF reader (it selects nodes - 1 = 0 cells across),
    // and a 2DRectMesh (VXVY) is read by it in x-y but handed down the pipeline with the y-z extent. A 2DSMesh puts
    // the nodes where their x, y say, at z = 0, in the XDMF and Xdmf3 readers alike.
    x << "    <Topology TopologyType=\"2DSMesh\" Dimensions=\"" << points.str() << "\"/>\n";
    x << "    <Geometry GeometryType=\"XY\">\n     <DataItem Dimensions=\"" << (n[0] + 1) * (n[1] + 1)
      << " 2\" NumberType=\"Float\" Precision=\"8\" Format=\"" << (nodes.empty() ? "XML" : "HDF") << "\">";
    if (nodes.empty())
      for (PetscInt j = 0; j <= n[1]; ++j)
        for (PetscInt i = 0; i <= n[0]; ++i) x << (i || j ? " " : "") << lo[0] + i * h[0] << " " << lo[1] + j * h[1];
    else x << nodes;
    x << "</DataItem>\n    </Geometry>\n";
  }
  // 2D vectors as vectors of two components: both readers load them (the XDMF reader adds z = 0), whereas the Xdmf3
  // reader skips a HyperSlab that picks one component.
  for (const XdmfCellField &f : fields)
    x << "    <Attribute Name=\"" << f.name << "\" AttributeType=\"" << (f.components == 1 ? "Scalar" : "Vector") << "\" Center=\"Cell\">"
      << heavy(f.dataset, f.components) << "</Attribute>\n";
  x << "   </Grid>\n";
  return x.str();
}

std::string XdmfParticleGrid(const SnapshotRecord &s, PetscInt dim, const std::vector<std::string> &extra_scalars)
{
  std::ostringstream x;
  x << std::setprecision(15); // the times as fluid.xmf gives them, so that ParaView pairs the two series' steps
  auto item = [&](const char *name, int comps) {
    std::ostringstream d;
    d << "<DataItem Dimensions=\"" << s.particles;
    if (comps > 1) d << " " << comps;
    d << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << s.file << ":/particles/" << name << "</DataItem>";
    return d.str();
  };
  x << "   <Grid Name=\"particles\" GridType=\"Uniform\">\n    <Time Value=\"" << s.time << "\"/>\n";
  x << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << s.particles << "\" NodesPerElement=\"1\"/>\n";
  x << "    <Geometry GeometryType=\"" << (dim == 3 ? "XYZ" : "XY") << "\">" << item("position", (int)dim) << "</Geometry>\n";
  const char *vec[] = {"velocity", "omega"};
  for (const char *v : vec)
    x << "    <Attribute Name=\"" << v << "\" AttributeType=\"Vector\" Center=\"Node\">" << item(v, 3) << "</Attribute>\n";
  std::vector<std::string> scal = {"diameter", "id"};
  scal.insert(scal.end(), extra_scalars.begin(), extra_scalars.end());
  for (const std::string &v : scal)
    x << "    <Attribute Name=\"" << v << "\" AttributeType=\"Scalar\" Center=\"Node\">" << item(v.c_str(), 1) << "</Attribute>\n";
  x << "   </Grid>\n";
  return x.str();
}

PetscErrorCode XdmfWriteParticles(MPI_Comm comm, const std::string &dir, PetscInt dim, const std::vector<SnapshotRecord> &series)
{
  PetscFunctionBeginUser;
  std::string grids; // every rank holds the series; rank 0 writes
  for (const SnapshotRecord &s : series) grids += XdmfParticleGrid(s, dim, {});
  PetscCall(XdmfWriteFile(comm, dir + "/" + run_files::particles_xdmf, XdmfDocument(grids, "particles")));
  PetscFunctionReturn(0);
}

std::vector<XdmfCellField> XdmfFluidFields(PetscInt dim)
{
  return {{"pressure", "/fluid/pressure", 1}, {"void_fraction", "/fluid/void_fraction", 1}, {"velocity", "/fluid/velocity", (int)dim}};
}

PetscErrorCode XdmfWriteFluidNodes(MPI_Comm comm, const std::string &dir, const Domain &dom, const FluidGrid &grid)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  if (dom.dim != 2) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::vector<PetscScalar> xy;
  if (!rank)
    for (PetscInt j = 0; j <= grid.n[1]; ++j)
      for (PetscInt i = 0; i <= grid.n[0]; ++i) xy.insert(xy.end(), {dom.lo[0] + i * grid.h[0], dom.lo[1] + j * grid.h[1]});
  const PetscInt64 bytes = (PetscInt64)(grid.n[0] + 1) * (grid.n[1] + 1) * 2 * (PetscInt64)sizeof(PetscScalar);
  PetscCall(WriteHDF5File(comm, dir + "/" + kFluidNodesFile, bytes, [&](PetscViewer viewer) {
    Vec v;
    PetscFunctionBeginUser;
    PetscCall(VecCreateMPIWithArray(comm, 2, (PetscInt)xy.size(), PETSC_DECIDE, xy.data(), &v));
    PetscCall(PetscObjectSetName((PetscObject)v, "nodes"));
    PetscCall(VecView(v, viewer));
    PetscCall(VecDestroy(&v));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/nodes", "units", PETSC_STRING, "m"));
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/nodes", "description", PETSC_STRING,
                                            "x, y of the gas grid's nodes, x fastest (the geometry of fluid.xmf)"));
    PetscFunctionReturn(0);
  }));
  PetscFunctionReturn(0);
}

PetscErrorCode XdmfWriteFluid(MPI_Comm comm, const std::string &dir, const Domain &dom, const FluidGrid &grid,
                              const std::vector<SnapshotRecord> &series)
{
  PetscFunctionBeginUser;
  const std::vector<XdmfCellField> fields = XdmfFluidFields(dom.dim);
  const std::string                nodes  = std::string(kFluidNodesFile) + ":/nodes";
  std::string                      grids;
  for (const SnapshotRecord &s : series) grids += XdmfCellGrid("gas", dom.dim, grid.n, dom.lo, grid.h, s.file, fields, &s.time, nodes);
  PetscCall(XdmfWriteFile(comm, dir + "/" + run_files::fluid_xdmf, XdmfDocument(grids, "gas")));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
