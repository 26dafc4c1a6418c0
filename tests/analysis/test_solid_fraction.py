"""Time-averaged solid fraction of a uniform random packing (no gravity, particles at rest, a few steps): every
particle counts whole in the cell of its centre (eq. 5.2), so the mean over the cells is N V_p / V_box exactly, and
each cell lies within sampling error of its expected value. random_fill puts centres uniformly in the box shrunk
by a radius, so a cell expects N x (its share of that shrunk box) particles, and with the Poisson estimate
sigma = sqrt(expected count) V_p / V_cell (conservative: a non-overlapping fill is sub-Poisson) every cell must lie
within 4 sigma and the rms over cells below 1.3 sigma. 3D on 1 and 2 ranks (the two agree), 2D one particle deep
(depth -domain_lz enters the cell volume)."""
import numpy as np

import analysis_files as af
from fluidbed_tools import testing as t

d = 1e-3
vp = np.pi / 6 * d**3
cases = [  # (label, dim, count, extra options, ranks); the box is the default 20 x 40 x 20 mm, in 2D 1 mm deep
    ("3D", 3, 4000, [], 1),
    ("3D", 3, 4000, [], 2),
    ("2D", 2, 300, ["-domain_dim", 2, "-domain_lz", 1e-3], 1),
]
fields = {}
for label, dim, n, extra, ranks in cases:
    args = ["-insert_type", "random", "-insert_count", n, "-insert_seed", 11, "-gravity", "0,0,0", "-pgrid_cell_diameters", 5,
            "-max_steps", 3, "-average", "-average_interval", 1e-6] + extra
    out, _ = t.run(None, args=args, nprocs=ranks, outdir="sf_%s_%d" % (label, ranks))
    a = af.read(out)
    s = t.summary(out)["averages"]
    lo, h, nc = af.grid(a)
    L = np.array([0.02, 0.04, 0.02 if dim == 3 else 1e-3])
    t.check(np.allclose(h * nc, L, rtol=1e-14, atol=0), "%s: grid spacing x cells = the box %s m (depth in 2D)" % (label, L))
    phi = n * vp / np.prod(L)
    sf = af.cells_xyz(a["fields/solid_fraction"])
    t.check(sf.shape == tuple(nc), "%s, %d rank(s): field of %s cells" % (label, ranks, "x".join(map(str, nc))))
    t.check(int(a["measures/samples"][0]) == 4 and s["samples"] == 4, "%s: 4 samples (t = 0 and 3 steps)" % label)
    t.check(abs(sf.mean() - phi) <= 1e-12 * phi, "%s: mean over cells %.15f = N V_p / V_box %.15f" % (label, sf.mean(), phi))
    # expected count per cell: N times the cell's share of the box of allowed centres [lo + r, hi - r]
    share = []
    for ax in range(3):
        edges = lo[ax] + h[ax] * np.arange(nc[ax] + 1)
        if ax < dim:
            a0, a1 = lo[ax] + d / 2, lo[ax] + L[ax] - d / 2
            share.append(np.clip(np.minimum(edges[1:], a1) - np.maximum(edges[:-1], a0), 0, None) / (a1 - a0))
        else:
            share.append(np.ones(1))
    expect_n = n * share[0][:, None, None] * share[1][None, :, None] * share[2][None, None, :]
    vcell = np.prod(h)
    expect = expect_n * vp / vcell
    sigma = np.sqrt(expect_n) * vp / vcell
    z = (sf - expect) / sigma
    worst, rms = np.max(np.abs(z)), np.sqrt(np.mean(z**2))
    t.check(worst <= 4.0, "%s: largest deviation %.2f sigma (limit 4; %.1f particles per cell expected, sigma %.0f%%)"
            % (label, worst, expect_n.mean(), 100 / np.sqrt(expect_n.mean())))
    t.check(rms <= 1.3, "%s: rms deviation %.2f sigma (limit 1.3)" % (label, rms))
    # every cell holds particles: the expanded-volume height is the box, the bulk solid fraction is phi
    # (analysis.h5 holds the measures in full precision, summary.json with 10 significant digits)
    h_vol, bulk, mass = (af.measure(a, k) for k in ("expanded_bed_height_volume", "bulk_solid_fraction", "bed_mass"))
    t.check(abs(h_vol - L[1]) <= 1e-12 * L[1], "%s: expanded-volume height %.6g m = the box" % (label, h_vol))
    t.check(abs(bulk - phi) <= 1e-12 * phi, "%s: bulk solid fraction (eq. 3.7) %.15f = phi" % (label, bulk))
    t.check(abs(mass - n * 2500 * vp) <= 1e-12 * n * 2500 * vp, "%s: bed mass %.12g kg = N m_p" % (label, mass))
    t.check(all(abs(s[k] - v) <= 5e-10 * abs(v) for k, v in (("bulk_solid_fraction", bulk), ("bed_mass_kg", mass))),
            "%s: summary.json carries the same values" % label)
    t.check(np.all(a["fields/velocity"] == 0) and np.all(a["fields/granular_temperature"] == 0), "%s: particles at rest: v = 0, theta = 0" % label)
    fields[(label, ranks)] = sf

diff = np.max(np.abs(fields[("3D", 1)] - fields[("3D", 2)]))
t.check(diff <= 1e-15, "3D: 1 and 2 ranks give the same field (largest difference %.1e)" % diff)
