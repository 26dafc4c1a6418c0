"""Reading a run's output files: the CSV tables (monitor.csv, particles.csv, track.csv, fluid_cells.csv),
summary.json and the HDF5 files (analysis.h5, snapshot_NNNNN.h5, checkpoint.h5). numpy; h5py for the HDF5 files."""
import csv
import json
import os
import re

import numpy as np


def table(path):
    """A CSV file as a dict of numpy columns."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: np.atleast_1d(data[name]) for name in data.dtype.names}


def summary(outdir):
    """A run's summary.json."""
    with open(os.path.join(outdir, "summary.json")) as f:
        return json.load(f)


def run_cost(s):
    """A run's cost from its summary.json s: wall seconds per simulated second per core, over the steps this run took
    (a run continued from a checkpoint counts its last part only), and its processor share, the processor time over
    wall time x ranks (below 1: it waited for its core on a loaded machine, or for its writes; nan where the run did not record it)."""
    span = s["steps_this_run"] * s["dt"] if s.get("steps_this_run") and s.get("dt") else s["time"]
    cost = s["wall_time_run"] * s["ranks"] / span if span > 0 else float("nan")
    cpu = s.get("cpu_time_run_sum_over_ranks")
    share = cpu / (s["wall_time_run"] * s["ranks"]) if cpu is not None and s["wall_time_run"] > 0 else float("nan")
    return cost, share


def read_h5(path):
    """Every dataset of an HDF5 file as a dict of arrays keyed by dataset path without the leading slash."""
    import h5py

    data = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: data.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
    return data


def run_options(run, defaults):
    """The numeric options named in defaults ({"-domain_ly": None, ...}) as a run was given them: from the options
    file and then the command line recorded in its command.txt (scripts/validate.sh) or command.json (the studies'
    runs, fluidbed_tools/study.py; later ones win); the defaults where neither has one."""
    opts = dict(defaults)
    path = os.path.join(run, "command.txt")
    if os.path.exists(path):
        words = open(path).read().split()
    elif os.path.exists(os.path.join(run, "command.json")):
        words = [str(w) for w in json.load(open(os.path.join(run, "command.json")))["args"]]
    else:
        return opts
    pairs = []
    for i, w in enumerate(words):
        if w == "-options_file" and i + 1 < len(words) and os.path.exists(words[i + 1]):
            for line in open(words[i + 1]):
                m = re.match(r"\s*(-\w+)\s+(\S+)", line)
                if m:
                    pairs.append((m.group(1), m.group(2)))
    pairs += [(w, words[i + 1]) for i, w in enumerate(words[:-1]) if w.startswith("-")]
    for k, v in pairs:
        if k in opts:
            try:
                opts[k] = float(v)
            except ValueError:
                pass
    return opts


def mirror_particles(src, dst, lx):
    """A particles.csv (or any CSV with those columns) reflected about the plane x = lx / 2: x -> lx - x, the x components of velocity and force
    negated, and the spin as the axial vector it is (its y and z components negated, x kept)."""
    rows = list(csv.DictReader(open(src)))
    for r in rows:
        r["x"] = repr(lx - float(r["x"]))
        for key in ("vx", "fx", "wy", "wz"):
            if key in r:
                r[key] = repr(-float(r[key]))
    with open(dst + ".part", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    os.replace(dst + ".part", dst)
