"""Helpers for the scene and MPI tests: run the fluidbed executable on an options file, read its outputs, check.

Each test is a script that exits nonzero when an assertion fails and prints the figures it measured. The names a
test uses come from here (`from fluidbed_tools import testing as t`): t.run, t.check, t.fail, t.rel,
t.check_bad_input, t.pvbatch, and, from run.py and outputs.py, t.SRC, t.EXE, t.example, t.table, t.summary."""
import os
import shutil
import subprocess
import sys
import time

from .outputs import summary, table
from .run import EXE, SRC, example, execute

__all__ = ["EXE", "SRC", "example", "summary", "table", "run", "fail", "check", "rel", "check_bad_input", "pvbatch"]


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


PARAVIEW_PACKAGES = ("scripts/test.sh installs them (FLUIDBED_TEST_PACKAGES in scripts/setup.sh), or: "
                     "apt-get install --no-install-recommends paraview python3-paraview xvfb xauth")


def pvbatch(script, args, first_display, tries=4, timeout=300):
    """Runs ParaView's pvbatch on script with args in a virtual X server (xvfb-run), returns the completed process.
    xvfb-run -a takes the first display from first_display on that has no lock file: give each test its own range,
    so that two tests started together, or a server an earlier run left without its lock file, do not make pvbatch
    meet a server that is not its own. A server that refuses pvbatch's connection ("bad X server connection": seen
    about one start in three on a loaded machine, and on every start in the first seconds after the packages were
    installed) says nothing about the files: wait, then try another display, at most tries times. Fails the test
    when pvbatch or xvfb-run is missing."""
    exe, xvfb = shutil.which("pvbatch"), shutil.which("xvfb-run")
    missing = [name for name, path in (("pvbatch", exe), ("xvfb-run", xvfb)) if not path]
    if missing:
        fail("%s not installed (not on PATH): this test opens the output in ParaView's pvbatch in a virtual X server; %s" % (
            " and ".join(missing) + (" is" if len(missing) == 1 else " are"), PARAVIEW_PACKAGES))
    for attempt in range(tries):
        if attempt:
            time.sleep(5 * attempt)
        display = first_display + (os.getpid() + 7 * attempt) % 400
        p = subprocess.run([xvfb, "-a", "-n", str(display), exe, script] + [str(a) for a in args], capture_output=True, text=True,
                           timeout=timeout)
        if "bad X server connection" not in p.stdout + p.stderr:
            break
        print("the virtual X server refused pvbatch (attempt %d of %d)" % (attempt + 1, tries))
    if "No module named 'paraview'" in p.stdout + p.stderr:
        fail("pvbatch has no Python module paraview (Debian's python3-paraview is missing): " + PARAVIEW_PACKAGES)
    return p
