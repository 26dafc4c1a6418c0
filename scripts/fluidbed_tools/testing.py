"""Helpers for the scene and MPI tests: run the fluidbed executable on an options file, read its outputs, check.

Each test is a script that exits nonzero when an assertion fails and prints the figures it measured. The names a
test uses come from here (`from fluidbed_tools import testing as t`): t.run, t.check, t.fail, t.rel,
t.check_bad_input, and, from run.py and outputs.py, t.SRC, t.EXE, t.example, t.table, t.summary."""
import sys

from .outputs import summary, table
from .run import EXE, SRC, example, execute

__all__ = ["EXE", "SRC", "example", "summary", "table", "run", "fail", "check", "rel", "check_bad_input"]


def run(options_file=None, args=(), nprocs=1, outdir="out", expect_fail=False, timeout=1200, clean=True, env=None, preexec_fn=None):
    """Runs fluidbed (run.execute), returns (output directory, completed process). Fails the test on an unexpected
    status. The output directory is emptied first unless clean is False (a restart continuing in place). env and
    preexec_fn go to subprocess.run (e.g. a resource limit for the run)."""
    outdir, p, cmd = execute(options_file, args, nprocs, outdir, timeout, clean, env, preexec_fn)
    if not expect_fail and p.returncode != 0:
        print(p.stdout[-4000:], p.stderr[-4000:])
        fail("fluidbed exited with status %d: %s" % (p.returncode, " ".join(cmd)))
    return outdir, p


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
