"""Helpers for the gas-phase tests: the cell table written by -fluid_output_cells and the monitor's gas columns."""
import os

import numpy as np

from fluidbed_tools import testing as t


def cells(outdir):
    """fluid_cells.csv as a dict of arrays shaped (nz, ny, nx), plus the sizes under 'n'."""
    c = t.table(os.path.join(outdir, "fluid_cells.csv"))
    n = (int(c["k"].max()) + 1, int(c["j"].max()) + 1, int(c["i"].max()) + 1)
    out = {k: v.reshape(n) for k, v in c.items()}
    out["n"] = n
    return out


def monitor(outdir):
    return t.table(os.path.join(outdir, "monitor.csv"))


def ghia(path=None):
    """Ghia, Ghia & Shin (1982) Re = 100 centre-line table: {'u': (y, u/U), 'v': (x, v/U)}."""
    path = path or os.path.join(t.SRC, "tests", "data", "ghia1982_re100.csv")
    rows = {"u": [], "v": []}
    with open(path) as f:
        for line in f:
            parts = line.strip().split(",")
            if line.startswith("#") or parts[0] not in rows:
                continue
            rows[parts[0]].append((float(parts[1]), float(parts[2])))
    return {k: (np.array([r[0] for r in v]), np.array([r[1] for r in v])) for k, v in rows.items()}
