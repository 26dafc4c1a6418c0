"""The KSP comparison's smallest case (docs/ksp.md): pressure systems dumped from a running bed load and are what
they should be, and scripts/ksp_compare.py solves them.

- The default 2D jetted bed (33 x 60 cells, implicit drag on) dumps gas steps 1-4 on 1 rank and step 3 on 2 ranks;
  a gas-only box (no particles, so no drag) dumps step 1 in model B.
- Each dump loads with petsc4py: the matrix is square with one row per cell, symmetric (each face coefficient enters
  the two rows that share the face), its rows sum to 0 and the right-hand side to 0 (pure Neumann pressure: the
  constant null space), and the dumped solution solves it to the run's tolerance. Without drag, model B's operator has
  constant coefficients: every off-diagonal entry is -A_f / h_f of its direction (two values in 2D). With the drag the
  coefficients vary (more than two values).
- The dump is in natural ordering: the 2-rank dump of step 3 equals the 1-rank one to round-off.
- ksp_compare.py with CG + BoomerAMG and CG + ICC on the four steps (rebuild and reuse, zero and previous guess)
  converges in a finite number of iterations with the true residual at the tolerance; the operator assembled again
  from the dumped void fraction and drag (--derive B) equals the dumped matrix.
- scripts/ksp_report.py --keep-csv adds a part to the tables written from an earlier one, and a part given again
  replaces its own rows."""
import csv
import glob
import json
import os
import subprocess
import sys

from fluidbed_tools import testing as t

bed = t.example("jetted_bed_2d.opts")
out1, _ = t.run(bed, args=["-max_steps", 4, "-fluid_p_dump_steps", "1-5"], outdir="ksp_bed_1")
out2, _ = t.run(bed, args=["-max_steps", 3, "-fluid_p_dump_steps", 3], nprocs=2, outdir="ksp_bed_2")
out3, _ = t.run(bed, args=["-particles", 0, "-max_steps", 1, "-fluid_p_dump_steps", 1, "-fluid_eps_packed_bed", "0.03,0.45"], outdir="ksp_gas")


# the study's smallest case
script = os.path.join(t.SRC, "scripts", "ksp_compare.py")
res = os.path.abspath("ksp_compare_ci")
p = subprocess.run([sys.executable, script, out1, "--solvers", "cg_hypre,cg_icc", "--ranks", "1", "--out", res, "--no-plots", "--quiet"],
                   capture_output=True, text=True, timeout=300)
print(p.stdout[-1500:], p.stderr[-1500:])
t.check(p.returncode == 0, "ksp_compare.py ran (exit %d)" % p.returncode)
data = json.load(open(os.path.join(res, "ksp_compare.json")))
recs = data["records"]
for solver in ("cg_hypre", "cg_icc"):
    rs = [r for r in recs if r["solver"] == solver]
    modes = sorted(set((r["mode"], r["guess"]) for r in rs))
    its = [r["its"] for r in rs]
    t.check(len(rs) == 4 * 2 + 3 * 2 and all(r["reason"] > 0 and 0 < r["its"] < 5000 and r["true_rel_residual"] <= 2e-8 for r in rs),
            "%s: %d solves (%s) converged in %d-%d iterations, true residual at most %.1e" % (
                solver, len(rs), ", ".join("%s/%s" % m for m in modes), min(its), max(its), max(r["true_rel_residual"] for r in rs)))
rows = {r["solver"]: r for r in data["summary"]}
t.check(rows["cg_hypre"]["its_zero"] < rows["cg_icc"]["its_zero"] and rows["cg_hypre"]["cost_rebuild"] > 0 and os.path.exists(os.path.join(res, "ksp_compare.md")),
        "BoomerAMG needs fewer iterations than ICC (%.1f against %.1f from zero); cost %.3g wall s per simulated s; table written" % (
            rows["cg_hypre"]["its_zero"], rows["cg_icc"]["its_zero"], rows["cg_hypre"]["cost_rebuild"]))
p = subprocess.run([sys.executable, script, out1, "--solvers", "cg_hypre", "--steps", "1", "--no-reuse", "--derive", "B", "--out", res + "_derive",
                    "--no-plots", "--quiet"], capture_output=True, text=True, timeout=300)
t.check(p.returncode == 0, "ksp_compare.py --derive B ran (exit %d)" % p.returncode)
sysm = json.load(open(os.path.join(res + "_derive", "ksp_compare.json")))["systems"][0]
t.check(sysm["reassembly_vs_dumped"] < 1e-9, "the operator assembled again from the dumped eps and drag equals the dumped matrix: %.1e relative (the JSON carries h and dt to 10 digits)"
        % sysm["reassembly_vs_dumped"])

# the report adds a part to the tables of earlier ones (--keep-csv) and replaces a part given again, without duplicates
report = os.path.join(t.SRC, "scripts", "ksp_report.py")
tables, figs = os.path.abspath("ksp_report_ci"), os.path.abspath("ksp_report_ci_figures")
counts = []
for parts in ([res], [res + "_derive"], [res + "_derive"]):
    p = subprocess.run([sys.executable, report] + [os.path.join(x, "ksp_compare.json") for x in parts] + ["--csv", tables, "--figures", figs] +
                       ["--keep-csv"] * (len(counts) > 0), capture_output=True, text=True, timeout=300)
    t.check(p.returncode == 0, "ksp_report.py %s ran (exit %d) %s" % (os.path.basename(parts[0]), p.returncode, p.stderr[-500:]))
    with open(os.path.join(tables, "solvers.csv")) as f:
        rows = list(csv.DictReader(f))
    counts.append(sorted((r["part"], r["solver"]) for r in rows))
