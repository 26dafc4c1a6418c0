"""Shared reading and drawing helpers of the plot scripts (scripts/plot_*.py, scripts/jet_fountain.py): a run's
analysis.h5 (time averages on the particle grid, docs/analysis.md), its snapshot_NNNNN.h5 files (/particles, /fluid)
and monitor.csv. matplotlib (Agg), h5py and numpy only."""
import argparse
import glob
import os
import sys
import warnings
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .outputs import read_h5  # noqa: E402

MM = 1e3  # axes in mm


def die(message):
    print("error: " + message, file=sys.stderr)
    sys.exit(2)


def parser(doc, single_run=True):
    """The command line of a plot script: its docstring as help; a run directory and an output PNG unless
    single_run is False."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0], epilog="example:" + doc.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    if single_run:
        ap.add_argument("run", help="run directory (fluidbed -output_dir)")
        ap.add_argument("output", help="PNG file to write")
    return ap


def analysis_path(run):
    path = os.path.join(run, "analysis.h5")
    if not os.path.isfile(path):
        die("%s has no analysis.h5: run fluidbed with -average (or -average_start)" % run)
    return path


def read_analysis(run):
    """The run's analysis.h5 (read_h5)."""
    return read_h5(analysis_path(run))


def box(run):
    """(lo, hi) of the domain, 3 values each: from analysis.h5, else from fluid.xmf (z 0..1 in 2D)."""
    if os.path.isfile(os.path.join(run, "analysis.h5")):
        with h5py.File(os.path.join(run, "analysis.h5"), "r") as f:
            lo, h, n = f["grid/origin"][()], f["grid/spacing"][()], f["grid/cells"][()]
        return lo, lo + h * n
    xmf = os.path.join(run, "fluid.xmf")
    if not os.path.isfile(xmf):
        die("%s has neither analysis.h5 nor fluid.xmf to give the domain" % run)
    grid = ET.parse(xmf).getroot().find("./Domain/Grid/Grid")
    items = grid.find("Geometry").findall("DataItem")
    lo = np.zeros(3)
    hi = np.ones(3)
    if grid.find("Geometry").get("GeometryType") == "XY":  # 2D: the node coordinates (in fluid_grid.h5 or inline)
        if items[0].get("Format") == "HDF":
            name, dataset = items[0].text.strip().split(":")
            with h5py.File(os.path.join(run, name), "r") as f:
                nodes = f[dataset][()]
        else:
            nodes = np.array(items[0].text.split(), dtype=float).reshape(-1, 2)
        lo[:2], hi[:2] = nodes.min(axis=0), nodes.max(axis=0)
        return lo, hi
    nodes = [int(s) for s in grid.find("Topology").get("Dimensions").split()][::-1]  # CoRectMesh: origin and spacing
    origin = [float(s) for s in items[0].text.split()][::-1]
    spacing = [float(s) for s in items[1].text.split()][::-1]
    for a in range(len(nodes)):
        lo[a] = origin[a]
        hi[a] = origin[a] + spacing[a] * (nodes[a] - 1)
    return lo, hi


def depth_mean(field, dim):
    """A cell field (nz, ny, nx[, c]) in 3D or (ny, nx[, c]) in 2D as (ny, nx[, c]), averaged over the depth."""
    f = np.asarray(field, dtype=float)
    if dim != 3:
        return f
    with warnings.catch_warnings():  # a column no particle reached is NaN through the depth: NaN is the answer
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanmean(f, axis=0)


def snapshots(run):
    files = sorted(glob.glob(os.path.join(run, "snapshot_*.h5")))
    if not files:
        die("%s has no snapshot_NNNNN.h5 files: run fluidbed with -output_interval" % run)
    return files


def snapshot_void_fraction(path, lo, hi, cells):
    """The void fraction of a snapshot: the gas's /fluid/void_fraction when the gas is on, otherwise the particles
    binned on a grid of `cells` (each particle whole in the cell of its centre, eq. 5.2-5.3). Returns (field over
    (y, x) averaged over the depth, time, source)."""
    with h5py.File(path, "r") as f:
        time = float(np.ravel(f.attrs["time"])[0]) if "time" in f.attrs else float("nan")
        if "fluid/void_fraction" in f:
            eps = np.asarray(f["fluid/void_fraction"][()], float)
            return (np.mean(eps, axis=0) if eps.ndim == 3 else eps), time, "gas"
        if "particles/position" not in f:
            die("%s has neither /fluid nor /particles" % path)
        x = np.atleast_2d(f["particles/position"][()])
        d = np.atleast_1d(f["particles/diameter"][()])
    dim = x.shape[1]
    n = [int(c) for c in cells[:dim]]
    edges = [np.linspace(lo[a], hi[a], n[a] + 1) for a in range(dim)]
    xc = np.column_stack([np.clip(x[:, a], lo[a], np.nextafter(hi[a], lo[a])) for a in range(dim)])
    vol, _ = np.histogramdd(xc, bins=edges, weights=np.pi / 6 * d**3)
    vcell = np.prod((hi - lo)[:dim] / n) * (1.0 if dim == 3 else hi[2] - lo[2])
    eps = 1.0 - vol / vcell  # indexed [x, y(, z)]
    eps = eps.mean(axis=2) if dim == 3 else eps
    return eps.T, time, "particles"


def field_image(ax, field, lo, hi, label, cmap="viridis", vmin=None, vmax=None):
    im = ax.imshow(field, origin="lower", extent=[lo[0] * MM, hi[0] * MM, lo[1] * MM, hi[1] * MM], cmap=cmap, vmin=vmin, vmax=vmax,
                   interpolation="nearest", aspect="equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    plt.colorbar(im, ax=ax, label=label)
    return im


def add_ymax_option(ap):
    ap.add_argument("--ymax", type=float, default=None,
                    help="top of the plotted region (m); default: 1.3 times the height of the time-averaged bed (its highest "
                         "cells with a mean solid fraction above 0.005), the whole domain at most")


def plot_top(ymax, solid_fraction, lo, hi):
    """Top (m) of the region to draw: ymax when given, else 1.3 times the height of the highest layer of the
    time-averaged solid fraction (ny, nx) above 0.005, within the domain."""
    if ymax is not None:
        return min(ymax, hi[1])
    rows = np.nonzero(np.nanmax(solid_fraction, axis=1) > 0.005)[0]
    if rows.size == 0:
        return hi[1]
    top = lo[1] + (rows[-1] + 1) * (hi[1] - lo[1]) / solid_fraction.shape[0]
    return min(hi[1], lo[1] + 1.3 * (top - lo[1]))


def save(fig, output):
    directory = os.path.dirname(os.path.abspath(output))
    os.makedirs(directory, exist_ok=True)
    fig.tight_layout()
    fig.savefig(output, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print("wrote %s" % output)
