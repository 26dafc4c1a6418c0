"""analysis.h5 and analysis.xmf: the XDMF parses, every DataItem names a dataset of analysis.h5 with the shape it
declares, and the fields have the particle grid's shape in natural order ((nz,) ny, nx[, dim]); every dataset
carries "units" and "description" attributes; profiles, cross-section and series have their documented shapes;
the gas series (pressure drop, jet heights) appear exactly when the gas is on. Cases: a coupled 3D bed with two
jets on 1 rank, the gas alone with a jet in 2D on 2 ranks, a DEM-only 2D bed on 1 rank, a DEM-only 3D bed on 4
ranks. -average_output_interval writes
analysis.h5 during the run (counted through the AvgWrite event of -log_view)."""
import os
import xml.etree.ElementTree as ET

import h5py
import numpy as np

import analysis_files as af
from fluidbed_tools import testing as t

gas_2d = ["-particles", 0, "-fluid", "-domain_dim", 2, "-domain_lx", 0.02, "-domain_ly", 0.04, "-domain_lz", 0.005, "-grid_nx", 10,
          "-grid_ny", 20, "-inlet_jets", "0.01,0.004,2", "-fluid_bc_yhi", "outlet", "-t_final", 0.004, "-average", "-average_interval", 1e-3]
cases = [  # (label, options file, args, ranks, dim, jets, gas)
    ("coupled 3D, 2 jets", t.example("coupling/small_bed.opts"),
     ["-inlet_velocity", 0.1, "-inlet_jets", "0.005,0.0033333333,4,0.015,0.0033333333,4", "-couple_substeps", 5, "-t_final", 0.006,
      "-average", "-average_interval", 1e-3, "-average_heights", "0.002,0.01,0.03"], 1, 3, 2, True),
    ("gas only 2D, 1 jet", None, gas_2d, 2, 2, 1, True),
    ("DEM 2D", None, ["-domain_dim", 2, "-domain_lz", 1e-3, "-insert_count", 200, "-t_final", 0.01, "-average_start", 0.002,
                      "-average_interval", 1e-3, "-average_heights", "0.005"], 1, 2, 0, False),
    ("DEM 3D", None, ["-insert_count", 500, "-t_final", 0.005, "-average", "-average_interval", 1e-3], 4, 3, 0, False),
]
for label, opts, args, ranks, dim, jets, gas in cases:
    out, _ = t.run(opts, args=args, nprocs=ranks, outdir="files_%d_%dd_%s" % (ranks, dim, "gas" if gas else "dem"))
    root = ET.parse(os.path.join(out, "analysis.xmf")).getroot()
    grid = root.find("./Domain/Grid")
    topo = grid.find("Topology")
    nodes = [int(s) for s in topo.get("Dimensions").split()]
    # 2D: a 2DSMesh with its node coordinates, which ParaView lays in the x-y plane with the particles
    t.check(topo.get("TopologyType") == ("3DCoRectMesh" if dim == 3 else "2DSMesh") and len(nodes) == dim,
            "%s: %s of %s nodes" % (label, topo.get("TopologyType"), nodes))
    a = af.read(out)
    nc = a["grid/cells"].astype(int)
    cells = tuple(int(c) for c in nc[:dim][::-1])  # XDMF and HDF5 order: (z,) y, x
    t.check(tuple(n - 1 for n in nodes) == cells, "%s: the XDMF mesh has the particle grid's %s cells" % (label, cells))
    items, names = 0, []
    with h5py.File(os.path.join(out, "analysis.h5"), "r") as f:
        for att in grid.findall("Attribute"):
            names.append(att.get("Name"))
            for item in att.iter("DataItem"):
                if item.get("Format") != "HDF":
                    continue
                fname, dset = item.text.strip().split(":")
                shape = tuple(int(s) for s in item.get("Dimensions").split())
                if fname != "analysis.h5" or dset not in f or f[dset].shape != shape:
                    t.fail("%s: %s:%s is missing or shaped %s, the XDMF says %s" % (label, fname, dset, f[dset].shape if dset in f else None, shape))
                if shape[:dim] != cells:
                    t.fail("%s: %s has shape %s, not the grid's %s" % (label, dset, shape, cells))
                items += 1
        t.check(items >= 8, "%s: %d DataItems resolve to datasets of the declared shape (%s)" % (label, items, ", ".join(names)))
        missing = []
        f.visititems(lambda name, obj: missing.append(name) if isinstance(obj, h5py.Dataset) and not ("units" in obj.attrs and "description" in obj.attrs) else None)
        t.check(not missing, "%s: all %d datasets carry units and description%s" % (label, len(a), " (missing: %s)" % missing if missing else ""))
        t.check(f["fields/velocity"].shape == cells + (dim,) and f["fields/solid_fraction"].shape == cells,
                "%s: velocity %s, solid fraction %s" % (label, f["fields/velocity"].shape, f["fields/solid_fraction"].shape))
    vectors = {att.get("Name"): att.find("DataItem").get("Dimensions") for att in grid.findall("Attribute") if att.get("AttributeType") == "Vector"}
    t.check(set(vectors) == {"velocity", "solid_flux"} and all(d.split()[-1] == str(dim) for d in vectors.values()),
            "%s: velocity and solid flux are vectors of %d components: %s" % (label, dim, vectors))
    ns, nx, ny = len(a["series/time"]), nc[0], nc[1]
    nh = len(a.get("profiles/heights", []))
    t.check(ns == int(af.measure(a, "samples")) and a["cross_section/solid_fraction"].shape == (ny,),
            "%s: %d samples in the series, cross-section of %d layers" % (label, ns, ny))
    if nh:
        t.check(all(a["profiles/" + k].shape == (nh, nx) for k in ("solid_fraction", "velocity_y", "granular_temperature", "mass_flow_x")),
                "%s: profiles at %d heights of %d columns" % (label, nh, nx))
    t.check(("series/pressure_drop" in a) == gas and ("series/jet_height" in a) == (jets > 0) and ("measures/pressure_drop" in a) == gas,
            "%s: gas series %s" % (label, "present" if gas else "absent"))
    if jets:
        jh = a["series/jet_height"]
        t.check(jh.shape == (ns, jets) and np.isnan(jh[0]).all() and np.isfinite(jh[1:]).all() and np.isnan(a["series/pressure_drop"][0]),
                "%s: jet heights %s per sample and jet, NaN at t = 0 before the first gas step, then finite" % (label, jh.shape))
        t.check(a["jets/slots"].shape == (jets, 2), "%s: jet slots %s m" % (label, np.round(a["jets/slots"], 6).tolist()))
    s = t.summary(out)["averages"]
    t.check(s["samples"] == ns and ("pressure_drop_mean_Pa" in s) == gas and ("jet_penetration_height_m" in s) == (jets > 0),
            "%s: summary.json averages with %d keys" % (label, len(s)))

# intermediate writes: 4 during the run (every 2 ms from t = 2 ms) and the final one
_, p = t.run(None, args=["-insert_count", 300, "-t_final", 0.008, "-average", "-average_interval", 1e-3, "-average_output_interval", 2e-3,
                         "-log_view"], outdir="files_interval")
line = next((l for l in p.stdout.splitlines() if l.startswith("AvgWrite")), "")
count = int(line.split()[1]) if line else -1
t.check(count == 5, "-average_output_interval 2 ms over 8 ms: analysis.h5 written %d times (4 during the run, 1 at the end)" % count)
