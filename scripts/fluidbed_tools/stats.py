"""Statistics of a run's time series. numpy only."""
import math

import numpy as np


def batch_error(series, batches=10):
    """The standard error of a time series' mean by batch means: the series cut into batches (each longer than the
    flow's correlation time, e.g. a bubble period), the standard deviation of their means over sqrt(batches)."""
    b = np.array([x.mean() for x in np.array_split(np.asarray(series), batches)])
    return float(b.std(ddof=1) / math.sqrt(len(b)))
