"""Reading a run's output files: the CSV tables (monitor.csv, particles.csv, track.csv, fluid_cells.csv),
summary.json and the HDF5 files (analysis.h5, snapshot_NNNNN.h5, checkpoint.h5). numpy; h5py for the HDF5 files."""
import json
import os

import numpy as np


def table(path):
    """A CSV file as a dict of numpy columns."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: np.atleast_1d(data[name]) for name in data.dtype.names}


def summary(outdir):
    """A run's summary.json."""
    with open(os.path.join(outdir, "summary.json")) as f:
        return json.load(f)


def read_h5(path):
    """Every dataset of an HDF5 file as a dict of arrays keyed by dataset path without the leading slash."""
    import h5py

    data = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: data.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
    return data
