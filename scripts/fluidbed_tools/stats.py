"""Statistics of a run's time series. numpy only."""
import math

import numpy as np


def standard_error(values):
    """The standard error of the mean of independent values (e.g. one statistic measured on consecutive blocks of a
    run): their sample standard deviation over sqrt(count)."""
    v = np.asarray(values, dtype=float)
    return float(v.std(ddof=1) / math.sqrt(len(v)))


def batch_error(series, batches=10):
    """The standard error of a time series' mean by batch means: the series cut into batches (each longer than the
    flow's correlation time, e.g. a bubble period), the standard deviation of their means over sqrt(batches)."""
    return standard_error([x.mean() for x in np.array_split(np.asarray(series), batches)])
