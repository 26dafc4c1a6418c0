"""Helpers for the scene and MPI tests: run the fluidbed executable on an options file and read its outputs.

Each test is a script that exits nonzero when an assertion fails and prints the figures it measured."""
import csv
import json
import os
import shutil
import subprocess
import sys

import numpy as np

SRC = os.environ.get("FLUIDBED_SOURCE", os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXE = os.environ.get("FLUIDBED_EXE", os.path.join(SRC, "build", "fluidbed"))
MPIEXEC = os.environ.get("FLUIDBED_MPIEXEC", "mpiexec")


def example(path):
    return os.path.join(SRC, "examples", path)


def run(options_file=None, args=(), nprocs=1, outdir="out", expect_fail=False, timeout=1200, clean=True, env=None, preexec_fn=None):
    """Runs fluidbed, returns (output directory, completed process). Fails the test on an unexpected status.
    The output directory is emptied first unless clean is False (a restart continuing in place). env and preexec_fn
    go to subprocess.run (e.g. a resource limit for the run)."""
    if clean and os.path.isdir(outdir):
        shutil.rmtree(outdir)
    cmd = [EXE]
    if options_file:
        cmd += ["-options_file", options_file]
    cmd += ["-output_dir", outdir] + ([] if "-progress_interval" in [str(a) for a in args] else ["-progress_interval", "0"]) + [str(a) for a in args]
    if nprocs > 1:
        cmd = [MPIEXEC, "--allow-run-as-root", "--oversubscribe", "-n", str(nprocs)] + cmd
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, preexec_fn=preexec_fn)
    if not expect_fail and p.returncode != 0:
        print(p.stdout[-4000:], p.stderr[-4000:])
        fail("fluidbed exited with status %d: %s" % (p.returncode, " ".join(cmd)))
    return outdir, p


def table(path):
    """A CSV file as a dict of numpy columns."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: np.atleast_1d(data[name]) for name in data.dtype.names}


def summary(outdir):
    with open(os.path.join(outdir, "summary.json")) as f:
        return json.load(f)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def check(condition, message):
    """Prints the measured figure either way; fails the test when the condition does not hold."""
    print(("ok:   " if condition else "FAIL: ") + message)
    if not condition:
        sys.exit(1)


def rel(a, b):
    return abs(a - b) / abs(b)


def check_bad_input(cases, common=(), outdir="bad_input", ranks=(1, 2)):
    """Runs each (args, words) case with the common options on every rank count and checks a clean failure: nonzero
    exit, no crash, and every word in the output (the option's name, its range)."""
    for nprocs in ranks:
        for args, words in cases:
            _, p = run(None, args=list(common) + list(args) + ["-t_final", "0"], nprocs=nprocs, outdir=outdir, expect_fail=True, timeout=60)
            text = p.stdout + p.stderr
            crashed = any(s in text for s in ("Segmentation", "signal", "core dumped", "Caught signal"))
            missing = [w for w in words if w not in text]
            first = next((line for line in text.splitlines() if "error" in line.lower()), "(no error line)")
            check(p.returncode != 0 and not crashed and not missing,
                  "%d rank(s) %s: exit %d, %s%s" % (nprocs, " ".join(args), p.returncode, first.strip()[:150], " MISSING %s" % missing if missing else ""))
