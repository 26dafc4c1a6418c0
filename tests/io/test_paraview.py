"""The XDMF output in a real ParaView (Debian's 5.11 pvbatch, in a virtual X server): the particle, gas and averages
series of a short 2D run of the default scene and of a short 3D coupled bed open with the XDMF reader and with the
reader ParaView picks itself (Xdmf3ReaderS); every time step loads with the snapshot's particle count and the grid's
cells, and with the values of the HDF5 files in the order of the cells; the fields have their names; the gas and
averages grids span the box (2D: in the x-y plane at z = 0, where the particles lie) and the particles lie inside
them, reaching the walls within a cell; the picture of the particles over the void fraction (saved in the output
directory) has the particles in the bed's rows and the freeboard's void fraction above. tests/io/paraview_check.py
does the ParaView side."""
import glob
import json
import os
import time

import h5py
import matplotlib.image
import numpy as np

from fluidbed_tools import testing as t

CHECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview_check.py")

scenes = [  # (label, options file, arguments, dim)
    ("2D default scene", t.example("jetted_bed_2d.opts"),
     ["-max_steps", 400, "-output_interval", 1e-3, "-average", "-average_interval", 5e-4], 2),
    ("3D coupled bed", t.example("coupling/small_bed.opts"),
     ["-max_steps", 300, "-output_interval", 5e-4, "-average", "-average_interval", 2e-4], 3),
]
GAS_FIELDS = {"pressure", "void_fraction", "velocity"}
AVERAGE_FIELDS = {"solid_fraction", "void_fraction", "velocity", "granular_temperature", "solid_flux"}
READERS = ("XDMFReader", "OpenDataFile")
VIRIDIS_TOP = np.array([0.993, 0.906, 0.144])  # the picture's colour of void fraction 1 (the top of Viridis)


def fmt(bounds):
    return "x %.4g..%.4g, y %.4g..%.4g, z %.4g..%.4g mm" % tuple(1e3 * b for b in bounds)


