#!/usr/bin/env python3
"""Pressure-solver comparison on the systems of running beds (docs/ksp.md).

fluidbed writes the pressure system of selected gas steps with -fluid_p_dump_interval / -fluid_p_dump_steps
(src/fluid/pressure_dump.cpp): a PETSc binary file holding, in natural ordering, the matrix, the right-hand side, the
initial guess (the previous step's pressure as phi = dt p / rho), the solution, the void fraction and the drag
coefficient, with a JSON file describing the grid, the model and the run. This script loads them with petsc4py and
solves them with each solver of a catalogue (--list shows it):

- rebuild: the preconditioner is set up on each step's matrix; each step is solved from a zero and from the
  previous-step initial guess (one set-up, two solves);
- reuse: the preconditioner of the first dumped step of a directory is kept for the later ones
  (KSPSetReusePreconditioner, as -fluid_pc_reuse does in the run) while the matrix changes.

Iterations, set-up and solve times, the cost per simulated second of bed (the time per step times the run's gas
steps per simulated second), KSP's cheap extreme-eigenvalue estimates, and with --spectra SLEPc's extreme
eigenvalues of the preconditioned operator (and the whole spectrum of small systems, densely) and the smallest
eigenvalues of the matrix itself (the constant null space, near-null modes). With --ranks 1,2 the solves run under
mpiexec on each rank count and the results are merged. Writes <out>/ksp_compare.json, <out>/ksp_compare.md and,
unless --no-plots, convergence histories, iterations against grid size and spectra as PNG files.

The tolerance is the run's: relative 1e-8 on the unpreconditioned residual (CG and pipelined CG with the
preconditioner on the left; GMRES and BiCGStab on the right), the constant null space attached when the pressure is
pure Neumann.

Needs Debian's python3-petsc4py and python3-slepc4py (re-executes itself with /usr/bin/python3 when the Python it
runs under has no petsc4py).
"""
import argparse
import glob
import json
import os
import re
import subprocess
import sys
import time

from fluidbed_tools.run import launcher


def _need(modules):
    """Debian's packages live in Debian's Python: run under it when this Python lacks one of the modules."""
    for m in modules:
        try:
            __import__(m)
        except ImportError:
            debian = "/usr/bin/python3"
            if os.path.exists(debian) and os.path.realpath(sys.executable) != os.path.realpath(debian):
                os.execv(debian, [debian] + sys.argv)
            sys.exit("ksp_compare.py: Python module %s is missing (Debian: apt-get install python3-numpy python3-matplotlib python3-petsc4py "
                     "python3-slepc4py)" % m)


_need(["numpy"])
import numpy as np  # noqa: E402


def _need_petsc4py():
    _need(["petsc4py", "slepc4py"])


# ---------------------------------------------------------------------------------------------------------------------
# The catalogue. opts are PETSc options without the solver's prefix; mat "hyprestruct" loads the system into hypre's
# structured matrix (PFMG/SMG); mg "app" builds the hierarchy as fluidbed does for -fluid_p_pc_type mg, "flex" chooses
# the coarsening factors level by level; max_cells skips systems larger than that (Jacobi).
BOOMER = {"pc_hypre_type": "boomeramg"}
SOLVERS = {
    "cg_hypre": dict(ksp="cg", pc="hypre", opts=BOOMER,
                     desc="BoomerAMG, PETSc's defaults: Falgout coarsening, strong threshold 0.25, symmetric-SOR/Jacobi, classical interpolation (the run's default in 2D)"),
    "cg_hypre_st0.5": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_strong_threshold=0.5), desc="BoomerAMG, strong threshold 0.5"),
    "cg_hypre_st0.7": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_strong_threshold=0.7), desc="BoomerAMG, strong threshold 0.7"),
    "cg_hypre_hmis": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_coarsen_type="HMIS", pc_hypre_boomeramg_interp_type="ext+i",
                                                          pc_hypre_boomeramg_P_max=4), desc="BoomerAMG, HMIS coarsening, ext+i interpolation, P_max 4"),
    "cg_hypre_pmis": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_coarsen_type="PMIS", pc_hypre_boomeramg_interp_type="ext+i",
                                                          pc_hypre_boomeramg_P_max=4), desc="BoomerAMG, PMIS coarsening, ext+i interpolation, P_max 4"),
    "cg_hypre_agg": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_coarsen_type="HMIS", pc_hypre_boomeramg_interp_type="ext+i",
                                                         pc_hypre_boomeramg_P_max=4, pc_hypre_boomeramg_agg_nl=1),
                         desc="BoomerAMG, HMIS + one level of aggressive coarsening"),
    "cg_hypre_l1gs": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_relax_type_all="l1scaled-SOR/Jacobi"),
                          desc="BoomerAMG, l1-scaled hybrid Gauss-Seidel smoother"),
    "cg_hypre_cheby": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_relax_type_all="Chebyshev"), desc="BoomerAMG, Chebyshev smoother"),
    "cg_hypre_jac": dict(ksp="cg", pc="hypre", opts=dict(BOOMER, pc_hypre_boomeramg_relax_type_all="Jacobi"), desc="BoomerAMG, Jacobi smoother"),
    "cg_pfmg": dict(ksp="cg", pc="pfmg", mat="hyprestruct", opts={}, desc="hypre PFMG on the structured matrix (the run's default in 3D)"),
    "cg_pfmg_rb": dict(ksp="cg", pc="pfmg", mat="hyprestruct", opts=dict(pc_pfmg_relax_type="symmetric-Red/Black"), desc="PFMG, symmetric red/black Gauss-Seidel"),
    "cg_pfmg_ng": dict(ksp="cg", pc="pfmg", mat="hyprestruct", opts=dict(pc_pfmg_rap_type="non-Galerkin"), desc="PFMG, non-Galerkin coarse operators"),
    "cg_smg": dict(ksp="cg", pc="smg", mat="hyprestruct", opts={}, desc="hypre SMG (semicoarsening with line/plane smoothing) on the structured matrix"),
    "cg_gamg": dict(ksp="cg", pc="gamg", opts={}, desc="PETSc GAMG, defaults (smoothed aggregation)"),
    "cg_gamg_agg0": dict(ksp="cg", pc="gamg", opts=dict(pc_gamg_agg_nsmooths=0), desc="GAMG, plain (unsmoothed) aggregation"),
    "cg_gamg_th": dict(ksp="cg", pc="gamg", opts=dict(pc_gamg_threshold=0.02), desc="GAMG, graph threshold 0.02"),
    "cg_mg": dict(ksp="cg", pc="mg", mg="app", opts=dict(pc_mg_galerkin="both"),
                  desc="geometric MG as fluidbed's -fluid_p_pc_type mg: one factor per direction for every level, Q0 interpolation, Galerkin"),
    "cg_mg_flex": dict(ksp="cg", pc="mg", mg="flex", opts=dict(pc_mg_galerkin="both"),
                       desc="geometric MG, factors chosen level by level (2, 3, 5, 7), Q0 interpolation, Galerkin"),
    "cg_icc": dict(ksp="cg", pc="icc", opts={}, desc="ICC(0); block Jacobi with ICC(0) per rank on more than one rank"),
    "cg_jacobi": dict(ksp="cg", pc="jacobi", opts={}, max_cells=40000, desc="point Jacobi (reference; small systems only)"),
    "gmres_hypre": dict(ksp="gmres", pc="hypre", opts=BOOMER, desc="GMRES(30), BoomerAMG on the right"),
    "bcgs_hypre": dict(ksp="bcgs", pc="hypre", opts=BOOMER, desc="BiCGStab, BoomerAMG on the right"),
    "pipecg_hypre": dict(ksp="pipecg", pc="hypre", opts=BOOMER, desc="pipelined CG (one reduction per iteration), BoomerAMG"),
    "pipecg_pfmg": dict(ksp="pipecg", pc="pfmg", mat="hyprestruct", opts={}, desc="pipelined CG, PFMG"),
    "gmres_gamg": dict(ksp="gmres", pc="gamg", opts={}, desc="GMRES(30), GAMG on the right"),
    "bcgs_mg": dict(ksp="bcgs", pc="mg", mg="flex", opts=dict(pc_mg_galerkin="both"), desc="BiCGStab, geometric MG (flex) on the right"),
}
PRESETS = {
    "main": ["cg_hypre", "cg_pfmg", "cg_smg", "cg_gamg", "cg_mg", "cg_mg_flex", "cg_icc", "cg_jacobi", "gmres_hypre", "bcgs_hypre", "pipecg_hypre"],
    "knobs": ["cg_hypre", "cg_hypre_st0.5", "cg_hypre_st0.7", "cg_hypre_hmis", "cg_hypre_pmis", "cg_hypre_agg", "cg_hypre_l1gs",
              "cg_hypre_cheby", "cg_hypre_jac", "cg_pfmg", "cg_pfmg_rb", "cg_pfmg_ng", "cg_gamg", "cg_gamg_agg0", "cg_gamg_th"],
}
PRESETS["all"] = list(SOLVERS)


