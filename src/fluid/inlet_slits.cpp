// The slits inlet (-inlet_type slits): a porous distributor over the bottom and slits through the depth, each with
// its own superficial velocity: the seed's jetted and spouted beds (chapters 3-5).
#include "fluidbed/inlets.hpp"
#include "fluidbed/options.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace fluidbed {

namespace {

// The bottom slits: centre, width, velocity triplets, checked against the fluid cells along x.
PetscErrorCode ReadJets(const InletFace &f, const PetscReal *vals, PetscInt n, std::vector<kernels::JetCells> *out)
{
  const PetscReal h = f.h[0], x0 = f.dom->lo[0];

  PetscFunctionBeginUser;
  PetscCheck(n % 3 == 0, f.comm, PETSC_ERR_USER_INPUT,
             "-inlet_jets takes centre,width,velocity for each slit (a multiple of 3 values), got %d values", (int)n);
  for (PetscInt s = 0; s < n / 3; ++s) {
    const PetscReal c = vals[3 * s], w = vals[3 * s + 1], v = vals[3 * s + 2];
    PetscCheck(w > 0, f.comm, PETSC_ERR_ARG_OUTOFRANGE, "-inlet_jets: jet %d has width %.6g m: allowed (0, %.6g] m", (int)s + 1, (double)w,
               (double)f.dom->len[0]);
    const kernels::JetSnap snap = kernels::snap_jet(c, w, x0, h, f.n[0]);
    PetscCheck(snap.inside, f.comm, PETSC_ERR_ARG_OUTOFRANGE,
               "-inlet_jets: jet %d (centre %.6g mm, width %.6g mm) extends beyond the bottom, x = %.6g..%.6g mm", (int)s + 1, 1e3 * c,
               1e3 * w, 1e3 * x0, 1e3 * f.dom->hi[0]);
    if (!snap.ok) {
      if (snap.centre_ok)
        SETERRQ(f.comm, PETSC_ERR_USER_INPUT,
                "-inlet_jets: jet %d (centre %.4f mm, width %.4f mm): its edges x = %.4f and %.4f mm do not fall on cell faces (fluid "
                "cells of %.6f mm along x); "
                "the nearest valid width is %.8g m (%ld cells)",
                (int)s + 1, 1e3 * c, 1e3 * w, 1e3 * (c - 0.5 * w), 1e3 * (c + 0.5 * w), 1e3 * h, (double)snap.nearest_width,
                snap.nearest_cells);
      SETERRQ(f.comm, PETSC_ERR_USER_INPUT,
              "-inlet_jets: jet %d (centre %.4f mm, width %.4f mm): its edges x = %.4f and %.4f mm do not fall on cell faces (fluid cells "
              "of %.6f mm along x), "
              "and no width does at this centre; the nearest valid centre is %.8g m, with widths that are whole numbers of cells (nearest "
              "%.8g m)",
              (int)s + 1, 1e3 * c, 1e3 * w, 1e3 * (c - 0.5 * w), 1e3 * (c + 0.5 * w), 1e3 * h, (double)snap.nearest_centre,
              (double)(std::max(1.0, std::round(w / h)) * h));
    }
    for (std::size_t q = 0; q < out->size(); ++q)
      PetscCheck(snap.last <= (*out)[q].first || snap.first >= (*out)[q].last, f.comm, PETSC_ERR_USER_INPUT,
                 "-inlet_jets: jets %d and %d overlap", (int)q + 1, (int)s + 1);
    out->push_back({snap.first, snap.last, v});
  }
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode InletCreateSlits(const InletFace &face, Inlet *inlet)
{
  PetscReal distributor = 0, jets[96] = {0};
  PetscInt  njets    = 96;
  PetscBool set_jets = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(face.comm, "inlet_", "Gas inlet slits (-inlet_type slits): a porous distributor and slits (jets) through the depth",
                    "Fluid");
  PetscCall(OptionsReal(PetscOptionsObject, "-velocity",
                        "Superficial gas velocity through the distributor (the bottom outside the slits; 0: a wall)", "m/s",
                        Closed(-1e3, 1e3), &distributor, NULL));
  PetscCall(OptionsRealArray(PetscOptionsObject, "-jets",
                             "Slits through the depth: centre x [m], width [m], superficial velocity [m/s] of each, comma-separated",
                             "m,m,m/s", Closed(-1e4, 1e4), jets, &njets, PETSC_FALSE, &set_jets));
  PetscOptionsEnd();
  if (set_jets) PetscCall(ReadJets(face, jets, njets, &inlet->openings));
  // the same profile in every row along z: slits run through the depth
  const std::vector<double> row = kernels::inlet_profile(face.n[0], distributor, inlet->openings);
  for (PetscInt k = 0; k < face.n[2]; ++k) inlet->velocity.insert(inlet->velocity.end(), row.begin(), row.end());
  char summary[128];
  PetscCall(PetscSNPrintf(summary, sizeof(summary), "distributor %.6g m/s, %d slit(s)", (double)distributor, (int)inlet->openings.size()));
  inlet->summary = summary;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
