"""The analysis of scripts/umf_sweep.py (U_mf from a pressure-drop sweep) on inputs with known answers, no runs:

- Ergun's U_mf for a voidage carries the bed's buoyant weight: Ergun's gradient at that velocity equals
  (1 - eps)(rho_p - rho_g) g to 1e-12 relative;
- a noise-free sweep (pressure drop = H Ergun(eps, U) up to U_mf, the bed weight above) gives back Ergun's U_mf to
  1e-9 relative (the fit's form a U + b U^2 is Ergun's);
- the exact sphere volume in a slab: a whole sphere, half a sphere, a cap of height r/2 (5 pi r^3 / 24);
- the voidage of a simple cubic packing, 1 - pi / 6, in the bulk within 1e-3, and the bed height is the top layer's."""
import math

import numpy as np

from fluidbed_tools import testing as t
import umf_sweep as us

for eps in (0.36, 0.41, 0.45, 0.5):
    u = us.ergun_umf(eps)
    weight = (1 - eps) * (us.RHO_P - us.RHO_G) * us.G
    t.check(t.rel(us.ergun_gradient(eps, u), weight) < 1e-12,
            "voidage %.2f: Ergun U_mf %.4f m/s carries the buoyant weight (%.1f Pa/m)" % (eps, u, weight))

eps, H = 0.41, 0.024
umf = us.ergun_umf(eps)
plateau = H * (1 - eps) * (us.RHO_P - us.RHO_G) * us.G
velocities = np.array([0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.5, 0.6, 0.7])
dp = np.minimum(H * us.ergun_gradient(eps, velocities), plateau)
found, found_plateau, a, b = us.umf_from_curve(velocities, dp, 0.5)
t.check(t.rel(found, umf) < 1e-9 and t.rel(found_plateau, plateau) < 1e-12,
        "noise-free sweep: U_mf %.6f m/s from the curve, Ergun %.6f m/s; plateau %.3f Pa" % (found, umf, found_plateau))

r = 1e-3
whole = us.sphere_volume_in_slab(np.array([0.0]), np.array([2 * r]), -1.0, 1.0)[0]
half = us.sphere_volume_in_slab(np.array([0.0]), np.array([2 * r]), 0.0, 1.0)[0]
cap = us.sphere_volume_in_slab(np.array([0.0]), np.array([2 * r]), 0.5 * r, 1.0)[0]
t.check(t.rel(whole, 4 / 3 * math.pi * r ** 3) < 1e-12 and t.rel(half, 2 / 3 * math.pi * r ** 3) < 1e-12 and t.rel(cap, 5 * math.pi * r ** 3 / 24) < 1e-12,
        "sphere volume in a slab: whole, half and a cap of height r/2 exact")

d = 1.2e-3
n = (16, 20, 8)  # a simple cubic packing 16 x 20 x 8 spheres in a box of exactly that many diameters
g = np.meshgrid(*[(np.arange(k) + 0.5) * d for k in n], indexing="ij")
cubic = {"x": g[0].ravel(), "y": g[1].ravel(), "z": g[2].ravel(), "d": np.full(g[0].size, d)}
bulk, mean, height = us.packed_voidage(cubic, n[0] * d, n[2] * d, columns=4)
t.check(abs(bulk - (1 - math.pi / 6)) < 1e-3 and t.rel(height, n[1] * d) < 1e-12 and abs(mean - (1 - math.pi / 6)) < 1e-12,
        "simple cubic packing: bulk voidage %.5f, mean %.5f (1 - pi/6 = %.5f), height %.2f mm" % (bulk, mean, 1 - math.pi / 6, 1e3 * height))

# layer by layer: six equally filled layers below empty ones give the single-voidage Ergun U_mf of that voidage;
# a loose layer on top of them lowers the packed pressure drop per unit weight and so raises U_mf
per_layer = 400
ys = np.repeat((np.arange(6) + 0.5) * us.LAYER, per_layer)
uniform = {"y": ys, "d": np.full(ys.size, d)}
found, eps_layers = us.layered_ergun_umf(uniform, us.LX, us.LZ)
eps6 = 1 - per_layer * math.pi / 6 * d ** 3 / (us.LX * us.LZ * us.LAYER)
t.check(t.rel(found, us.ergun_umf(eps6)) < 1e-9 and np.all(eps_layers[6:] == 1.0),
        "six uniform layers of voidage %.4f: U_mf %.6f m/s layer by layer, %.6f m/s from the single voidage" % (eps6, found, us.ergun_umf(eps6)))
loose = {"y": np.concatenate([ys, np.full(40, 6.5 * us.LAYER)]), "d": np.full(ys.size + 40, d)}
t.check(us.layered_ergun_umf(loose, us.LX, us.LZ)[0] > found, "a loose top layer raises the layered U_mf (%.4f > %.4f m/s)"
        % (us.layered_ergun_umf(loose, us.LX, us.LZ)[0], found))