def solver_names(text):
    names = []
    for item in text.split(","):
        item = item.strip()
        if not item:
            continue
        for name in PRESETS.get(item, [item]):
            if name not in SOLVERS:
                sys.exit("ksp_compare.py: unknown solver %s (--list shows the catalogue)" % name)
            if name not in names:
                names.append(name)
    return names


def find_dumps(paths):
    """Dump files (*.bin with a JSON next to them) grouped by directory: {dir: [files sorted by step]}."""
    files = []
    for p in paths:
        if os.path.isdir(p):
            sub = os.path.join(p, "pressure_dump")
            files += glob.glob(os.path.join(sub if os.path.isdir(sub) else p, "pressure_step*.bin"))
        else:
            files += glob.glob(p)
    by_dir = {}
    for f in sorted(set(os.path.abspath(f) for f in files)):
        if os.path.exists(f[:-4] + ".json"):
            by_dir.setdefault(os.path.dirname(f), []).append(f)
    # runs of consecutive steps are the sequences a preconditioner can be kept over; a directory with several (the
    # start of a run and a later moment) gives one group each, keyed by directory and first step
    groups = {}
    for d, fs in by_dir.items():
        steps = [json.load(open(f[:-4] + ".json"))["step"] for f in fs]
        order = np.argsort(steps)
        run = []
        for i in order:
            if run and steps[i] != steps[run[-1]] + 1:
                groups[(d, steps[run[0]])] = [fs[j] for j in run]
                run = []
            run.append(i)
        if run:
            groups[(d, steps[run[0]])] = [fs[j] for j in run]
    return groups


def scene_name(directory):
    d = os.path.basename(directory)
    return os.path.basename(os.path.dirname(directory)) if d == "pressure_dump" else d


# ---------------------------------------------------------------------------------------------------------------------
# Worker: the PETSc part, run on each rank count.

