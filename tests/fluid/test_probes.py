"""The gas pressure probes (-probe_heights, -probe_points) read the pressure field they say they read. On the
lid-driven cavity (examples/fluid/cavity_re100.opts, 16 x 16 cells, 0.2 s: a pressure field that varies in x and y),
the monitor's last row and fluid_cells.csv are written at the same final step, so:
- a height probe equals the layer means of fluid_cells.csv interpolated linearly between layer centres, and
  continued linearly over the outer half layers (a height on a centre, between two centres, on the top wall);
- a point probe equals the pressure of the cell that holds the point;
each to 1e-9 of the field's range, on 1 rank and on 2 ranks (the grid split, so a probe's cell or a layer spans
both ranks' parts)."""
import numpy as np

from fluidbed_tools import testing as t
import gas

L, n = 0.01, 16
h = L / n
heights = [4.5 * h, 5.0 * h, 6.3 * h, L]  # a layer centre, between two centres, part way, the top wall
points = [(1.5e-3, 8.5e-3), (9.5e-3, 9.5e-3), (5.1e-3, 0.2e-3)]


def expected_height(layer_mean, y):
    s = min(max(y / h - 0.5, -0.5), n - 0.5)
    j = 0 if s <= 0 else min(int(np.floor(s)), n - 2)
    w = s - j
    return (1 - w) * layer_mean[j] + w * layer_mean[j + 1]


for ranks in (1, 2):
    args = ["-grid_nx", n, "-grid_ny", n, "-t_final", 0.2, "-monitor_dt", 0.05, "-fluid_output_cells", 1,
            "-probe_heights", ",".join("%.9g" % y for y in heights),
            "-probe_points", ",".join("%.9g,%.9g,0" % p for p in points)]
    out, _ = t.run(t.example("fluid/cavity_re100.opts"), args=args, nprocs=ranks, outdir="probes_%d" % ranks)
    c = gas.cells(out)
    p = c["p"][0]  # (ny, nx)
    scale = np.ptp(p)
    t.check(scale > 0, "%d rank(s): the cavity's pressure varies (range %.3e Pa)" % (ranks, scale))
    m = gas.monitor(out)
    last = {k: v[-1] for k, v in m.items()}
    t.check(abs(last["time"] - 0.2) < 2e-3, "%d rank(s): the monitor's last row at t = %.5f s, the final step" % (ranks, last["time"]))
    layer_mean = p.mean(axis=1)
    names = [k for k in m if k.startswith("p_y")]
    t.check(len(names) == len(heights), "%d rank(s): one monitor column per height (%s)" % (ranks, ", ".join(names)))
    for name, y in zip(names, heights):
        want = expected_height(layer_mean, y)
        t.check(abs(last[name] - want) <= 1e-9 * scale,
                "%d rank(s): %s = %.9e Pa, the layer means interpolated to %.4g mm: %.9e Pa" % (ranks, name, last[name], 1e3 * y, want))
    for q, (x, y) in enumerate(points):
        i, j = min(int(x / h), n - 1), min(int(y / h), n - 1)
        got = last["p_probe%d" % q]
        t.check(abs(got - p[j, i]) <= 1e-9 * scale,
                "%d rank(s): p_probe%d at (%.4g, %.4g) mm = %.9e Pa, cell (%d, %d): %.9e Pa" % (ranks, q, 1e3 * x, 1e3 * y, got, i, j, p[j, i]))
