"""Verification 2: lid-driven cavity at Re = 100 (examples/fluid/cavity_re100.opts on a 32 x 32 grid) against
Ghia, Ghia & Shin (1982), tests/data/ghia1982_re100.csv. Every tabulated centre-line velocity within 2% of the lid
velocity, and the extremes (u_min, v_max, v_min) within 2% of Ghia's values. After every projection the largest
|div u| stays below the KSP tolerance times U/h."""
import numpy as np

from fluidbed_tools import testing as t
import gas

L, U, n = 0.01, 0.149378, 32
out, _ = t.run(t.example("fluid/cavity_re100.opts"), args=["-grid_nx", n, "-grid_ny", n, "-monitor_dt", 0.002], outdir="cavity_%d" % n)
c = gas.cells(out)
ref = gas.ghia()
Re = 1.205 * U * L / 1.8e-5
print("Re = %.3f" % Re)

# u on the vertical centre line: the x-faces at x = L/2 (face n/2), at the cell centres in y; walls at both ends
y = np.concatenate([[0.0], (np.arange(n) + 0.5) / n, [1.0]])
u = np.concatenate([[0.0], c["ufx"][0, :, n // 2] / U, [1.0]])
x = np.concatenate([[0.0], (np.arange(n) + 0.5) / n, [1.0]])
v = np.concatenate([[0.0], c["ufy"][0, n // 2, :] / U, [0.0]])
du = np.interp(ref["u"][0], y, u) - ref["u"][1]
dv = np.interp(ref["v"][0], x, v) - ref["v"][1]
for (p, r), d in zip(zip(*ref["u"]), du):
    print("  u(y = %.4f) = %+.5f  Ghia %+.5f  diff %+.4f U" % (p, r + d, r, d))
for (p, r), d in zip(zip(*ref["v"]), dv):
    print("  v(x = %.4f) = %+.5f  Ghia %+.5f  diff %+.4f U" % (p, r + d, r, d))
t.check(np.max(np.abs(du)) < 0.02, "u on x = L/2: largest difference from Ghia %.4f U (limit 0.02 U)" % np.max(np.abs(du)))
t.check(np.max(np.abs(dv)) < 0.02, "v on y = L/2: largest difference from Ghia %.4f U (limit 0.02 U)" % np.max(np.abs(dv)))
for name, mine, theirs in (("u_min", np.interp(0.4531, y, u), -0.21090), ("v_max", np.interp(0.2344, x, v), 0.17527),
                           ("v_min", np.interp(0.8047, x, v), -0.24533)):
    t.check(t.rel(mine, theirs) < 0.02, "%s = %.5f, Ghia %.5f: %.2f%% (limit 2%%)" % (name, mine, theirs, 100 * t.rel(mine, theirs)))

mon = gas.monitor(out)
s = t.summary(out)["fluid"]
h = L / n
rtol = 1e-8  # the pressure KSP's default relative tolerance
worst = np.max(mon["max_div"][1:] / (rtol * np.maximum(mon["gas_max_speed"][1:], U) / h))
t.check(worst < 1.0, "%d monitor rows: max |div u| / (rtol U / h) at most %.2e (limit 1)" % (len(mon["max_div"]) - 1, worst))
rel_change = abs(mon["gas_max_speed"][-1] - mon["gas_max_speed"][-11]) / mon["gas_max_speed"][-1]
t.check(rel_change < 1e-4, "steady: the largest speed changed by %.1e over the last 0.02 s" % rel_change)
print("pressure: %.1f iterations and %.3g ms per solve (%s + %s)" % (s["pressure_iterations_per_solve"], 1e3 * s["pressure_time_per_solve"], s["ksp_type"], s["pc_type"]))