t.check(counts[0] == [("ksp_compare_ci", "cg_hypre"), ("ksp_compare_ci", "cg_icc")] and
        counts[1] == counts[0] + [("ksp_compare_ci_derive", "cg_hypre")] and counts[2] == counts[1],
        "solvers.csv: %d rows from the first part, %d after adding the second with --keep-csv, %d after giving it again" % tuple(len(c) for c in counts))

# petsc4py initialises MPI: imported after the runs above, whose mpiexec must not inherit a singleton's environment
try:
    import petsc4py
    petsc4py.init([])
    from petsc4py import PETSc
except ImportError:
    t.fail("petsc4py is missing: scripts/test.sh installs python3-petsc4py (FLUIDBED_TEST_PACKAGES in scripts/setup.sh)")


def load(path):
    meta = json.load(open(path[:-4] + ".json"))
    viewer = PETSc.Viewer().createBinary(path, "r", comm=PETSc.COMM_SELF)
    A = PETSc.Mat().create(PETSc.COMM_SELF)
    A.setType("aij")
    A.load(viewer)
    vecs = []
    for _ in range(5):
        v = PETSc.Vec().create(PETSc.COMM_SELF)
        v.load(viewer)
        vecs.append(v)
    return meta, A, vecs


files = sorted(glob.glob(os.path.join(out1, "pressure_dump", "pressure_step*.bin")))
t.check(len(files) == 4, "1 rank: %d dumps (steps 1-4 asked)" % len(files))
for path in files + [os.path.join(out3, "pressure_dump", "pressure_step00000001.bin")]:
    meta, A, (b, x0, x, eps, beta) = load(path)
    name = "%s step %d" % (os.path.basename(os.path.dirname(os.path.dirname(path))), meta["step"])
    rows, cols = A.getSize()
    t.check(rows == cols == meta["cells"] == meta["n"][0] * meta["n"][1] == 1980 and b.getSize() == eps.getSize() == rows,
            "%s: the matrix is %d x %d, %d cells (%d x %d), vectors of %d" % (name, rows, cols, meta["cells"], meta["n"][0], meta["n"][1], b.getSize()))
    At = A.copy()
    At.transpose()
    At.axpy(-1.0, A)
    asym = At.norm() / A.norm()
    t.check(asym < 1e-14, "%s: symmetric, ||A - A^T|| / ||A|| = %.1e" % (name, asym))
    one = A.createVecRight()
    one.set(1.0)
    r = A.createVecLeft()
    A.mult(one, r)
    t.check(meta["constant_null_space"] and r.norm() < 1e-12 * A.norm() and abs(b.sum()) < 1e-10 * b.norm() * rows ** 0.5,
            "%s: pure Neumann: ||A 1|| = %.1e (||A|| %.3g), sum(b) = %.1e (||b|| %.3g)" % (name, r.norm(), A.norm(), b.sum(), b.norm()))
    A.mult(x, r)
    r.aypx(-1.0, b)
    t.check(r.norm() <= 1e-7 * b.norm(), "%s: the dumped solution solves the dumped system: residual %.1e of ||b||" % (name, r.norm() / b.norm()))
    indptr, cj, cv = A.getValuesCSR()
    offdiag = set()
    for i in range(rows):
        for k in range(indptr[i], indptr[i + 1]):
            if cj[k] != i:
                offdiag.add(round(float(cv[k]), 15))
    h = meta["h"]
    expect = {round(-h[1] * h[2] / h[0], 15), round(-h[0] * h[2] / h[1], 15)}
    if not meta["implicit_drag"]:
        t.check(meta["model"] == "B" and offdiag == expect,
                "%s: model B without drag: constant coefficients, off-diagonals %s (expected -A_f/h_f: %s)" % (name, sorted(offdiag), sorted(expect)))
    else:
        t.check(len(offdiag) > 2 and max(abs(v) for v in offdiag) <= max(abs(v) for v in expect) * (1 + 1e-12),
                "%s: implicit drag on: %d distinct off-diagonal values, at most |-A_f/h_f| (the drag only lowers c_f)" % (name, len(offdiag)))

# the same step dumped on 2 ranks (natural ordering): equal to round-off
_, A1, v1 = load(os.path.join(out1, "pressure_dump", "pressure_step00000003.bin"))
m2, A2, v2 = load(os.path.join(out2, "pressure_dump", "pressure_step00000003.bin"))
D = A1.copy()
D.axpy(-1.0, A2)
dv = max((a - c).norm() / max(a.norm(), 1e-300) for a, c in zip(v1, v2) if a.norm() > 0)
t.check(m2["ranks"] == 2 and D.norm() < 1e-10 * A1.norm() and dv < 1e-6,
        "step 3 dumped on 2 ranks equals the 1-rank dump: matrix %.1e, vectors at most %.1e relative" % (D.norm() / A1.norm(), dv))

