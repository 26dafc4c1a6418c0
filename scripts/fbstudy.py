"""Running a study's points: each point is one fluidbed run in a directory of its own, started with mpiexec on --ranks
ranks, --jobs at a time, and skipped when a finished run with the same command is already there (a study resumes
where it stopped and can be extended on more cores). The stability map (stability_map.py) and later studies use it."""
import concurrent.futures
import json
import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.environ.get("FLUIDBED_EXE", os.path.join(ROOT, "build", "fluidbed"))
MPIEXEC = os.environ.get("FLUIDBED_MPIEXEC", "mpiexec")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1",
           OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))


def command(args, outdir, ranks=1, exe=EXE):
    """The command line of a run of `args` (options) into outdir."""
    cmd = [exe] + [str(a) for a in args] + ["-output_dir", outdir, "-progress_interval", "0"]
    if ranks > 1:
        cmd = [MPIEXEC, "--allow-run-as-root", "--oversubscribe", "-n", str(ranks)] + cmd
    return cmd


def done(args, outdir, ranks=1, exe=EXE):
    """Whether the point's run is finished in outdir (without running it)."""
    cmd = command(args, outdir, ranks, exe)
    return finished_run(outdir, cmd[cmd.index(exe):])


def run(args, outdir, ranks=1, exe=EXE, timeout=None, fresh=False):
    """Runs one point unless it is finished (or fresh: always, e.g. to measure its cost again on a quiet machine);
    returns (summary dict or None, exit status, wall seconds, reused). A run refused at start-up (exit 2) or failed
    without a summary returns None and its status."""
    cmd = command(args, outdir, ranks, exe)
    tail = cmd[cmd.index(exe):]
    if not fresh and finished_run(outdir, tail):
        with open(os.path.join(outdir, "command.json")) as f:
            meta = json.load(f)
        path = os.path.join(outdir, "summary.json")
        s = json.load(open(path)) if os.path.isfile(path) else None
        return s, meta["exit_status"], meta["wall_s"], True
    if os.path.isdir(outdir):
        shutil.rmtree(outdir)
    os.makedirs(outdir)
    t0 = time.time()
    with open(os.path.join(outdir, "stdout.txt"), "w") as out:
        try:
            p = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=ENV, timeout=timeout)
            status = p.returncode
        except subprocess.TimeoutExpired:
            status = -1
    wall = time.time() - t0
    with open(os.path.join(outdir, "command.json"), "w") as f:
        json.dump({"args": tail, "ranks": ranks, "exit_status": status, "wall_s": wall}, f)
    path = os.path.join(outdir, "summary.json")
    if not os.path.isfile(path):
        return None, status, wall, False
    with open(path) as f:
        return json.load(f), status, wall, False


def finished_run(outdir, tail):
    """Whether outdir holds a finished run of this command tail (the executable and its options)."""
    try:
        with open(os.path.join(outdir, "command.json")) as f:
            meta = json.load(f)
        # the options make the point; the executable that ran it (a copy kept aside while the sources change) is recorded
        if meta["args"][1:] != tail[1:] or meta["exit_status"] < 0:
            return False
        return meta["exit_status"] == 2 or os.path.isfile(os.path.join(outdir, "summary.json"))
    except (OSError, ValueError, KeyError):
        return False


def summary(outdir):
    """A run's summary.json."""
    with open(os.path.join(outdir, "summary.json")) as f:
        return json.load(f)


def run_all(points, jobs, worker):
    """Calls worker(point) for every point, `jobs` at a time; yields (point, result) as they finish."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = {pool.submit(worker, p): p for p in points}
        for fut in concurrent.futures.as_completed(futures):
            yield futures[fut], fut.result()


def log(message):
    print(message, flush=True)
    sys.stdout.flush()