class Worker:
    def __init__(self, args):
        import petsc4py
        petsc4py.init([sys.argv[0]] + (args.petsc_options or []))
        from petsc4py import PETSc
        self.PETSc = PETSc
        self.comm = PETSc.COMM_WORLD
        self.size = self.comm.getSize()
        self.rank = self.comm.getRank()
        self.args = args
        self.records, self.spectra, self.matrix_spectra, self.histories, self.systems, self.notes = [], [], [], [], [], []
        self.pc_done = set()  # (directory, preconditioner) pairs whose spectrum is done: GMRES and CG share one

    def log(self, text):
        if self.rank == 0 and not self.args.quiet:
            print(text, flush=True)

    # -- loading ------------------------------------------------------------------------------------------------------
    def make_da(self, meta, as3d):
        PETSc = self.PETSc
        dim = meta["dim"]
        n = list(meta["n"][:dim])
        per = list(meta["periodic"][:dim])
        if as3d and dim == 2:  # a 2D grid is a 3D grid one cell deep (hypre's structured matrix is 3D only here)
            n.append(1)
            per.append(False)
            dim = 3
        bt = [PETSc.DM.BoundaryType.PERIODIC if p else PETSc.DM.BoundaryType.NONE for p in per]
        da = PETSc.DMDA().create(dim=dim, sizes=n, dof=1, stencil_width=1, stencil_type=PETSc.DMDA.StencilType.STAR,
                                 boundary_type=bt, comm=self.comm)
        da.setMatType("aij")
        return da

    def load(self, path, da):
        PETSc = self.PETSc
        meta = json.load(open(path[:-4] + ".json"))
        viewer = PETSc.Viewer().createBinary(path, "r", comm=self.comm)
        A = da.createMatrix()
        A.load(viewer)  # natural ordering in the file, the DMDA's ordering here (MatLoad_MPI_DA)
        vecs = {}
        for key in ("b", "x0", "x", "eps", "beta"):
            v = da.createGlobalVec()
            v.load(viewer)
            vecs[key] = v
        viewer.destroy()
        ns = None
        if meta.get("constant_null_space"):
            ns = PETSc.NullSpace().create(constant=True, comm=self.comm)
            A.setNullSpace(ns)
            A.setTransposeNullSpace(ns)
        A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        return dict(path=path, meta=meta, A=A, ns=ns, **vecs)

    def assemble(self, sysm, da, model):
        """The projection operator of fluidbed (src/fluid/pressure.cpp) assembled again from the dumped void fraction and
        drag for the given model: face coefficient c_f = c0 eps_f / (eps_f + dt beta_f / rho) (c0 = 1 for model B, eps_f
        for model A; eps_f, beta_f the means of the two cells), entry c_f A_f / h_f per face between two cells, no flux
        through the walls. Coupled runs are model B only (the coupling implements the seed's model B): this gives
        model A's operator for the void fractions of coupled beds. Pressure outlets are not reproduced."""
        PETSc = self.PETSc
        meta = sysm["meta"]
        if meta.get("pressure_outlet"):
            raise RuntimeError("the reassembly does not reproduce pressure outlets")
        dim = da.getDim()
        h = meta["h"]
        area = [h[(a + 1) % 3] * h[(a + 2) % 3] for a in range(3)]
        ranges = da.getRanges()
        granges = da.getGhostRanges()
        gshape = [g[1] - g[0] for g in granges][::-1]  # (z,) y, x
        loc = {}
        for key in ("eps", "beta"):
            lv = da.createLocalVec()
            da.globalToLocal(sysm[key], lv)
            loc[key] = lv.getArray().reshape(gshape).copy()
            lv.destroy()
        # padded by one cell so that the neighbours of the owned block always exist (beyond a non-periodic boundary
        # the local array has no ghosts; those neighbours are masked below)
        E = np.pad(loc["eps"], 1, mode="edge")
        B = np.pad(loc["beta"], 1, mode="edge")
        gidx = np.pad(np.arange(loc["eps"].size).reshape(gshape), 1, constant_values=-1)
        # owned block in padded ghosted array coordinates, (z,) y, x order
        lo = [ranges[a][0] - granges[a][0] + 1 for a in range(dim)][::-1]
        hi = [ranges[a][1] - granges[a][0] + 1 for a in range(dim)][::-1]
        own = tuple(slice(l, u) for l, u in zip(lo, hi))
        rows = gidx[own].ravel()
        n_glob = list(da.getSizes())[::-1]
        start = [r[0] for r in ranges][::-1]
        cols, vals = [], []
        diag = np.zeros(rows.size)
        dt = meta["dt_of_assembly"]
        for a in range(dim):
            ax = dim - 1 - a  # array axis of direction a
            periodic = meta["periodic"][a]
            for side in (-1, 1):
                sh = [0] * dim
                sh[ax] = side
                nb = tuple(slice(l + d, u + d) for l, u, d in zip(lo, hi, sh))
                ef = 0.5 * (E[own] + E[nb])
                bf = 0.5 * (B[own] + B[nb])
                c0 = ef if model == "A" else np.ones_like(ef)
                c = np.where(bf > 0, c0 * ef / (ef + dt * bf / meta["rho"]), c0)
                w = (c * area[a] / h[a]).ravel()
                # neighbours outside a non-periodic domain: a wall (given normal velocity, no pressure flux)
                gpos = (np.arange(lo[ax], hi[ax]) - lo[ax] + start[ax] + side)
                inside = np.ones(E[own].shape, bool)
                if not periodic:
                    shape = [1] * dim
                    shape[ax] = -1
                    inside = np.broadcast_to(((gpos >= 0) & (gpos < n_glob[ax])).reshape(shape), E[own].shape)
                inside = inside.ravel()
                w = np.where(inside, w, 0.0)
                cols.append(np.where(inside, gidx[nb].ravel(), -1))
                vals.append(-w)
                diag += w
        cols.append(rows)
        vals.append(diag)
        A = da.createMatrix()
        A.setValuesLocalRCV(rows[:, None].astype(PETSc.IntType), np.stack(cols, axis=1).astype(PETSc.IntType), np.stack(vals, axis=1))
        A.assemble()
        return A

    def structured_copy(self, A, da):
        """The matrix A (a DMDA matrix of da) as hypre's structured matrix on the same DMDA: each owned row through
        MatSetValuesLocal with its exact stencil (the structured matrix takes no other columns)."""
        PETSc = self.PETSc
        da.setMatType("hyprestruct")
        H = da.createMatrix()
        da.setMatType("aij")
        ltog = np.asarray(da.getLGMap().getIndices())
        order = np.argsort(ltog)
        rstart, rend = A.getOwnershipRange()
        indptr, cols, vals = A.getValuesCSR()
        loc_cols = order[np.searchsorted(ltog[order], cols)]
        loc_rows = order[np.searchsorted(ltog[order], np.arange(rstart, rend))]
        counts = np.diff(indptr)
        for k in np.unique(counts):
            sel = np.nonzero(counts == k)[0]
            idx = indptr[sel][:, None] + np.arange(k)[None, :]
            H.setValuesLocalRCV(loc_rows[sel][:, None].astype(PETSc.IntType), loc_cols[idx].astype(PETSc.IntType), vals[idx])
        H.assemble()
        return H

    def contrast(self, sysm, da):
        """Face-coefficient statistics of the system from its void fraction and drag (rank 0, natural ordering)."""
        PETSc = self.PETSc
        meta = sysm["meta"]
        out = {}
        arrays = {}
        for key in ("eps", "beta"):
            nat = da.createNaturalVec()
            da.globalToNatural(sysm[key], nat)
            sc, z = PETSc.Scatter.toZero(nat)
            sc.scatter(nat, z, False, PETSc.ScatterMode.FORWARD)
            arrays[key] = z.getArray().copy() if self.rank == 0 else None
        if self.rank:
            return out
        dim = meta["dim"]
        shape = [meta["n"][2], meta["n"][1], meta["n"][0]][3 - dim:]
        e = arrays["eps"].reshape(shape)
        b = arrays["beta"].reshape(shape)
        dt = meta["dt_of_assembly"]
        coefs = []
        for a in range(dim):
            ax = dim - 1 - a
            ef = 0.5 * (np.take(e, range(1, e.shape[ax]), axis=ax) + np.take(e, range(0, e.shape[ax] - 1), axis=ax))
            bf = 0.5 * (np.take(b, range(1, b.shape[ax]), axis=ax) + np.take(b, range(0, b.shape[ax] - 1), axis=ax))
            c0 = ef if meta["model"].startswith("A") else np.ones_like(ef)
            c = np.where(bf > 0, c0 * ef / (ef + dt * bf / meta["rho"]), c0)
            coefs.append(c.ravel())
        c = np.concatenate(coefs) if coefs else np.ones(1)
        out.update(eps_min=float(e.min()), eps_max=float(e.max()), eps_std=float(e.std()), coef_min=float(c.min()), coef_max=float(c.max()),
                   coef_contrast=float(c.max() / c.min()), dense_cells=float(np.mean(e < 0.6)))
        return out

    # -- solvers -------------------------------------------------------------------------------------------------------
    def mg_hierarchy(self, da, mode):
        """Coarsening factors per level (finest first) for PCMG on the cells each rank owns; None when none coarsens.
        app: fluidbed's rule (pressure.cpp): the same factor q in 2..8 for every level in a direction, q^(L-1) dividing
        every rank's cells and leaving two, L chosen for the smallest coarse grid. flex: level by level, per direction
        the smallest of 2, 3, 5, 7 dividing every rank's cells (at least two coarse cells left in the direction), until
        the coarse grid has at most 64 cells or nothing divides."""
        dim = da.getDim()
        n = list(da.getSizes())
        own = [list(r) for r in da.getOwnershipRanges()]
        if mode == "app":
            best, best_L, best_fac = None, 1, None
            for L in range(2, 9):
                fac = []
                coarse = 1
                for a in range(dim):
                    f = 1
                    for q in range(2, 9):
                        pw = q ** (L - 1)
                        if n[a] % pw == 0 and n[a] // pw >= 2 and all(o % pw == 0 for o in own[a]):
                            f = q
                            break
                    fac.append(f)
                    coarse *= n[a] // f ** (L - 1)
                if np.prod(fac) == 1:
                    break
                if best is None or coarse < best:
                    best, best_L, best_fac = coarse, L, fac
            return [best_fac] * (best_L - 1) if best_fac else None
        levels = []
        while np.prod(n) > 64 and len(levels) < 12:
            fac = []
            for a in range(dim):
                f = 1
                for q in (2, 3, 5, 7):
                    if n[a] % q == 0 and n[a] // q >= 2 and all(o % q == 0 for o in own[a]):
                        f = q
                        break
                fac.append(f)
            if np.prod(fac) == 1:
                break
            levels.append(fac)
            n = [n[a] // fac[a] for a in range(dim)]
            own = [[o // fac[a] for o in own[a]] for a in range(dim)]
        return levels or None

    def q0_interpolation(self, m, fac):
        """Piecewise-constant interpolation from a grid coarser by fac for this rank's block of m fine cells (x
        fastest; the coarse parents of a rank's cells are on the same rank)."""
        PETSc = self.PETSc
        m = list(m) + [1] * (3 - len(m))
        fac = list(fac) + [1] * (3 - len(fac))
        mc = [m[a] // fac[a] for a in range(3)]
        nf, nc = int(np.prod(m)), int(np.prod(mc))
        P = PETSc.Mat().createAIJ(size=((nf, None), (nc, None)), nnz=(1, 1), comm=self.comm)
        P.setUp()
        rstart, _ = P.getOwnershipRange()
        cstart, _ = P.getOwnershipRangeColumn()
        k, j, i = np.meshgrid(np.arange(m[2]), np.arange(m[1]), np.arange(m[0]), indexing="ij")
        rows = rstart + ((k * m[1] + j) * m[0] + i).ravel()
        cols = cstart + (((k // fac[2]) * mc[1] + j // fac[1]) * mc[0] + i // fac[0]).ravel()
        P.setValuesRCV(rows[:, None].astype(PETSc.IntType), cols[:, None].astype(PETSc.IntType), np.ones((nf, 1)))
        P.assemble()
        return P

    def make_ksp(self, name, spec, A, da, prefix):
        PETSc = self.PETSc
        opts = PETSc.Options()
        ksp = PETSc.KSP().create(self.comm)
        ksp.setOptionsPrefix(prefix)
        ksp.setType(spec["ksp"])
        pc = ksp.getPC()
        pc_type = spec["pc"]
        if pc_type == "icc" and self.size > 1:
            pc_type = "bjacobi"
            opts[prefix + "sub_pc_type"] = "icc"
        pc.setType(pc_type)
        for key, value in spec["opts"].items():
            opts[prefix + key] = value
        info = {}
        if spec.get("mg"):
            levels = self.mg_hierarchy(da, spec["mg"])
            if levels is None:
                raise RuntimeError("the grid (per rank) does not coarsen by whole factors")
            pc.setMGLevels(len(levels) + 1)
            m = [r[1] - r[0] for r in da.getRanges()]
            for l, fac in enumerate(levels):
                P = self.q0_interpolation(m, fac)
                pc.setMGInterpolation(len(levels) - l, P)
                m = [m[a] // fac[a] for a in range(len(m))]
            info["mg_factors"] = levels
            info["mg_coarse_cells"] = int(np.prod([n // int(np.prod([f[a] for f in levels])) for a, n in enumerate(da.getSizes())]))
        ksp.setTolerances(rtol=self.args.rtol, atol=1e-50, max_it=self.args.max_it)
        ksp.setFromOptions()
        if spec["ksp"] in ("gmres", "fgmres", "bcgs"):
            ksp.setPCSide(PETSc.PC.Side.RIGHT)
        ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
        ksp.setOperators(A, A)
        if spec["ksp"] in ("cg", "gmres"):
            ksp.setComputeSingularValues(True)
        return ksp, info

    def clear_options(self, prefix):
        opts = self.PETSc.Options()
        for key in list(opts.getAll().keys()):
            if key.startswith(prefix):
                opts.delValue(key)

    def timed(self, fn):
        self.comm.barrier()
        t0 = time.perf_counter()
        fn()
        self.comm.barrier()
        return time.perf_counter() - t0

    def solve(self, ksp, sysm, guess, history=False):
        PETSc = self.PETSc
        x = sysm["b"].duplicate()
        if guess == "zero":
            x.set(0.0)
            ksp.setInitialGuessNonzero(False)
        else:
            sysm["x0"].copy(x)
            ksp.setInitialGuessNonzero(True)
        if history:
            ksp.setConvergenceHistory(length=self.args.max_it + 1, reset=True)
        t = self.timed(lambda: ksp.solve(sysm["b"], x))
        for _ in range(self.args.repeat - 1):  # the fastest of repeated solves: the least disturbed by other jobs
            x2 = x.duplicate()
            sysm["x0"].copy(x2) if guess != "zero" else x2.set(0.0)
            t = min(t, self.timed(lambda: ksp.solve(sysm["b"], x2)))
            x2.destroy()
        r = sysm["b"].duplicate()
        sysm["A"].mult(x, r)
        r.aypx(-1.0, sysm["b"])
        bnorm = sysm["b"].norm()
        out = dict(its=ksp.getIterationNumber(), reason=int(ksp.getConvergedReason()), solve_s=t, true_rel_residual=r.norm() / bnorm if bnorm else 0.0)
        if history:
            h = np.asarray(ksp.getConvergenceHistory())
            out["history"] = (h / bnorm).tolist() if bnorm else h.tolist()
        if guess == "zero":
            try:
                smax, smin = ksp.computeExtremeSingularValues()
                out.update(est_max=float(smax), est_min=float(smin), est_cond=float(smax / smin) if smin > 0 else None)
            except Exception:
                pass
        x.destroy()
        r.destroy()
        return out

    def run_sequence(self, directory, files, solvers, tag_time=False):
        PETSc = self.PETSc
        args = self.args
        meta0 = json.load(open(files[0][:-4] + ".json"))
        if meta0.get("cells", 0) > args.max_cells:
            self.log("skip %s: %d cells > --max-cells" % (directory, meta0["cells"]))
            return
        if args.steps:
            files = files[:args.steps]
        scene = scene_name(directory) + ("@%.3gs" % meta0["time"] if tag_time else "")
        directory = "%s#%d" % (directory, meta0["step"])  # one key per sequence
        layouts = {}
        need3d = any(SOLVERS[s].get("mat") == "hyprestruct" for s in solvers)

        def systems(as3d):
            as3d = as3d and meta0["dim"] == 2  # a 3D grid serves every solver as it is
            if as3d not in layouts:
                da = self.make_da(meta0, as3d)
                layouts[as3d] = (da, [self.load(f, da) for f in files])
            return layouts[as3d]

        da, syss = systems(False)
        if args.derive:
            scene += "+" + args.derive
            for s in syss:
                A = self.assemble(s, da, args.derive)
                if s["ns"]:
                    A.setNullSpace(s["ns"])
                A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
                s["A_dumped"], s["A"] = s["A"], A
                s["meta"] = dict(s["meta"], model=args.derive + " (reassembled)")
            for key in list(layouts):
                if key:  # the 3D view of a 2D grid gets the reassembled matrices too
                    for s3, s in zip(layouts[key][1], syss):
                        A3 = self.assemble(s3, layouts[key][0], args.derive)
                        if s3["ns"]:
                            A3.setNullSpace(s3["ns"])
                        s3["A"] = A3
                        s3["meta"] = s["meta"]
        if need3d and meta0["dim"] == 2 and not any(meta0["periodic"]):
            systems(True)
        for s in syss:
            rec = dict(scene=scene, dir=directory, file=os.path.basename(s["path"]), step=s["meta"]["step"], time=s["meta"]["time"],
                       dt=s["meta"]["dt"], dim=s["meta"]["dim"], n=s["meta"]["n"], cells=s["meta"]["cells"], model=s["meta"]["model"],
                       implicit_drag=s["meta"]["implicit_drag"], ranks=self.size, run_ksp_iterations=s["meta"].get("run_ksp_iterations"),
                       run_pc_type=s["meta"].get("run_pc_type"))
            rec.update(self.contrast(s, da))
            if "A_dumped" in s:
                D = s["A"].copy()
                D.axpy(-1.0, s["A_dumped"])
                rec["reassembly_vs_dumped"] = D.norm() / s["A_dumped"].norm()  # 0 for the model that ran, the model change otherwise
            # the dumped solution must solve the dumped system to the run's tolerance (a check of the dump itself)
            r = s["b"].duplicate()
            s["A"].mult(s["x"], r)
            r.aypx(-1.0, s["b"])
            rec["dumped_solution_rel_residual"] = r.norm() / s["b"].norm() if s["b"].norm() else 0.0
            self.systems.append(rec)
        self.log("%s: %d system(s), %d cells, %s, steps %s" % (scene, len(syss), meta0["cells"], "x".join(str(v) for v in meta0["n"][:meta0["dim"]]),
                                                             ",".join(str(s["meta"]["step"]) for s in syss)))
        for idx, name in enumerate(solvers):
            spec = SOLVERS[name]
            if meta0["cells"] > spec.get("max_cells", 1 << 60) and not args.no_size_limits:
                self.notes.append("%s: %s skipped: %d cells, above its limit of %d (--no-size-limits runs it)" % (scene, name, meta0["cells"], spec["max_cells"]))
                continue
            structured = spec.get("mat") == "hyprestruct"
            if structured and any(meta0["periodic"]):
                self.notes.append("%s: %s skipped: hypre's structured matrix in PETSc 3.18 takes no periodic directions" % (scene, name))
                continue
            lda, lsys = systems(structured)
            mats = [self.structured_copy(s["A"], lda) if structured else s["A"] for s in lsys]
            if structured:
                for s, H in zip(lsys, mats):
                    if s["ns"]:
                        H.setNullSpace(s["ns"])
            prefix = "s%d_" % idx
            try:
                for mode in (("rebuild", "reuse") if len(lsys) > 1 and not args.no_reuse else ("rebuild",)):
                    ksp, info = self.make_ksp(name, spec, mats[0], lda, prefix)
                    for k, (s, M) in enumerate(zip(lsys, mats)):
                        if mode == "reuse" and k == 0:
                            setup = self.timed(ksp.setUp)
                            ksp.getPC().setReusePreconditioner(True)
                            continue  # the first step's solve is the rebuild one
                        ksp.setOperators(M, M)
                        setup = self.timed(ksp.setUp)
                        for guess in args.guesses:
                            hist = mode == "rebuild" and k == 0 and guess == "zero"
                            out = self.solve(ksp, dict(s, A=M), guess, history=hist)
                            rec = dict(scene=scene, dir=directory, step=s["meta"]["step"], cells=s["meta"]["cells"], ranks=self.size, solver=name,
                                       ksp=spec["ksp"], pc=spec["pc"], mode=mode, guess=guess,
                                       dt=s["meta"]["dt"], steps_per_second=s["meta"]["gas_steps_per_simulated_second"], **info)
                            if "history" in out:
                                self.histories.append(dict(scene=scene, step=rec["step"], ranks=self.size, solver=name, residuals=out.pop("history")))
                            rec.update(out)
                            rec["setup_each_s"] = setup if mode == "rebuild" else None
                            self.records.append(rec)
                    pc_key = (spec["pc"], json.dumps(spec["opts"], sort_keys=True), spec.get("mg"))
                    if (args.spectra and mode == "rebuild" and self.size == 1 and meta0["cells"] <= args.spectra_max_cells
                            and (directory, pc_key) not in self.pc_done):
                        self.pc_done.add((directory, pc_key))
                        ksp.setOperators(mats[0], mats[0])
                        ksp.getPC().setReusePreconditioner(False)
                        ksp.setUp()
                        self.pc_spectrum(scene, lsys[0], mats[0], ksp, name)
                    ksp.destroy()
                its = [r["its"] for r in self.records if r["solver"] == name and r["dir"] == directory and r["mode"] == "rebuild" and r["guess"] == args.guesses[0]]
                self.log("  %-16s %s" % (name, " ".join(str(i) for i in its)))
            except Exception as exc:  # a solver that cannot run on this system is reported, not fatal
                self.notes.append("%s: %s failed: %s" % (scene, name, str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__))
                self.log("  %-16s FAILED %s" % (name, self.notes[-1]))
            finally:
                self.clear_options(prefix)
                if structured:
                    for H in mats:
                        H.destroy()
        if args.spectra and self.size == 1 and meta0["cells"] <= args.spectra_max_cells:
            self.matrix_spectrum(scene, syss[0])

    # -- spectra -------------------------------------------------------------------------------------------------------
    def pc_spectrum(self, scene, sysm, A, ksp, name):
        """Extreme eigenvalues of the preconditioned operator Q P^-1 A (Q removes the constant when the pressure is
        pure Neumann, as KSP does after each preconditioner application) on the complement of the null space: SLEPc
        Krylov-Schur (non-Hermitian: P^-1 A is self-adjoint in the A inner product only), and for small systems the
        whole spectrum from the dense operator."""
        PETSc = self.PETSc
        import slepc4py
        slepc4py.init([])
        from slepc4py import SLEPc
        pc = ksp.getPC()
        ns = sysm["ns"]
        tmp = A.createVecLeft()

        class Op:
            def mult(self, mat, x, y):
                A.mult(x, tmp)
                pc.apply(tmp, y)
                if ns:
                    ns.remove(y)

        n_loc, n = A.getLocalSize()[0], A.getSize()[0]
        M = PETSc.Mat().createPython(((n_loc, n), (n_loc, n)), Op(), comm=self.comm)
        M.setUp()
        out = dict(scene=scene, step=sysm["meta"]["step"], cells=n, solver=name, pc=SOLVERS[name]["pc"])
        pc_key = name.split("_", 1)[1]
        out["pc_key"] = pc_key
        t0 = time.perf_counter()
        for which, key in ((SLEPc.EPS.Which.LARGEST_REAL, "max"), (SLEPc.EPS.Which.SMALLEST_REAL, "min")):
            eps = SLEPc.EPS().create(self.comm)
            eps.setOperators(M)
            eps.setProblemType(SLEPc.EPS.ProblemType.NHEP)
            eps.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
            eps.setWhichEigenpairs(which)
            eps.setDimensions(nev=1, ncv=min(n - 2, 24))
            eps.setTolerances(tol=1e-5, max_it=self.args.eps_max_it)
            if ns:
                c = A.createVecRight()
                c.set(1.0 / np.sqrt(n))
                eps.setDeflationSpace([c])
            eps.solve()
            nconv = eps.getConverged()
            vals = [eps.getEigenvalue(i) for i in range(nconv)]
            if vals:
                v = sorted(vals, key=lambda z: z.real)
                out["slepc_" + key] = float((v[-1] if key == "max" else v[0]).real)
                out["slepc_%s_imag" % key] = float(max(abs(z.imag) for z in vals))
            else:
                out["slepc_" + key] = None
            out["slepc_%s_converged" % key] = nconv
            out["slepc_%s_its" % key] = eps.getIterationNumber()
            eps.destroy()
        out["slepc_s"] = time.perf_counter() - t0
        if out.get("slepc_max") and out.get("slepc_min"):
            out["slepc_cond"] = out["slepc_max"] / out["slepc_min"]
        if n <= self.args.dense_max:
            # every eigenvalue, from dense matrices: the preconditioner's inverse P^-1 column by column, and A. For a
            # symmetric P^-1 the nonzero eigenvalues of P^-1 A are those of the symmetric A^1/2 P^-1 A^1/2 (AB and BA
            # share them), which LAPACK's symmetric solver gives in a fraction of the general one's time; the null
            # vector of A (the constant) adds one zero, dropped. A non-symmetric P^-1 takes the general solver on Q P^-1 A.
            Pinv = np.empty((n, n))
            e = A.createVecRight()
            y = A.createVecLeft()
            # Only Q P^-1 Q matters (the residuals KSP preconditions have no constant component, and KSP removes it
            # from the result): the columns are P^-1 applied to Q e_j. Applied to e_j itself an AMG's coarse solve of
            # the singular matrix meets an inconsistent right-hand side and returns a huge constant component whose
            # round-off swamps the rest.
            for j in range(n):
                e.set(-1.0 / n if ns else 0.0)
                e.setValue(j, 1.0 - 1.0 / n if ns else 1.0)
                e.assemble()
                pc.apply(e, y)
                if ns:
                    ns.remove(y)
                Pinv[:, j] = y.getArray()
            Ad = self.dense(sysm["A"])  # the AIJ copy: a structured (hypre) matrix has no CSR rows to read
            asym = np.abs(Pinv - Pinv.T).max() / np.abs(Pinv).max()
            out["dense_pc_asymmetry"] = float(asym)
            if asym < 1e-8:
                w, V = np.linalg.eigh(Ad)
                S = (V * np.sqrt(np.clip(w, 0.0, None))) @ V.T
                Ps = 0.5 * (Pinv + Pinv.T)
                lam = np.linalg.eigvalsh(S @ Ps @ S)
                if ns:
                    lam = np.sort(lam)[1:]
                out["dense_method"] = "symmetric: eig(A^1/2 P^-1 A^1/2)"
                out["dense_max_imag"] = 0.0
            else:
                Mq = Pinv @ Ad  # Q P^-1 Q A = Q P^-1 A (A Q = A)
                lam = np.linalg.eigvals(Mq)
                out["dense_max_imag"] = float(np.abs(lam.imag).max())
                lam = lam.real
                if ns:
                    lam = np.sort(lam)
                    lam = np.delete(lam, np.argmin(np.abs(lam)))
                out["dense_method"] = "general: eig(Q P^-1 A)"
            lam = np.sort(np.asarray(lam).real)
            out["dense_eigs"] = lam.tolist()
            out["dense_min"] = float(lam.min())
            out["dense_max"] = float(lam.max())
            out["dense_cond"] = out["dense_max"] / out["dense_min"] if out["dense_min"] > 0 else None
        M.destroy()
        self.spectra.append(out)

    def dense(self, A):
        """A as a dense array (1 rank, small systems)."""
        indptr, cols, vals = A.getValuesCSR()
        n = A.getSize()[0]
        D = np.zeros((n, n))
        D[np.repeat(np.arange(n), np.diff(indptr)), cols] = vals
        return D

    def matrix_spectrum(self, scene, sysm):
        """The matrix itself: its largest eigenvalue and the eigenvalues nearest 0 (shift-and-invert about a small
        negative shift, Cholesky): how many sit at 0 (the constant null space: one expected when the pressure is pure
        Neumann) and near it."""
        PETSc = self.PETSc
        import slepc4py
        slepc4py.init([])
        from slepc4py import SLEPc
        A = sysm["A"].duplicate(copy=True)  # without the null space: the shifted factorisation below sees the matrix as it is
        A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        out = dict(scene=scene, step=sysm["meta"]["step"], cells=A.getSize()[0])
        one = A.createVecRight()
        one.set(1.0)
        r = A.createVecLeft()
        A.mult(one, r)
        out["A_times_ones_rel"] = r.norm() / (A.norm(PETSc.NormType.INFINITY) * np.sqrt(A.getSize()[0]))
        out["b_dot_ones_rel"] = abs(sysm["b"].sum()) / (sysm["b"].norm() * np.sqrt(A.getSize()[0])) if sysm["b"].norm() else 0.0
        t0 = time.perf_counter()
        eps = SLEPc.EPS().create(self.comm)
        eps.setOperators(A)
        eps.setProblemType(SLEPc.EPS.ProblemType.HEP)
        eps.setWhichEigenpairs(SLEPc.EPS.Which.LARGEST_REAL)
        eps.setDimensions(nev=1)
        eps.setTolerances(tol=1e-8, max_it=1000)
        eps.solve()
        lmax = eps.getEigenvalue(0).real if eps.getConverged() else float(A.norm(PETSc.NormType.INFINITY))
        eps.destroy()
        eps = SLEPc.EPS().create(self.comm)
        eps.setOperators(A)
        eps.setProblemType(SLEPc.EPS.ProblemType.HEP)
        eps.setDimensions(nev=8)
        eps.setTolerances(tol=1e-10, max_it=200)
        st = eps.getST()
        st.setType(SLEPc.ST.Type.SINVERT)
        sigma = -1e-6 * lmax
        eps.setTarget(sigma)
        eps.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_MAGNITUDE)
        st.setShift(sigma)
        sksp = st.getKSP()
        sksp.setType("preonly")
        spc = sksp.getPC()
        spc.setType("cholesky")
        spc.setFactorSolverType("mumps")
        eps.solve()
        vals = sorted(eps.getEigenvalue(i).real for i in range(eps.getConverged()))
        eps.destroy()
        A.destroy()
        out.update(lambda_max=float(lmax), smallest=[float(v) for v in vals], seconds=time.perf_counter() - t0)
        rel = [abs(v) / lmax for v in vals]
        out["zero_modes"] = int(sum(1 for v in rel if v < 1e-10))
        out["near_null_modes"] = int(sum(1 for v in rel if v < 1e-4))
        nonzero = [v for v, q in zip(vals, rel) if q >= 1e-10]
        if nonzero:
            out["lambda_min_nonzero"] = float(nonzero[0])
            out["cond_effective"] = float(lmax / nonzero[0])
        self.matrix_spectra.append(out)

    def run(self):
        groups = find_dumps(self.args.dumps)
        if not groups:
            sys.exit("ksp_compare.py: no dumps (pressure_step*.bin with their .json) under %s" % " ".join(self.args.dumps))
        solvers = solver_names(self.args.solvers)
        # smallest systems first: their results come early in a long study
        groups = dict(sorted(groups.items(), key=lambda kv: (json.load(open(kv[1][0][:-4] + ".json"))["cells"], kv[0])))
        multi = {}
        for d, _ in groups:
            multi[d] = multi.get(d, 0) + 1
        for (directory, first), files in groups.items():
            self.run_sequence(directory, files, solvers, multi[directory] > 1)
            if self.rank == 0:  # after each sequence: a long study that is stopped keeps what it measured
                with open(self.args.worker_out + ".tmp", "w") as f:
                    json.dump(dict(ranks=self.size, records=self.records, systems=self.systems, spectra=self.spectra, matrix_spectra=self.matrix_spectra,
                                   histories=self.histories, notes=self.notes), f)
                os.replace(self.args.worker_out + ".tmp", self.args.worker_out)


# ---------------------------------------------------------------------------------------------------------------------
# Driver: rank counts, merging, tables and plots (no PETSc needed).

def summarise(records, args_rtol):
    """Per (scene, ranks, solver): mean iterations by mode and guess, set-up and solve time, cost per simulated second."""
    rows = {}
    for r in records:
        key = (r["scene"], r["ranks"], r["solver"])
        rows.setdefault(key, []).append(r)
    out = []
    for (scene, ranks, solver), rs in rows.items():
        def pick(mode, guess):
            return [r for r in rs if r["mode"] == mode and r["guess"] == guess]
        reb_prev, reb_zero, reu_prev = pick("rebuild", "previous"), pick("rebuild", "zero"), pick("reuse", "previous")
        main = reb_prev or reb_zero
        setups = [r["setup_each_s"] for r in main if r.get("setup_each_s") is not None]
        setup = float(np.median(setups)) if setups else 0.0
        solve = float(np.median([r["solve_s"] for r in main]))
        sps = float(np.mean([r["steps_per_second"] for r in main]))
        row = dict(scene=scene, ranks=ranks, solver=solver, cells=main[0]["cells"], systems=len(main),
                   its_prev=float(np.mean([r["its"] for r in reb_prev])) if reb_prev else None,
                   its_zero=float(np.mean([r["its"] for r in reb_zero])) if reb_zero else None,
                   its_reuse=float(np.mean([r["its"] for r in reu_prev])) if reu_prev else None,
                   its_max=int(max(r["its"] for r in rs)),
                   converged=all(r["reason"] > 0 and r["true_rel_residual"] <= 100 * args_rtol for r in rs),
                   worst_true_residual=float(max(r["true_rel_residual"] for r in rs)), setup_s=setup, solve_s=solve,
                   solve_zero_s=float(np.mean([r["solve_s"] for r in reb_zero])) if reb_zero else None,
                   solve_reuse_s=float(np.mean([r["solve_s"] for r in reu_prev])) if reu_prev else None, steps_per_second=sps,
                   est_cond=float(np.median([r["est_cond"] for r in reb_zero if r.get("est_cond")])) if any(r.get("est_cond") for r in reb_zero) else None,
                   mg_factors=main[0].get("mg_factors"))
        row["cost_rebuild"] = (setup + solve) * sps  # wall s per simulated s: set-up and solve every step
        if reu_prev:
            # the preconditioner of one step kept for the next len(reu)+1: its set-up shared, the later solves slower
            k = len(reu_prev) + 1
            row["cost_reuse"] = (setup / k + (solve + sum(r["solve_s"] for r in reu_prev)) / k) * sps
        out.append(row)
    return out


def fmt(v, f="%.3g"):
    return "-" if v is None else (f % v)


def markdown(data, args):
    lines = []
    load = data.get("load", {})
    lines.append("Generated by `scripts/ksp_compare.py %s` on %s; load average before/after each rank count: %s. Times are wall seconds on a shared "
                 "2-core machine and carry tens of percent of noise; iteration counts do not." % (" ".join(data.get("argv", [])), data.get("date", ""),
                                                                                                 ", ".join("%s ranks: %s / %s" % (k, v[0], v[1]) for k, v in load.items())))
    lines.append("")
    lines.append("### Systems")
    lines.append("")
    lines.append("| scene | step | t (s) | grid | cells | model | drag | eps min-max | face coefficient min-max (contrast) | run PC, its | dumped x residual |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
    seen = set()
    for s in data["systems"]:
        if s["ranks"] != min(data["ranks"]) or (s["scene"], s["step"]) in seen:
            continue
        seen.add((s["scene"], s["step"]))
        lines.append("| %s | %d | %.5g | %s | %d | %s | %s | %s-%s | %s-%s (%s) | %s, %s | %s |" % (
            s["scene"], s["step"], s["time"], " x ".join(str(v) for v in s["n"][:s["dim"]]), s["cells"], s["model"], "on" if s["implicit_drag"] else "off",
            fmt(s.get("eps_min"), "%.3f"), fmt(s.get("eps_max"), "%.3f"), fmt(s.get("coef_min"), "%.3g"), fmt(s.get("coef_max"), "%.3g"),
            fmt(s.get("coef_contrast"), "%.3g"), s.get("run_pc_type"), s.get("run_ksp_iterations"), fmt(s.get("dumped_solution_rel_residual"), "%.1e")))
    lines.append("")
    lines.append("### Solvers")
    lines.append("")
    lines.append("Iterations are means over the scene's dumped steps: *prev* from the previous step's pressure (the run's initial guess), *zero* from "
                 "zero, *reuse* with the first step's preconditioner kept (previous-step guess). Set-up and solve: median seconds per step (rebuild, "
                 "previous guess). Cost: wall seconds per simulated second of bed = (set-up + solve) x gas steps per simulated second (rebuild "
                 "every step), and with the preconditioner kept over the dumped steps. cond est: KSP's Lanczos/Arnoldi estimate of the preconditioned "
                 "operator's condition number (zero guess).")
    lines.append("")
    lines.append("| scene | cells | ranks | solver | its prev | its zero | its reuse | set-up (s) | solve (s) | cost rebuild (s/s) | cost reuse (s/s) | cond est | ok |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in sorted(data["summary"], key=lambda r: (r["cells"], r["scene"], r["ranks"], r["cost_rebuild"])):
        lines.append("| %s | %d | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["scene"], r["cells"], r["ranks"], r["solver"], fmt(r["its_prev"], "%.1f"), fmt(r["its_zero"], "%.1f"), fmt(r["its_reuse"], "%.1f"),
            fmt(r["setup_s"], "%.3g"), fmt(r["solve_s"], "%.3g"), fmt(r["cost_rebuild"], "%.3g"), fmt(r.get("cost_reuse"), "%.3g"),
            fmt(r["est_cond"], "%.3g"), "yes" if r["converged"] else "NO"))
    if data["spectra"]:
        lines.append("")
        lines.append("### Spectra of the preconditioned operator (1 rank)")
        lines.append("")
        lines.append("SLEPc: Krylov-Schur on Q P^-1 A with the constant deflated (tolerance 1e-5); dense: every eigenvalue of the dense operator "
                     "(small systems). cond = lambda_max / lambda_min on the complement of the null space.")
        lines.append("")
        lines.append("| scene | step | cells | PC | SLEPc min | SLEPc max | SLEPc cond | dense min | dense max | dense cond | max imag | KSP estimate |")
        lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
        est = {}
        for r in data["records"]:
            if r["ranks"] == 1 and r["mode"] == "rebuild" and r["guess"] == "zero" and r.get("est_cond"):
                est.setdefault((r["scene"], r["step"], r["solver"]), r["est_cond"])
        for s in data["spectra"]:
            lines.append("| %s | %d | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                s["scene"], s["step"], s["cells"], s["solver"], fmt(s.get("slepc_min"), "%.4g"), fmt(s.get("slepc_max"), "%.4g"),
                fmt(s.get("slepc_cond"), "%.4g"), fmt(s.get("dense_min"), "%.4g"), fmt(s.get("dense_max"), "%.4g"), fmt(s.get("dense_cond"), "%.4g"),
                fmt(max(s.get("slepc_max_imag") or 0, s.get("slepc_min_imag") or 0, s.get("dense_max_imag") or 0), "%.1e"),
                fmt(est.get((s["scene"], s["step"], s["solver"])), "%.4g")))
    if data["matrix_spectra"]:
        lines.append("")
        lines.append("### The matrix itself (1 rank)")
        lines.append("")
        lines.append("| scene | step | cells | lambda_max | eigenvalues nearest 0 / lambda_max | zero modes (< 1e-10) | near-null (< 1e-4) | cond (nonzero) | "
                     "\\|A 1\\| rel | \\|1.b\\| rel |")
        lines.append("|---|---|---|---|---|---|---|---|---|---|")
        for s in data["matrix_spectra"]:
            lines.append("| %s | %d | %d | %.4g | %s | %d | %d | %s | %.1e | %.1e |" % (
                s["scene"], s["step"], s["cells"], s["lambda_max"], ", ".join("%.2e" % (v / s["lambda_max"]) for v in s["smallest"][:5]),
                s["zero_modes"], s["near_null_modes"], fmt(s.get("cond_effective"), "%.4g"), s["A_times_ones_rel"], s["b_dot_ones_rel"]))
    if data["notes"]:
        lines.append("")
        lines.append("Notes from the runs:")
        lines.append("")
        for n in sorted(set(data["notes"])):
            lines.append("- " + n)
    return "\n".join(lines) + "\n"


def style(i):
    """Colour and line style of the i-th curve: ten colours, then the next line style."""
    return dict(color="C%d" % (i % 10), ls=["-", "--", "-.", ":"][(i // 10) % 4])


def plots(data, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    made = []

    def save(fig, path):
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
        return path

    # convergence histories: one figure per scene (first step, 1 rank, zero guess)
    scenes = sorted(set(h["scene"] for h in data["histories"] if h["ranks"] == min(data["ranks"])))
    for scene in scenes:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for i, h in enumerate(x for x in data["histories"] if x["scene"] == scene and x["ranks"] == min(data["ranks"])):
            ax.semilogy(range(len(h["residuals"])), h["residuals"], label=h["solver"], lw=1.2, **style(i))
        ax.set_xlabel("iteration")
        ax.set_ylabel("||b - A x|| / ||b||")
        ax.set_title("%s: convergence from a zero guess (first dumped step)" % scene, fontsize=9)
        ax.axhline(1e-8, color="k", lw=0.5, ls=":")
        ax.set_xscale("symlog", linthresh=30)
        ax.legend(fontsize=7, ncol=2)
        made.append(save(fig, os.path.join(out, "history_%s.png" % scene)))
    # iterations against grid size: scenes grouped into families (a trailing _r<k> is a refinement of one scene)
    fam = {}
    for r in data["summary"]:
        if r["ranks"] != min(data["ranks"]) or r["its_zero"] is None:
            continue
        f = re.sub(r"_r\d+$", "", r["scene"])
        fam.setdefault(f, {}).setdefault(r["solver"], []).append((r["cells"], r["its_zero"]))
    for f, by_solver in fam.items():
        if max(len(v) for v in by_solver.values()) < 2:
            continue
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        for i, (solver, pts) in enumerate(sorted(by_solver.items())):
            pts.sort()
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker="o", label=solver, lw=1.2, ms=4, **style(i))
        ax.set_xlabel("cells")
        ax.set_ylabel("iterations to 1e-8 (zero guess, mean over steps)")
        ax.set_title("%s: iterations against grid size" % f, fontsize=9)
        ax.legend(fontsize=7, ncol=2)
        made.append(save(fig, os.path.join(out, "iterations_vs_cells_%s.png" % f)))
    # spectra: eigenvalues of the preconditioned operator per PC (dense where available, SLEPc extremes otherwise)
    for scene in sorted(set(s["scene"] for s in data["spectra"])):
        ss = [s for s in data["spectra"] if s["scene"] == scene]
        fig, ax = plt.subplots(figsize=(7, 0.45 * len(ss) + 1.5))
        for y, s in enumerate(ss):
            if s.get("dense_eigs"):
                ev = np.asarray(s["dense_eigs"])
                ax.plot(ev, np.full(ev.size, y), "|", ms=9, alpha=0.5)
            for key in ("slepc_min", "slepc_max"):
                if s.get(key):
                    ax.plot([s[key]], [y], "kx", ms=6)
        ax.set_yticks(range(len(ss)))
        ax.set_yticklabels([s["solver"] for s in ss], fontsize=7)
        ax.set_xscale("log")
        ax.set_xlabel("eigenvalues of P^-1 A (| dense, x SLEPc extremes)")
        ax.set_title("%s, step %d: spectra of the preconditioned operator" % (scene, ss[0]["step"]), fontsize=9)
        made.append(save(fig, os.path.join(out, "spectrum_%s.png" % scene)))
    return made


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("dumps", nargs="*", help="dump directories (a run's output directory or its pressure_dump) or pressure_step*.bin files")
    ap.add_argument("--solvers", default="main", help="comma-separated solver names or presets (%s); default main" % ", ".join(PRESETS))
    ap.add_argument("--list", action="store_true", help="print the catalogue and exit")
    ap.add_argument("--ranks", default="1", help="comma-separated rank counts, each run under mpiexec (default 1)")
    ap.add_argument("--out", default="bench/ksp/compare", help="output directory (default bench/ksp/compare)")
    ap.add_argument("--guesses", default="zero,previous", help="initial guesses: zero, previous (default both)")
    ap.add_argument("--no-reuse", action="store_true", help="skip the runs that keep the first step's preconditioner")
    ap.add_argument("--steps", type=int, default=0, help="at most this many dumped steps per directory (0: all)")
    ap.add_argument("--repeat", type=int, default=1, help="time each solve this many times and keep the fastest (default 1)")
    ap.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance (the run's default 1e-8)")
    ap.add_argument("--max-it", type=int, default=5000, help="iteration limit")
    ap.add_argument("--max-cells", type=int, default=1 << 40, help="skip systems larger than this")
    ap.add_argument("--no-size-limits", action="store_true",
                    help="run solvers with a size limit of their own (point Jacobi: 40,000 cells) on larger systems too")
    ap.add_argument("--spectra", action="store_true", help="SLEPc spectra of the preconditioned operators and of the matrix (1 rank)")
    ap.add_argument("--spectra-max-cells", type=int, default=200000, help="largest system for --spectra (default 200000)")
    ap.add_argument("--dense-max", type=int, default=2500, help="largest system whose whole spectrum is computed densely (default 2500)")
    ap.add_argument("--eps-max-it", type=int, default=300, help="Krylov-Schur restarts for the extreme eigenvalues")
    ap.add_argument("--derive", choices=["A", "B"], help="solve the operator of this model assembled again from the dumped void fraction and drag "
                    "(coupled runs are model B only: --derive A gives model A's operator of a coupled bed; --derive B checks the reassembly)")
    ap.add_argument("--no-plots", action="store_true", help="no PNG files")
    ap.add_argument("--merge", nargs="*", help="merge these ksp_compare.json files (and their tables) instead of solving")
    ap.add_argument("--mpiexec", default=os.environ.get("FLUIDBED_MPIEXEC", "mpiexec"), help="MPI launcher")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--worker-out", help=argparse.SUPPRESS)
    ap.add_argument("--petsc-options", nargs=argparse.REMAINDER, help="PETSc options for every solve (last on the command line)")
    args = ap.parse_args()
    args.guesses = [g for g in args.guesses.split(",") if g]
    if args.list:
        for name, spec in SOLVERS.items():
            print("%-16s %s" % (name, spec["desc"]))
        for name, members in PRESETS.items():
            print("preset %-9s %s" % (name, ",".join(members)))
        return
    if args.worker_out:
        _need_petsc4py()
        Worker(args).run()
        return
    os.makedirs(args.out, exist_ok=True)
    if args.merge:
        parts = [json.load(open(p)) for p in args.merge]
        data = dict(argv=sum((p.get("argv", []) for p in parts), []), date=parts[0].get("date"), ranks=sorted(set(sum((p["ranks"] for p in parts), []))),
                    load={k: v for p in parts for k, v in p.get("load", {}).items()})
        for key in ("records", "systems", "spectra", "matrix_spectra", "histories", "notes"):
            data[key] = sum((p[key] for p in parts), [])
    else:
        if not args.dumps:
            ap.error("no dumps given")
        _need_petsc4py()
        ranks = [int(r) for r in args.ranks.split(",") if r]
        data = dict(argv=sys.argv[1:], date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), ranks=ranks, load={}, records=[], systems=[], spectra=[],
                    matrix_spectra=[], histories=[], notes=[])
        env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"), OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
        for n in ranks:
            part = os.path.join(args.out, "raw_%d.json" % n)
            cmd = [sys.executable, os.path.abspath(__file__), "--worker-out", part, "--solvers", args.solvers, "--guesses", ",".join(args.guesses),
                   "--steps", str(args.steps), "--repeat", str(args.repeat), "--rtol", str(args.rtol), "--max-it", str(args.max_it), "--max-cells", str(args.max_cells),
                   "--spectra-max-cells", str(args.spectra_max_cells)] + (["--derive", args.derive] if args.derive else []) + [
                    "--dense-max", str(args.dense_max), "--eps-max-it", str(args.eps_max_it)]
            cmd += ["--no-reuse"] * args.no_reuse + ["--no-size-limits"] * args.no_size_limits + ["--spectra"] * (args.spectra and n == 1) + ["--quiet"] * args.quiet + list(args.dumps)
            if args.petsc_options:
                cmd += ["--petsc-options"] + args.petsc_options
            if n > 1:
                cmd = launcher(n, args.mpiexec) + cmd
            before = "%.2f" % os.getloadavg()[0]
            print("ksp_compare: %d rank(s), load %s: %s" % (n, before, " ".join(cmd)), flush=True)
            p = subprocess.run(cmd, env=env)
            if p.returncode != 0:
                sys.exit("ksp_compare.py: the %d-rank run failed (exit %d)" % (n, p.returncode))
            part_data = json.load(open(part))
            data["load"][str(n)] = (before, "%.2f" % os.getloadavg()[0])
            for key in ("records", "systems", "spectra", "matrix_spectra", "histories", "notes"):
                data[key] += part_data[key]
    data["summary"] = summarise(data["records"], args.rtol)
    with open(os.path.join(args.out, "ksp_compare.json"), "w") as f:
        json.dump(data, f, indent=1)
    text = markdown(data, args)
    with open(os.path.join(args.out, "ksp_compare.md"), "w") as f:
        f.write(text)
    if not args.quiet:
        print(text)
    if not args.no_plots:
        for p in plots(data, args.out):
            print("wrote " + p)


if __name__ == "__main__":
    main()
