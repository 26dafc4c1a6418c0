// Contact models by name (include/fluidbed/contact_model.hpp), the contact parameters and the DEM time step (seed
// eq. 3.2-3.3, Table 3.3 / 5.3 defaults), and what every model shares: its history slots in the swarm and their
// sync with the neighbour lists.
#include "dem_impl.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/registry.hpp"

#include "history_slots.hpp"

#include <string>

namespace fluidbed {

namespace {
PetscErrorCode RegisterBuiltins()
{
  PetscFunctionBeginUser;
  PetscCall(ContactModelRegister("lsd", ContactModelCreateLsd));
  PetscFunctionReturn(0);
}
NamedRegistry contact_models("-dem_contact_model", RegisterBuiltins);
} // namespace

PetscErrorCode ContactModelRegister(const char *name, ContactModelCreate create)
{
  PetscFunctionBeginUser;
  PetscCall(contact_models.Add(name, (void (*)(void))create));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactModelList(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  PetscCall(contact_models.List(list));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactModelGet(const char *name, ContactModel *model)
{
  void (*fn)(void);

  PetscFunctionBeginUser;
  PetscCall(contact_models.Find(name, &fn));
  *model = ContactModel{};
  PetscCall(((ContactModelCreate)fn)(model));
  PetscCheck(model->forces && model->mirror && model->elastic_energy && model->history_size > 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "contact model %s does not set its history size and all its functions", name);
  PetscFunctionReturn(0);
}

PetscErrorCode DemParamsSetFromOptions(MPI_Comm comm, const Domain &dom, const ParticleProps &props, DemParams *p)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "dem_", "DEM: linear spring-dashpot contacts (seed eq. 2.3-2.10)", "DEM");
  {
    PetscFunctionList models;
    PetscCall(ContactModelList(&models));
    PetscCall(PetscOptionsFList("-contact_model", "Contact model (lsd: linear spring-dashpot with a Coulomb slider, eq. 2.3-2.10)",
                                "ContactModelRegister", models, p->contact_model, p->contact_model, sizeof(p->contact_model), NULL));
  }
  PetscCall(OptionsReal(PetscOptionsObject, "-kn", "Normal spring stiffness k_n", "N/m", Positive(1e12), &p->kn, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-kt", "Tangential spring stiffness k_t (negative: equal to k_n, as in the seed)", "N/m",
                        Closed(-1.0, 1e12), &p->kt, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-e", "Coefficient of normal restitution e (sets the damping, eq. 3.3)", "",
                        RealRange{0.0, 1.0, true, false}, &p->e, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-mu", "Particle-particle friction coefficient (Coulomb slider, eq. 2.8)", "",
                        Closed(0.0, 10.0), &p->mu, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-dt_factor",
                        "Time step as a fraction of the contact duration t_cr (eq. 3.2); above 1 contacts are not resolved", "",
                        RealRange{0.0, 10.0, true, false}, &p->dt_factor, NULL));
  PetscCall(
    OptionsReal(PetscOptionsObject, "-skin",
                "Verlet-list skin; lists are rebuilt when a particle has moved half of it (with -dem_skin_adaptive: the largest skin)", "d",
                Closed(0.01, 2.0), &p->skin, NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-skin_adaptive",
                        "Adaptive skin: each particle's share of its pairs' skin is its speed at the rebuild times twice the last "
                        "interval between rebuilds, between half of -dem_skin_min and half of -dem_skin, and the lists are rebuilt "
                        "when a particle has moved its own share (off: every share is half of -dem_skin). Results do not depend on it, "
                        "but for the last bits of a gas-coupled bed's coupling sums on several ranks (the rebuilds decide which rank "
                        "sums a particle by the ranks' boundary)",
                        &p->skin_adaptive, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-skin_min",
                        "Adaptive skin (-dem_skin_adaptive): the skin of two slow particles, at most -dem_skin", "d", Closed(0.01, 2.0),
                        &p->skin_min, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-sort_interval",
                       "Neighbour-list rebuilds between sorts of the particles' storage by neighbour bin (0: automatic, when a particle "
                       "may have moved one bin since the last sort: 2 (d_max + skin) / skin rebuilds). Results do not depend on it",
                       0, 1 << 30, &p->sort_interval, NULL));
  PetscCall(
    OptionsInt(PetscOptionsObject, "-max_contacts", "Contact history slots per particle (walls included)", 4, 128, &p->max_contacts, NULL));
  PetscCall(
    OptionsBool(PetscOptionsObject, "-pseudo2d", "3D only: confine motion to the x-y plane (one-particle-deep beds)", &p->pseudo2d, NULL));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, "wall_", "DEM: particle-wall contacts (walls are particles of infinite diameter)", "DEM");
  PetscCall(
    OptionsReal(PetscOptionsObject, "-kn", "Wall normal stiffness (negative: -dem_kn)", "N/m", Closed(-1.0, 1e12), &p->wall_kn, NULL));
  PetscCall(
    OptionsReal(PetscOptionsObject, "-kt", "Wall tangential stiffness (negative: -dem_kt)", "N/m", Closed(-1.0, 1e12), &p->wall_kt, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-e", "Wall restitution (negative: -dem_e)", "", Closed(-1.0, 1.0), &p->wall_e, NULL));
  PetscCall(
    OptionsReal(PetscOptionsObject, "-mu", "Wall friction coefficient (negative: -dem_mu)", "", Closed(-1.0, 10.0), &p->wall_mu, NULL));
  PetscOptionsEnd();

  PetscCheck(!p->skin_adaptive || p->skin_min <= p->skin, comm, PETSC_ERR_USER_INPUT,
             "-dem_skin_min %g must not exceed -dem_skin %g: the adaptive skin lies between them", (double)p->skin_min, (double)p->skin);
  if (p->kt < 0) p->kt = p->kn;
  if (p->wall_kn < 0) p->wall_kn = p->kn;
  if (p->wall_kt < 0) p->wall_kt = p->kt;
  if (p->wall_e < 0) p->wall_e = p->e;
  if (p->wall_mu < 0) p->wall_mu = p->mu;
  PetscCheck(p->wall_kn > 0 && p->wall_e > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "-wall_kn and -wall_e must be positive (got %.6g, %.6g)",
             (double)p->wall_kn, (double)p->wall_e);
  PetscCheck(!(p->pseudo2d && dom.dim == 2), comm, PETSC_ERR_USER_INPUT,
             "-dem_pseudo2d is for 3D domains; -domain_dim 2 is planar already");

  p->pp             = kernels::lsd_model(p->kn, p->kt, p->e, p->mu);
  p->pw             = kernels::lsd_model(p->wall_kn, p->wall_kt, p->wall_e, p->wall_mu);
  const PetscReal m = props.Mass(props.d_min); // the lightest particles have the shortest contacts
  p->t_cr           = kernels::critical_time(p->kn, p->e, 0.5 * m);
  p->t_cr_wall      = kernels::critical_time(p->wall_kn, p->wall_e, m);
  p->dt             = p->dt_factor * PetscMin(p->t_cr, p->t_cr_wall);
  PetscFunctionReturn(0);
}

PetscErrorCode HistorySlotsFull(const ParticleArrays &p, PetscInt i, PetscInt64 key)
{
  PetscFunctionBeginUser;
  {
    std::string keys;
    for (PetscInt s = 0; s < p.K; ++s) keys += " " + std::to_string((long long)p.ckey[p.K * i + s]);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
            "particle %lld has more than %d simultaneous contacts (partners:%s; new %lld): raise -dem_max_contacts", (long long)p.id[i],
            (int)p.K, keys.c_str(), (long long)key);
  }
}

PetscErrorCode DemContactForces(Dem *dem)
{
  PetscFunctionBeginUser;
  PetscCall(dem->contact.forces(dem));
  if (dem->external) PetscCall(dem->external(dem->external_ctx, dem->swarm, dem->bodies.data()));
  PetscFunctionReturn(0);
}

PetscErrorCode DemSyncPairHistory(Dem *dem)
{
  NeighbourList &nl     = dem->nl;
  const PetscInt nlocal = (PetscInt)nl.start.size() - 1;
  ParticleArrays p;

  PetscFunctionBeginUser;
  if (nlocal <= 0) PetscFunctionReturn(0);
  PetscCall(ParticleArraysGet(dem->swarm, &p));
  for (PetscInt i = 0; i < nlocal; ++i) {
    const PetscInt64 id = dem->body_id[(std::size_t)i];
    for (PetscInt k = nl.wall_start[(std::size_t)i]; k < nl.wall_start[(std::size_t)i + 1]; ++k) {
      const WallContact &wc = nl.walls[(std::size_t)k];
      if (wc.slot >= 0) HistoryCopy(p.hs, nl.WallHistory(k), SlotHistory(p, i, wc.slot));
    }
    for (PetscInt q = nl.pair_start[(std::size_t)i]; q < nl.pair_start[(std::size_t)i + 1]; ++q) {
      ContactPair   &pr = nl.pairs[(std::size_t)q];
      const PetscInt j  = pr.partner;
      if (pr.slot >= 0) HistoryCopy(p.hs, nl.PairHistory(q), SlotHistory(p, i, pr.slot));
      if (j >= nlocal) continue; // a ghost partner: its owner keeps its own side
      if (pr.slot >= 0) {
        if (pr.partner_slot < 0) PetscCall(HistorySlotTake(p, j, id, &pr.partner_slot));
        dem->contact.mirror(nl.PairHistory(q), SlotHistory(p, j, pr.partner_slot));
      } else if (pr.partner_slot >= 0) {
        HistorySlotFree(p, j, pr.partner_slot);
        pr.partner_slot = -1;
      }
    }
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  PetscFunctionReturn(0);
}

PetscErrorCode DemParamsView(const DemParams &p, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(
    viewer, "DEM: contact model %s, k_n %.6g N/m, k_t %.6g N/m, e %.6g, mu %.6g; walls k_n %.6g N/m, e %.6g, mu %.6g%s\n", p.contact_model,
    (double)p.kn, (double)p.kt, (double)p.e, (double)p.mu, (double)p.wall_kn, (double)p.wall_e, (double)p.wall_mu,
    p.pseudo2d ? "; pseudo-2D motion" : ""));
  PetscCall(PetscViewerASCIIPrintf(viewer, "DEM: t_cr %.4e s (particle pair), %.4e s (wall); dt = %.6g t_cr = %.4e s\n", (double)p.t_cr,
                                   (double)p.t_cr_wall, (double)p.dt_factor, (double)p.dt));
  if (p.dt_factor > 1.0)
    PetscCall(PetscViewerASCIIPrintf(
      viewer, "WARNING: -dem_dt_factor %.6g > 1: the time step exceeds the contact duration; contacts are not resolved\n",
      (double)p.dt_factor));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
