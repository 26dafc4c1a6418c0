"""Helpers for the analysis tests: read a run's analysis.h5 (time-averaged fields, profiles, series, measures)."""
import os

import numpy as np

from fluidbed_tools.outputs import read_h5


def read(outdir):
    """analysis.h5 as a dict of numpy arrays keyed by dataset path without the leading slash."""
    return read_h5(os.path.join(outdir, "analysis.h5"))


def measure(data, name):
    return float(data["measures/" + name][0])


def grid(data):
    """origin, spacing and cell counts (3 each; in 2D z is one layer of the bed's depth)."""
    return data["grid/origin"], data["grid/spacing"], data["grid/cells"].astype(int)


def cells_xyz(field):
    """A scalar field of shape (nz, ny, nx) or, in 2D, (ny, nx), as an array indexed [i, j, k]."""
    f = np.asarray(field)
    if f.ndim == 2:
        f = f[np.newaxis]
    return np.transpose(f, (2, 1, 0))
