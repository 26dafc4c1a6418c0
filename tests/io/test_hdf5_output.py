"""ParaView-readable output: particles.xmf parses as XML and every DataItem points at a dataset that exists in its
HDF5 file with the shape the XDMF states; times increase; the datasets hold the run's particles."""
import os
import xml.etree.ElementTree as ET

import h5py
import numpy as np

from fluidbed_tools import testing as t

for n, dim in ((1, 3), (2, 3), (2, 2)):
    args = ["-t_final", 0.01, "-insert_count", 300, "-output_interval", 0.0025]
    if dim == 2:
        args += ["-domain_dim", 2, "-domain_lz", 1e-3, "-insert_count", 200]
    out, _ = t.run(None, args=args, nprocs=n, outdir="h5_%d_%dd" % (n, dim))
    root = ET.parse(os.path.join(out, "particles.xmf")).getroot()
    grids = root.findall("./Domain/Grid/Grid")
    times = [float(g.find("Time").get("Value")) for g in grids]
    t.check(len(grids) == 5 and times == sorted(times), "%d rank(s), %dD: %d snapshots at t = %s" % (n, dim, len(grids), times))
    items = root.iter("DataItem")
    checked = 0
    for item in items:
        fname, dset = item.text.strip().split(":")
        shape = tuple(int(s) for s in item.get("Dimensions").split())
        with h5py.File(os.path.join(out, fname), "r") as f:
            t.check(dset in f and f[dset].shape == shape, "%s:%s has shape %s" % (fname, dset, shape)) if checked < 3 else None
            if not (dset in f and f[dset].shape == shape):
                t.fail("%s:%s missing or shaped %s, XDMF says %s" % (fname, dset, f[dset].shape if dset in f else None, shape))
        checked += 1
    t.check(checked == 5 * 5, "all %d DataItems resolve to datasets of the stated shape" % checked)
    geo = grids[-1].find("Geometry")
    t.check(geo.get("GeometryType") == ("XYZ" if dim == 3 else "XY"), "geometry type %s" % geo.get("GeometryType"))
    # the last snapshot holds the state at its step: compare with particles.csv of a run stopped at that step
    step = int(round(times[-1] / t.summary(out)["dt"]))
    ref, _ = t.run(None, args=args + ["-max_steps", step, "-output_interval", 0], nprocs=n, outdir="h5_ref")
    p = t.table(os.path.join(ref, "particles.csv"))
    with h5py.File(os.path.join(out, "snapshot_00004.h5"), "r") as f:
        ids = f["/particles/id"][:].astype(int)
        pos = f["/particles/position"][:][np.argsort(ids)]
    t.check(np.allclose(pos[:, 0], p["x"], rtol=0, atol=1e-15) and np.allclose(pos[:, 1], p["y"], rtol=0, atol=1e-15),
            "the last snapshot (step %d) holds the positions of that step" % step)
