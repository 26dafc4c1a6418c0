"""Coupling verification on a small bed of the Muller particles (examples/coupling/small_bed.opts):

2. packed bed below minimum fluidization (U = 0.15 m/s, about U_mf / 2): the pressure drop between two cell-centre
   heights inside the bed is within 2% of Ergun's for the bed's measured voidage, layer by layer;
3. bubbling bed (U = 0.6 m/s, about 2 U_mf, continued from the packed bed's checkpoint): the time-averaged pressure
   drop across the bed is within 3% of the bed's buoyant weight per unit area;
4. drag action and reaction cancel to round-off in every monitor row, and no particle is lost (mass conserved)."""
import math
import os

import numpy as np

from fluidbed_tools import reference
from fluidbed_tools import testing as t

d, rho_p, mu, rho_g, g = 1.2e-3, 1000.0, 1.8e-5, 1.205, 9.81
A, h = 0.02 * 0.01, 0.06 / 18  # bed cross-section, fluid cell height
Vp = math.pi / 6 * d ** 3
N = 3000


def ergun_gradient(eps, U):
    return reference.ergun_gradient(eps, U, d, mu, rho_g)


def balance(mon, label):
    worst = 0.0
    for c in ("x", "y", "z"):
        fp, fg = mon["drag_particles_" + c], mon["drag_gas_" + c]
        scale = np.max(np.abs(mon["drag_particles_y"])) or 1.0
        worst = max(worst, np.max(np.abs(fp + fg)) / scale)
    t.check(worst < 1e-12, "%s: drag on the particles + drag on the gas = 0 to %.1e of the total drag (limit 1e-12)" % (label, worst))
    t.check(np.all(mon["particles"] == N), "%s: %d particles in every row (mass conserved)" % (label, N))


# 2. packed bed
packed, _ = t.run(t.example("coupling/small_bed.opts"), args=["-t_final", 0.25, "-checkpoint_interval", 0.25], outdir="packed")
mon = t.table(os.path.join(packed, "monitor.csv"))
p = t.table(os.path.join(packed, "particles.csv"))
U = 0.15
dp_meas = mon["p_y5mm_avg"][-1] - mon["p_y18_33mm_avg"][-1] - rho_g * g * 4 * h  # between the centres of layers 1 and 5
dp_ergun = reference.ergun_layers(p["y"], h, 1, 5, Vp, A, lambda eps: ergun_gradient(eps, U))
n = np.sum((p["y"] >= 1.5 * h) & (p["y"] < 5.5 * h))
eps_mean = 1 - n * Vp / (A * 4 * h)
print("packed bed: voidage between the probes %.4f; Ergun at that mean voidage %.3f Pa" % (eps_mean, ergun_gradient(eps_mean, U) * 4 * h))
t.check(mon["ke_trans"][-1] < 1e-4 * mon["ke_trans"].max(), "the packed bed is at rest (kinetic energy %.1e of its peak)" % (mon["ke_trans"][-1] / mon["ke_trans"].max()))
t.check(t.rel(dp_meas, dp_ergun) < 0.02, "packed bed at U = %.2f m/s: pressure drop %.3f Pa, Ergun for the measured voidage (layer by layer) %.3f Pa, %+.2f%% (limit 2%%)"
        % (U, dp_meas, dp_ergun, 100 * (dp_meas / dp_ergun - 1)))
balance(mon, "packed bed")
ke_packed = mon["ke_trans"][-1]

# 3. bubbling bed, continued from the packed bed
bubbling, _ = t.run(t.example("coupling/small_bed.opts"), args=["-restart", os.path.join(packed, "checkpoint.h5"), "-inlet_velocity", 0.6, "-t_final", 0.65],
                    outdir="bubbling")
mon = t.table(os.path.join(bubbling, "monitor.csv"))
late = mon["time"] > 0.35
# pressure at the distributor, extrapolated from the first two cell centres, minus the top probe and the gas column
p0 = mon["p_y1_667mm_avg"] + 0.5 * (mon["p_y1_667mm_avg"] - mon["p_y5mm_avg"])
dp = p0 - mon["p_y50mm_avg"] - rho_g * g * 0.05
weight = N * Vp * (rho_p - rho_g) * g / A
mean = dp[late].mean()
t.check(mon["ke_trans"][late].mean() > 1e3 * ke_packed,
        "the bed is fluidized: mean kinetic energy %.2e J, %.0f times the packed bed's at rest" % (mon["ke_trans"][late].mean(), mon["ke_trans"][late].mean() / ke_packed))
t.check(t.rel(mean, weight) < 0.03, "bubbling bed at U = 0.6 m/s: time-averaged pressure drop %.2f Pa over t = 0.35..0.65 s (fluctuating by %.1f Pa rms), "
        "buoyant bed weight / area %.2f Pa, %+.2f%% (limit 3%%)" % (mean, dp[late].std(), weight, 100 * (mean / weight - 1)))
balance(mon, "bubbling bed")
