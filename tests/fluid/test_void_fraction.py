"""Verification 4: a frozen, non-uniform void fraction. Gas enters the bottom at 1 m/s superficial and leaves
through the seed's uniform outlet; a sphere (a circle in 2D) of eps = 0.4 sits in eps = 1 gas. For both momentum
models (B: constant-coefficient pressure equation; A: div(eps grad phi), variable coefficients) the flow stays
divergence-free in the eps-weighted sense, div(eps u) = 0 in every cell after every projection (below the KSP
tolerance times U/h), and inflow = outflow to round-off; plain div(u) is not zero at the sphere's edge. A sphere
moving at 0.5 m/s with -fluid_deps_dt satisfies div(eps u) = -d(eps)/dt instead (model A, the preconditioner
rebuilt every 5 solves with -fluid_pc_reuse 5). A uniform flow through a uniform eps = 0.5 stays uniform (u = U /
eps to round-off) under gravity, with the hydrostatic pressure gradient -rho_g g, in both models."""
import numpy as np

from fluidbed_tools import testing as t
import gas

RTOL, U, rho, g = 1e-8, 1.0, 1.205, 9.81
lx, ly = 0.02, 0.04
box = ["-particles", 0, "-fluid", "-domain_lx", lx, "-domain_ly", ly, "-domain_lz", 0.01, "-inlet_velocity", U, "-fluid_bc_yhi", "outlet",
       "-fluid_bc_xlo", "freeslip", "-fluid_bc_xhi", "freeslip", "-fluid_initial_velocity", "0,%g,0" % U, "-monitor_dt", 0]


def divergence_checks(label, out, h, moving=False):
    """Every projection: max |div(eps u) + d(eps)/dt| below rtol U / h; with a moving eps, whose d(eps)/dt is far
    larger than U / h, below rtol ||b||_2 / V (b: the pressure equation's right-hand side), the bound CG's true
    residual norm gives."""
    mon = gas.monitor(out)
    scale = mon["div_scale"][1:] if moving else mon["gas_max_speed"][1:] / h
    ratio = mon["max_div"][1:] / (RTOL * scale)
    t.check(np.max(ratio) < 1.0, "%s: %d projections, max |div(eps u) + d(eps)/dt| / (rtol %s) at most %.2e (limit 1)"
            % (label, len(ratio), "||b|| / V" if moving else "U / h", np.max(ratio)))
    return mon


for model in ("B", "A"):
    label = "2D sphere eps 0.4, model %s" % model
    out, _ = t.run(args=box + ["-domain_dim", 2, "-grid_nx", 40, "-grid_ny", 80, "-fluid_eps_sphere", "0.01,0.02,0,0.004,0.4", "-fluid_model", model,
                               "-t_final", 0.01], outdir="sphere_2d_%s" % model)
    mon = divergence_checks(label, out, lx / 40)
    q = U * lx * 0.01
    t.check(np.max(np.abs(mon["inflow"] - mon["outflow"])) < 1e-13 * q and abs(mon["inflow"][-1] - q) < 1e-13 * q,
            "%s: inflow = outflow = %.10e m^3/s to round-off" % (label, mon["outflow"][-1]))
    c = gas.cells(out)
    eps, uf, vf = c["eps"][0], c["ufx"][0], c["ufy"][0]
    # eps-weighted and plain divergence of the interior cells, from the face velocities (face eps = mean of its cells)
    ex = 0.5 * (eps[:, 1:] + eps[:, :-1])
    ey = 0.5 * (eps[1:, :] + eps[:-1, :])
    hx, hy = lx / 40, ly / 80
    dw = (ex[1:-1, 1:] * uf[1:-1, 2:] - ex[1:-1, :-1] * uf[1:-1, 1:-1]) / hx + (ey[1:, 1:-1] * vf[2:, 1:-1] - ey[:-1, 1:-1] * vf[1:-1, 1:-1]) / hy
    dp = (uf[1:-1, 2:] - uf[1:-1, 1:-1]) / hx + (vf[2:, 1:-1] - vf[1:-1, 1:-1]) / hy
    t.check(np.max(np.abs(dw)) < RTOL * U / hx * 10 and np.max(np.abs(dp)) > 100.0,
            "%s: from fluid_cells.csv, max |div(eps u)| %.1e 1/s, max |div u| %.3g 1/s (at the sphere's edge)" % (label, np.max(np.abs(dw)), np.max(np.abs(dp))))
    vc = vf[40, 20]
    print("%s: interstitial velocity at the centre %.3f m/s (U / eps = %.3f), pressure drop %.4f Pa"
          % (label, vc, U / 0.4, np.mean(c["p"][0, 0, :]) - np.mean(c["p"][0, -1, :])))

# 3D moving sphere, d(eps)/dt kept, model A with the preconditioner reused for 5 solves
out, _ = t.run(args=box + ["-domain_dim", 3, "-grid_nx", 20, "-grid_ny", 40, "-grid_nz", 5, "-fluid_eps_sphere", "0.01,0.01,0.005,0.004,0.4",
                           "-fluid_eps_sphere_velocity", "0,0.5,0", "-fluid_deps_dt", "-fluid_model", "A", "-fluid_pc_reuse", 5, "-t_final", 0.01,
                           "-fluid_output_cells", 0], outdir="sphere_3d_moving")
mon = divergence_checks("3D moving sphere, model A, -fluid_deps_dt", out, lx / 20, moving=True)
s = t.summary(out)["fluid"]
t.check(s["pressure_pc_setups"] <= (s["pressure_solves"] + 4) // 5 + 1 and s["pressure_pc_setups"] >= 2,
        "3D moving sphere: %d preconditioner set-ups for %d solves with -fluid_pc_reuse 5" % (s["pressure_pc_setups"], s["pressure_solves"]))
t.check(np.max(np.abs(mon["outflow"] - mon["inflow"])) > 1e-9 * U * lx * 0.01,
        "3D moving sphere: outflow - inflow = integral of -d(eps)/dt, up to %.2e m^3/s" % np.max(np.abs(mon["outflow"] - mon["inflow"])))

# uniform flow through a uniform eps = 0.5 under gravity: unchanged
for model in ("B", "A"):
    out, _ = t.run(args=box + ["-domain_dim", 2, "-grid_nx", 20, "-grid_ny", 40, "-fluid_eps", 0.5, "-fluid_model", model, "-t_final", 0.01,
                               "-fluid_p_ksp_rtol", 1e-12], outdir="uniform_%s" % model)
    c = gas.cells(out)
    dv = np.max(np.abs(c["ufy"] - U / 0.5)) / (U / 0.5)
    du = np.max(np.abs(c["ufx"])) / (U / 0.5)
    p = c["p"][0, :, 0]
    slope = np.polyfit(c["y"][0, :, 0], p, 1)[0]
    t.check(dv < 1e-12 and du < 1e-12, "uniform eps 0.5, model %s: v = U / eps to %.1e, u = 0 to %.1e (relative, limit 1e-12)" % (model, dv, du))
    t.check(abs(slope + rho * g) < 1e-8 * rho * g, "uniform eps 0.5, model %s: dp/dy = %.10f Pa/m (-rho_g g = %.10f)" % (model, slope, -rho * g))
