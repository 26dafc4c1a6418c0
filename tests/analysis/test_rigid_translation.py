"""A rigid-body translation: every particle moves with the same velocity U (no gravity, a lattice with gaps, so no
contacts, and far enough from the walls that none is reached in the run). Sampled as the particles cross cells:
the granular temperature (eq. 3.4) is zero to round-off (the kernel's one-pass formula leaves about 1e-16 |U|^2;
the limit is 1e-13 |U|^2) in every cell where it is defined, the mean velocity (eq. 4.3) is U in every cell that
saw particles (1e-12 relative), the mean solid flux is <eps_s> U, and the whole-bed measures follow by hand:
P_c = rho_p N V_p sum_i |U_i|^3 / h_i (eq. 3.8, since sum <eps_s> over cells is N V_p / V_cell), P_d = 0 (eq. 3.9),
and with U_y < 0 the whole bed moves down: f_neg = 1, |v_neg| = |U_y| (eq. 3.6). On 1 and 2 ranks."""
import numpy as np

import analysis_files as af
from fluidbed_tools import testing as t

U = np.array([0.3, -0.2, 0.1])
rho, d, n = 2500.0, 1e-3, 400
vp = np.pi / 6 * d**3
# the lattice fills x, z in [4, 16] mm and y in [8, 32] mm of the 20 x 40 x 20 mm box; in 3 ms the particles move
# 0.9, 0.6, 0.3 mm, so none reaches a wall
args = ["-insert_type", "lattice", "-insert_count", n, "-insert_spacing", 2, "-insert_region", "0.004,0.016,0.008,0.032,0.004,0.016",
        "-insert_velocity", ",".join(map(str, U)), "-gravity", "0,0,0", "-t_final", 0.003, "-average", "-average_interval", 2e-4,
        "-pgrid_cell_diameters", 3]
for ranks in (1, 2):
    out, _ = t.run(None, args=args, nprocs=ranks, outdir="rigid_%d" % ranks)
    a = af.read(out)
    lo, h, nc = af.grid(a)
    samples = int(a["measures/samples"][0])
    sf = a["fields/solid_fraction"]
    theta, cover, v, flux = a["fields/granular_temperature"], a["fields/temperature_coverage"], a["fields/velocity"], a["fields/solid_flux"]
    seen = sf > 0
    t.check(samples == 16, "%d rank(s): %d samples over 3 ms" % (ranks, samples))
    t.check(np.count_nonzero(cover > 0) >= 20, "%d rank(s): %d cells had the granular temperature defined (2 or more particles)"
            % (ranks, np.count_nonzero(cover > 0)))
    worst = np.max(np.abs(theta)) / np.dot(U, U)
    t.check(worst <= 1e-13, "%d rank(s): granular temperature at most %.1e |U|^2 (limit 1e-13)" % (ranks, worst))
    dv = np.max(np.abs(v[seen] - U)) / np.linalg.norm(U)
    t.check(dv <= 1e-12, "%d rank(s): mean velocity = U in all %d cells that saw particles (largest deviation %.1e |U|)"
            % (ranks, np.count_nonzero(seen), dv))
    t.check(np.all(v[~seen] == 0), "%d rank(s): velocity 0 in the %d cells no particle reached" % (ranks, np.count_nonzero(~seen)))
    df = np.max(np.abs(flux - sf[..., None] * U)) / (sf.max() * np.linalg.norm(U))
    t.check(df <= 1e-12, "%d rank(s): mean solid flux = <eps_s> U (largest deviation %.1e)" % (ranks, df))
    pc = af.measure(a, "convective_power")
    pc_hand = rho * n * vp * np.sum(np.abs(U) ** 3 / h)
    t.check(abs(pc - pc_hand) <= 1e-12 * pc_hand, "%d rank(s): convective power %.12e W, by hand %.12e W" % (ranks, pc, pc_hand))
    pd = af.measure(a, "diffusive_power")
    t.check(abs(pd) <= 1e-12 * pc_hand, "%d rank(s): diffusive power %.1e W (zero to round-off)" % (ranks, pd))
    f_neg, v_neg = af.measure(a, "fraction_moving_down"), af.measure(a, "mean_downward_speed")
    t.check(f_neg == 1.0 and abs(v_neg - abs(U[1])) <= 1e-12 * abs(U[1]), "%d rank(s): f_neg %.15g, |v_neg| %.15g m/s = |U_y|" % (ranks, f_neg, v_neg))
    # eq. 3.6-3.7 by hand: h_exp from the occupied cells, m_bed = N m_p, A_d the box's cross-section
    A_d = 0.02 * 0.02
    h_exp = np.count_nonzero(sf > 0.01) * np.prod(h) / A_d
    eps_b = n * rho * vp / (rho * h_exp * A_d)
    mdot = rho * eps_b * 1.0 * abs(U[1]) * A_d
    circ = af.measure(a, "solid_circulation")
    t.check(abs(circ - mdot) <= 1e-12 * mdot, "%d rank(s): circulation %.12e kg/s, by hand %.12e kg/s (h_exp %.4g mm)"
            % (ranks, circ, mdot, 1e3 * h_exp))
