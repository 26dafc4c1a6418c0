"""Coupling verification 1: one particle in a uniform upward gas flow settles to the slip velocity u_gas - v_p
equal to the terminal velocity implied by the drag law (examples/coupling/terminal_velocity.opts): the seed's
Ergun/Wen-Yu blend (eq. 2.11-2.17) at the particle cell's void fraction, Model B (drag / eps), buoyancy. The
analytic value solves K(u) u = (rho_p - rho_g) g by bisection; the run must match it within 1%."""
import math
import os

from fluidbed_tools import reference
from fluidbed_tools import testing as t

d, rho_p, rho_g, mu, g = 1e-3, 2500.0, 1.205, 1.8e-5, 9.81
U = 6.77                                       # superficial inlet velocity of the example
eps = 1 - (math.pi / 6 * d ** 3) / (0.01 ** 3)  # one particle in a 10 mm particle cell


def K(u):  # the seed's blended law divided by (1 - eps), then by eps (Model B)
    return reference.huilin_gidaspow_k(eps, d, u, mu, rho_g) / eps


u_t = reference.terminal_velocity(K, rho_p, rho_g, g)

out, _ = t.run(t.example("coupling/terminal_velocity.opts"), args=["-t_final", 2.5], outdir="terminal_velocity")
tr = t.table(os.path.join(out, "track.csv"))
v = tr["vy"]
u_gas = U / eps  # interstitial gas velocity of the plug flow
slip = u_gas - v[-1]
t.check(abs(v[-1] - v[len(v) * 8 // 10]) < 1e-3 * u_t, "the particle has stopped accelerating (v = %.5f m/s, %.5f m/s at 80%% of the run)" % (v[-1], v[len(v) * 8 // 10]))
t.check(t.rel(slip, u_t) < 0.01, "slip u_gas - v_p = %.4f m/s, terminal velocity of the drag law %.4f m/s, %+.3f%% (limit 1%%)" % (slip, u_t, 100 * (slip / u_t - 1)))
