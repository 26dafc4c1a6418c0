"""A hand-built field: 12 particles at chosen places with chosen velocities (-insert_type list) in a 9 x 9 x 3 mm box
of 3 x 3 x 1 particle cells (3 mm), one sample at t = 0. The test recomputes everything from the seed's formulas
with numpy, independently of the solver's kernels, and compares to 1e-12 relative:
eq. 5.2 solid fraction, eq. 4.3 cell velocity, eq. 3.4 granular temperature (n = 3, divided by N), eq. 3.5
horizontal solid mass flow at two heights, eq. 3.6-3.7 solid circulation (bed = cells with eps_s > 0.01; f_neg and
|v_neg,avg| weighted by solid volume; h_exp from the occupied volume), eq. 3.8 convective and eq. 3.9 diffusive
power (Mdot the magnitude of the cell's mass-flow vector), the expanded bed heights. On 1 and 2 ranks."""
import numpy as np

import analysis_files as af
from fluidbed_tools import testing as t

mm = 1e-3
# (x, y, z) in mm, (vx, vy, vz) in m/s
particles = [
    ((1.0, 1.0, 1.5), (0.1, -0.2, 0.0)), ((2.2, 2.0, 1.5), (0.3, -0.4, 0.05)),  # cell (0, 0)
    ((4.5, 1.2, 1.5), (0.2, 0.1, 0.0)),  # cell (1, 0)
    ((7.0, 4.0, 1.0), (-0.1, 0.5, 0.0)), ((8.0, 5.0, 2.0), (0.1, 0.3, 0.0)), ((7.5, 5.5, 1.0), (-0.3, 0.4, -0.1)),  # cell (2, 1)
    ((4.0, 4.0, 1.5), (0.05, -0.3, 0.0)), ((5.2, 5.0, 1.5), (0.15, -0.1, 0.0)),  # cell (1, 1)
    ((1.5, 7.5, 1.5), (0.0, -0.05, 0.0)),  # cell (0, 2)
    ((1.5, 4.5, 1.5), (0.0, 0.0, 0.0)),  # cell (0, 1)
    ((7.5, 7.0, 1.5), (-0.2, 0.0, 0.1)), ((7.0, 8.2, 1.5), (0.2, -0.6, 0.0)),  # cell (2, 2)
]
rho, d = 2500.0, 1e-3
L = np.array([9, 9, 3]) * mm
n = np.array([3, 3, 1])
h = L / n
vp, vc = np.pi / 6 * d**3, np.prod(h)
area = np.array([h[1] * h[2], h[0] * h[2], h[0] * h[1]])  # face areas normal to x, y, z
heights = [1.5 * mm, 4.5 * mm]

# ---- by hand ----
cells = {}
for x, v in particles:
    c = tuple(int(np.floor(x[a] * mm / h[a])) for a in range(3))
    cells.setdefault(c, []).append(np.array(v))
eps = np.zeros(n)
vel = np.zeros(tuple(n) + (3,))
theta = np.zeros(n)
for c, vs in cells.items():
    vs = np.array(vs)
    eps[c] = len(vs) * vp / vc  # eq. 5.2
    vel[c] = vs.mean(axis=0)  # eq. 4.3
    if len(vs) >= 2:
        theta[c] = np.mean(np.sum((vs - vs.mean(axis=0)) ** 2, axis=1)) / 3  # eq. 3.4
mdot = rho * eps[..., None] * area * vel  # eq. 3.5 in every direction, kg/s
profiles = [mdot[:, int(y // h[1]), :, 0].sum(axis=1) for y in heights]  # columns of the layer, summed over z
occupied = eps > 0.01
A_d = L[0] * L[2]
h_exp = np.count_nonzero(occupied) * vc / A_d
m_bed = len(particles) * rho * vp
eps_b = m_bed / (rho * h_exp * A_d)  # eq. 3.7
vs_cell = eps * vc
down = occupied & (vel[..., 1] < 0)
f_neg = vs_cell[down].sum() / vs_cell[occupied].sum()
v_neg = (vs_cell[down] * -vel[..., 1][down]).sum() / vs_cell[down].sum()
circulation = rho * eps_b * f_neg * v_neg * A_d  # eq. 3.6
p_conv = np.sum(np.abs(mdot) * vel**2)  # eq. 3.8
p_diff = np.sum(np.sqrt(np.sum(mdot**2, axis=-1)) * theta)  # eq. 3.9
layer = eps.mean(axis=(0, 2))
print("by hand: eps_s per layer %s, h_exp %.3f mm, eps_b %.4f, f_neg %.4f, |v_neg| %.4f m/s, circulation %.4e kg/s, P_c %.4e W, P_d %.4e W"
      % (np.round(layer, 4), h_exp / mm, eps_b, f_neg, v_neg, circulation, p_conv, p_diff))

pos = ",".join("%g,%g,%g" % tuple(np.array(x) * mm) for x, _ in particles)
vel_opt = ",".join("%g,%g,%g" % v for _, v in particles)
args = ["-domain_lx", L[0], "-domain_ly", L[1], "-domain_lz", L[2], "-grid_nx", 3, "-grid_ny", 3, "-grid_nz", 1, "-pgrid_ratio", 1,
        "-particle_diameter", d, "-particle_density", rho, "-gravity", "0,0,0", "-insert_type", "list", "-insert_positions", pos,
        "-insert_velocities", vel_opt, "-max_steps", 1, "-average", "-average_interval", 1.0,
        "-average_heights", ",".join(str(y) for y in heights)]


def close(a, b, what, ranks):
    err = np.max(np.abs(np.asarray(a) - np.asarray(b))) / max(np.max(np.abs(b)), 1e-300)
    t.check(err <= 1e-12, "%d rank(s): %s as by hand (largest relative difference %.1e)" % (ranks, what, err))


for ranks in (1, 2):
    out, _ = t.run(None, args=args, nprocs=ranks, outdir="known_%d" % ranks)
    a = af.read(out)
    t.check(int(a["measures/samples"][0]) == 1, "%d rank(s): one sample (t = 0)" % ranks)
    close(af.cells_xyz(a["fields/solid_fraction"]), eps, "solid fraction (eq. 5.2)", ranks)
    close(np.transpose(a["fields/velocity"], (2, 1, 0, 3)), vel, "cell velocity (eq. 4.3)", ranks)
    close(af.cells_xyz(a["fields/granular_temperature"]), theta, "granular temperature (eq. 3.4)", ranks)
    close(a["profiles/mass_flow_x"], np.array(profiles), "horizontal solid mass flow at 1.5 and 4.5 mm (eq. 3.5) %s kg/s"
          % np.array2string(np.array(profiles), precision=3), ranks)
    for name, value in (("expanded_bed_height_volume", h_exp), ("bulk_solid_fraction", eps_b), ("fraction_moving_down", f_neg),
                        ("mean_downward_speed", v_neg), ("solid_circulation", circulation), ("convective_power", p_conv),
                        ("diffusive_power", p_diff), ("bed_mass", m_bed)):
        got = af.measure(a, name)
        t.check(abs(got - value) <= 1e-12 * abs(value), "%d rank(s): %s %.12e, by hand %.12e" % (ranks, name, got, value))
    close(a["cross_section/solid_fraction"], layer, "cross-section solid fraction", ranks)
    close(af.cells_xyz(a["fields/convective_power"]), np.sum(np.abs(mdot) * vel**2, axis=-1), "per-cell convective power", ranks)
