"""Verification 3: mass conservation of the projection with a jet inlet (the seed's bed, examples/fluid/
jet_empty_bed.opts, on coarse grids). After every projection the largest |div(eps u)| in any cell is below the
pressure KSP's relative tolerance times U/h (U the largest gas speed, h the smallest cell); with the seed's
uniform outlet the outflow equals the inflow to round-off, with a pressure outlet (p = 0) to the solver tolerance.
The limited convection stays bounded where 45.3 m/s gas meets still gas: a step of tangential velocity carried
at 45.3 m/s keeps every value between 0 and 45.3 m/s (to round-off). With -inlet_ramp_time the inflow follows the
linear ramp exactly and the outflow with it."""
import numpy as np

from fluidbed_tools import testing as t
import gas

V_JET, RTOL = 45.3, 1e-8
lx, ly, lz = 0.0564, 0.280, 0.00495


def check_divergence(label, out, h_min, first_row=1):
    mon = gas.monitor(out)
    rows = slice(first_row, None)  # row 0 is the initial state
    ratio = mon["max_div"][rows] / (RTOL * mon["gas_max_speed"][rows] / h_min)
    t.check(np.max(ratio) < 1.0, "%s: %d projections, max |div(eps u)| / (rtol U / h) at most %.2e (limit 1)" % (label, len(ratio), np.max(ratio)))
    return mon


# 2D, 35 x 50 cells (1.611 x 5.6 mm), one 1-cell slit, the seed's uniform outlet
args2d = ["-domain_dim", 2, "-grid_nx", 35, "-grid_ny", 50, "-inlet_jets", "0.0282,0.00161142857,%g" % V_JET, "-t_final", 0.01, "-monitor_dt", 0]
out, _ = t.run(t.example("fluid/jet_empty_bed.opts"), args=args2d, outdir="jet_2d")
mon = check_divergence("2D jet, uniform outlet", out, lx / 35)
q = V_JET * (lx / 35) * lz
imbalance = np.max(np.abs(mon["inflow"] - mon["outflow"])) / q
t.check(imbalance < 1e-13, "2D jet: inflow %.10e m^3/s (slit: %.10e), |inflow - outflow| / inflow at most %.1e (limit 1e-13)"
        % (mon["inflow"][-1], q, imbalance))
t.check(abs(mon["inflow"][-1] - q) < 1e-13 * q, "2D jet: the inflow is the slit's")
c = gas.cells(out)
bottom = c["ufy"][0, 0, :]
t.check(abs(bottom[17] - V_JET) < 1e-12 and np.max(np.abs(np.delete(bottom, 17))) == 0.0,
        "2D jet: the slit cell blows %.4f m/s, the rest of the bottom is a wall" % bottom[17])
print("2D jet: largest gas speed %.2f m/s at t = %.3g s" % (mon["gas_max_speed"][-1], mon["time"][-1]))

# -inlet_ramp_time: the same jet grows linearly over 4 ms; after every projection the inflow is the slit's times
# t / 4 ms (then 1), the outflow equals it, and the projection still conserves mass
T_RAMP = 0.004
out, _ = t.run(t.example("fluid/jet_empty_bed.opts"), args=args2d[:-4] + ["-t_final", 0.006, "-monitor_dt", 0, "-inlet_ramp_time", T_RAMP],
               outdir="jet_2d_ramp")
# (the monitor's gas speed is the step's starting one: 0 for the first step of a ramp, so the check starts a row later)
mon = check_divergence("2D jet ramped over 4 ms", out, lx / 35, first_row=2)
rows = slice(1, None)
expected = q * np.minimum(1.0, mon["time"][rows] / T_RAMP)
err = np.max(np.abs(mon["inflow"][rows] - expected)) / q
# limit: monitor.csv prints the time to 11 significant digits (relative 5e-11)
t.check(err < 1e-10 and mon["time"][-1] > T_RAMP,
        "ramped jet: inflow = slit x min(1, t / 4 ms) at all %d steps within %.1e of the slit's inflow (limit 1e-10)" % (len(expected), err))
imbalance = np.max(np.abs(mon["inflow"] - mon["outflow"])) / q
t.check(imbalance < 1e-13, "ramped jet: |inflow - outflow| / slit inflow at most %.1e (limit 1e-13)" % imbalance)
t.check(np.max(mon["gas_courant"]) <= 1.0, "ramped jet: the steps chosen while the inflow grows keep the gas Courant number at most %.3f "
        "(limit 1)" % np.max(mon["gas_courant"]))

# 3D, 35 x 50 x 5 cells, pressure outlet (p = 0 at the top): outflow follows the projection
args3d = ["-grid_nx", 35, "-grid_ny", 50, "-grid_nz", 5, "-inlet_jets", "0.0282,0.00161142857,%g" % V_JET, "-fluid_bc_yhi", "pressure", "-t_final", 0.005,
          "-monitor_dt", 0, "-fluid_output_cells", 0]
out, _ = t.run(t.example("fluid/jet_empty_bed.opts"), args=args3d, outdir="jet_3d_pressure_outlet")
mon = check_divergence("3D jet, pressure outlet", out, lx / 35)
imbalance = np.max(np.abs(mon["inflow"][1:] - mon["outflow"][1:])) / (V_JET * (lx / 35) * lz)
t.check(imbalance < 1e-6, "3D jet, pressure outlet: |inflow - outflow| / inflow at most %.1e (limit 1e-6)" % imbalance)

# boundedness: gas rising at 45.3 m/s brings in 45.3 m/s of tangential velocity (the bottom's) into still gas
out, _ = t.run(args=["-particles", 0, "-fluid", "-domain_dim", 2, "-domain_lx", 0.004, "-domain_ly", 0.04, "-domain_lz", 0.004, "-domain_periodic_x",
                     "-gravity", "0,0,0", "-grid_nx", 4, "-grid_ny", 80, "-inlet_velocity", V_JET, "-fluid_initial_velocity", "0,%g,0" % V_JET,
                     "-fluid_bc_ylo_velocity", "%g,0,0" % V_JET, "-fluid_bc_yhi", "outlet", "-t_final", 0.0004], outdir="jet_step")
c = gas.cells(out)
u = c["ufx"][0, :, 0]
front = np.interp(0.5 * V_JET, u[::-1], c["y"][0, ::-1, 0])
t.check(u.min() > -1e-10 * V_JET and u.max() < V_JET * (1 + 1e-10),
        "step carried at %.1f m/s: tangential velocity within [%.2e, %.6f] m/s (bounds 0, %.1f)" % (V_JET, u.min(), u.max(), V_JET))
t.check(abs(front - V_JET * 0.0004) < 2 * 0.0005, "the step's middle is at y = %.2f mm after 0.4 ms (carried: %.2f mm)" % (1e3 * front, 1e3 * V_JET * 0.0004))