for label, opts, args, dim in scenes:
    start = time.time()
    out, _ = t.run(opts, args=args, outdir="paraview_%dd" % dim)
    run_s = time.time() - start

    # what the HDF5 files hold
    snaps = sorted(glob.glob(os.path.join(out, "snapshot_*.h5")))
    times, counts, void, velocity, positions = [], [], [], [], []
    for s in snaps:
        with h5py.File(s, "r") as f:
            times.append(float(f.attrs["time"]))
            counts.append(f["/particles/position"].shape[0])
            positions.append(f["/particles/position"][()])
            void.append(f["/fluid/void_fraction"][()])
            velocity.append(f["/fluid/velocity"][()])
    with h5py.File(os.path.join(out, "analysis.h5"), "r") as f:
        origin, spacing, pcells = f["grid/origin"][()], f["grid/spacing"][()], f["grid/cells"][()].astype(int)
        avg_void, avg_velocity = f["fields/void_fraction"][()], f["fields/velocity"][()]
    lo, hi = origin.copy(), origin + spacing * pcells
    if dim == 2:
        lo[2] = hi[2] = 0.0  # the plane of the particles (XY positions) and of the grids
    box = [v for a in range(3) for v in (lo[a], hi[a])]
    gas_cells = np.array(void[0].shape[::-1] + ((1,) if dim == 2 else ()))  # nx, ny(, nz)
    h = (hi - lo) / np.maximum(gas_cells, 1)  # gas cell size (z: 0 in 2D)
    tol = 1e-6 * (hi - lo).max()  # bounds of what is drawn come in single precision
    t.check(len(snaps) >= 4, "%s: %d steps in %.1f s, %d snapshots at t = %s s, %d particles, gas grid %s cells, averages grid %s" % (
        label, args[1], run_s, len(snaps), ", ".join("%.4g" % v for v in times), counts[-1], "x".join(map(str, gas_cells[:dim])),
        "x".join(map(str, pcells[:dim]))))

    # ParaView
    report, picture = os.path.join(out, "paraview.json"), os.path.join(out, "particles_over_void_fraction.png")
    start = time.time()
    p = t.pvbatch(CHECK, [out, report, picture, "--box=" + ",".join("%.17g" % v for v in box)], first_display=100)  # 100-499
    pv_s = time.time() - start
    text = p.stdout + p.stderr
    if p.returncode or not os.path.isfile(report):
        print(text[-4000:])
        t.fail("%s: pvbatch %s exited with status %d and no report" % (label, CHECK, p.returncode))
    print("\n".join(line for line in p.stdout.splitlines() if line.startswith(READERS + ("report",))))
    r = json.load(open(report))
    arrays = np.load(os.path.splitext(report)[0] + ".npz")
    print("pvbatch: %.1f s" % pv_s)

    for reader in READERS:
        P, G, A = (r[reader][name] for name in ("particles", "fluid", "analysis"))
        tag = "%s, %s (%s)" % (label, reader, G.get("xml_name"))
        for name, series in (("particles.xmf", P), ("fluid.xmf", G), ("analysis.xmf", A)):
            t.check("error" not in series, "%s: ParaView opens %s%s" % (tag, name, ": " + series.get("error", "")))
        for name, series in (("particles", P), ("gas", G)):
            t.check(len(series["times"]) == len(snaps) and np.allclose(series["times"], times, rtol=1e-5, atol=1e-12),
                    "%s: the %s series has %d time steps (%d snapshots), at the snapshots' times" % (tag, name, len(series["times"]), len(snaps)))
        t.check(P["times"] == G["times"], "%s: particles and gas at the same times (ParaView pairs their steps): %s s" % (
            tag, ", ".join("%.9g" % v for v in G["times"])))

        # where ParaView puts them: the grids span the box; the particles lie inside, reaching the walls within a cell
        avg = A["steps"][-1] if A.get("steps") else {"cells": 0, "points": 0, "cell_arrays": [], "bounds": None, "surface_bounds": None}
        for name, s in (("gas", G["steps"][-1]), ("averages", avg)):
            for kind in ("bounds", "surface_bounds"):
                got = s[kind]
                t.check(got is not None and np.allclose(got, box, rtol=0, atol=tol),
                        "%s: %s %s %s, the box is %s" % (tag, name, "drawn at" if kind == "surface_bounds" else "bounds", fmt(got) if got else None, fmt(box)))
        for k, s in enumerate(P["steps"]):
            b = np.array(s["bounds"])
            inside = all(lo[a] - 1e-12 <= b[2 * a] <= b[2 * a + 1] <= hi[a] + 1e-12 for a in range(3))
            walls = [b[0] - lo[0], hi[0] - b[1], b[2] - lo[1]] + ([b[4] - lo[2], hi[2] - b[5]] if dim == 3 else [])
            near = all(g <= c for g, c in zip(walls, [h[0], h[0], h[1], h[2], h[2]]))
            flat = dim == 3 or (b[4] == 0 and b[5] == 0)
            if k == len(snaps) - 1 or not (inside and near and flat):
                t.check(inside and near and flat, "%s: step %d particles at %s: inside the gas grid, %s mm from its walls (cell %s mm)" % (
                    tag, k, fmt(b), ", ".join("%.3g" % (1e3 * g) for g in walls), ", ".join("%.3g" % (1e3 * c) for c in h[:dim])))
        if reader == "XDMFReader":
            t.check(np.allclose(P["steps"][-1]["surface_bounds"], P["steps"][-1]["bounds"], rtol=0, atol=tol),
                    "%s: the particles are drawn where they are: %s" % (tag, fmt(P["steps"][-1]["surface_bounds"])))

        # every step loads, with its particles and the grid's cells, and the values of the HDF5 files in cell order
        bad = [k for k, s in enumerate(P["steps"]) if s["points"] != counts[k]]
        vertex_cells = [s["cells"] for s in P["steps"]]
        if reader == "XDMFReader":  # the Xdmf3 reader makes no vertex cells of a Polyvertex without connectivity
            bad += [k for k, s in enumerate(P["steps"]) if s["cells"] != counts[k]]
        same = [np.allclose(arrays["%s/particles/%d/position" % (reader, k)][:, :dim], positions[k][:, :dim], rtol=0, atol=1e-12)
                for k in range(len(snaps)) if P["steps"][k]["points"]]
        t.check(not bad and len(same) == len(snaps) and all(same),
                "%s: every particle step loads: points %s, vertex cells %s, positions as in the snapshots%s" % (
                    tag, sorted(set(s["points"] for s in P["steps"])), sorted(set(vertex_cells)), " (bad steps %s)" % sorted(set(bad)) if bad else ""))
        names = set(P["steps"][-1]["point_arrays"])
        t.check({"velocity", "omega", "diameter", "id"} <= names, "%s: particle fields %s" % (tag, sorted(names)))

        cells, points = int(np.prod(gas_cells)), int(np.prod(gas_cells[:dim] + 1))
        bad = [k for k, s in enumerate(G["steps"]) if s["cells"] != cells or s["points"] != points or not GAS_FIELDS <= set(s["cell_arrays"])]
        vf_ok = all(np.array_equal(arrays["%s/fluid/%d/void_fraction" % (reader, k)], void[k].ravel()) for k in range(len(snaps)) if k not in bad)
        vel_ok = all(np.array_equal(arrays["%s/fluid/%d/velocity" % (reader, k)][:, :dim], velocity[k].reshape(-1, dim))
                     for k in range(len(snaps)) if k not in bad)
        t.check(not bad and vf_ok and vel_ok, "%s: every gas step loads with %d cells, %d nodes, fields %s; void fraction and velocity equal the "
                "snapshots' cell for cell%s" % (tag, G["steps"][-1]["cells"], G["steps"][-1]["points"], G["steps"][-1]["cell_arrays"],
                                                  " (bad steps %s)" % bad if bad else ""))

        avg_fields = {n[:-2] if n[-2:] in ("_x", "_y") else n for n in avg["cell_arrays"]}
        t.check(len(A.get("steps", [])) == 1 and avg["cells"] == int(np.prod(pcells)) and AVERAGE_FIELDS <= avg_fields
                and np.array_equal(arrays.get("%s/analysis/0/void_fraction" % reader, np.zeros(0)), avg_void.ravel())
                and np.array_equal(arrays.get("%s/analysis/0/velocity" % reader, np.zeros((0, dim)))[:, :dim], avg_velocity.reshape(-1, dim)),
                "%s: the averages load once (%d step) with the particle grid's %d cells, fields %s, values of analysis.h5" % (
                    tag, len(A.get("steps", [])), avg["cells"], avg["cell_arrays"]))

    # the picture: rows map to heights; particles (white) in the bed's rows, the void fraction 1 colour above the bed
    t.check("error" not in r["picture"] and os.path.isfile(picture), "%s: pvbatch drew the picture%s" % (label, ": " + r["picture"].get("error", "")))
    img = matplotlib.image.imread(picture)[:, :, :3]
    rows, cols = img.shape[:2]
    t.check([cols, rows] == r["picture"]["size"], "%s: picture %s, %d x %d pixels" % (label, picture, cols, rows))
    left = img[:, : int(0.6 * cols)]  # clear of the colour bar (upper right)
    white = (left.min(axis=2) > 0.7).mean(axis=1)
    height = lambda row: hi[1] - (row + 0.5) / rows * (hi[1] - lo[1])
    top = P["steps"][-1]["bounds"][3]
    bed = [i for i in range(rows) if lo[1] + 0.1 * (top - lo[1]) < height(i) < lo[1] + 0.9 * (top - lo[1])]
    free = [i for i in range(rows) if height(i) > top + 2 * h[1]]
    colour = left[free].reshape(-1, 3).mean(axis=0)
    t.check(white[bed].mean() > 0.05 and white[free].max() < 0.01 and np.abs(colour - VIRIDIS_TOP).max() < 0.1,
            "%s: particles cover %.0f %% of the bed's rows and %.1f %% of the rows above it, whose colour %s is the void fraction 1 of the gas %s" % (
                label, 100 * white[bed].mean(), 100 * white[free].max(), np.round(colour, 3).tolist(), np.round(VIRIDIS_TOP, 3).tolist()))
