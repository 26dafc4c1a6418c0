"""Running a study's points: each point is one fluidbed run in a directory of its own, started with mpiexec on --ranks
ranks, --jobs at a time, and skipped when a finished run with the same command is already there (a study resumes
where it stopped and can be extended on more cores). The stability map (scripts/stability_map.py), the speed-accuracy
study (scripts/speed_accuracy.py) and strong scaling (scripts/strong_scaling.py) use it; the command line and the
finished-run test are run.point_command and run.finished_run."""
import concurrent.futures
import csv
import json
import os
import shutil
import subprocess
import sys
import time

from . import run as _run


def run(args, outdir, ranks=1, exe=_run.EXE, timeout=None, fresh=False):
    """Runs one point unless it is finished (or fresh: always, e.g. to measure its cost again on a quiet machine);
    returns (summary dict or None, exit status, wall seconds, reused). A run refused at start-up (exit 2) or failed
    without a summary returns None and its status. The run's output goes to outdir/stdout.txt and its record (the
    command's tail, ranks, exit status, wall seconds) to outdir/command.json."""
    cmd = _run.point_command(args, outdir, ranks, exe)
    tail = cmd[cmd.index(exe):]
    if not fresh and _run.finished_run(outdir, tail):
        with open(os.path.join(outdir, "command.json")) as f:
            meta = json.load(f)
        path = os.path.join(outdir, "summary.json")
        s = json.load(open(path)) if os.path.isfile(path) else None
        if meta["exit_status"] is None:  # the driver stopped before the run ended: the run's own record
            return s, s["exit_code"], s["wall_time_setup"] + s["wall_time_run"], True
        return s, meta["exit_status"], meta["wall_s"], True
    if os.path.isdir(outdir):
        shutil.rmtree(outdir)
    os.makedirs(outdir)
    # the record first, without an exit status: a run that outlives its driver is still known by its options
    with open(os.path.join(outdir, "command.json"), "w") as f:
        json.dump({"args": tail, "ranks": ranks, "exit_status": None, "wall_s": None}, f)
    t0 = time.time()
    with open(os.path.join(outdir, "stdout.txt"), "w") as out:
        try:
            p = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=_run.ENV, timeout=timeout)
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


def run_all(points, jobs, worker):
    """Calls worker(point) for every point, `jobs` at a time; yields (point, result) as they finish."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = {pool.submit(worker, p): p for p in points}
        for fut in concurrent.futures.as_completed(futures):
            yield futures[fut], fut.result()


def parse_cell(v):
    """A CSV cell back to a number, a flag or None; other text (grids such as 175x200x5, names) stays text."""
    if v is None or v == "":
        return None
    if v in ("True", "False"):
        return v == "True"
    for conv in (int, float):
        try:
            return conv(v)
        except ValueError:
            pass
    return v


def kept_rows(path, keep):
    """The rows of an existing CSV table, their cells parsed, for which keep(row) is true; none where there is no
    table. A study run on a fresh machine, whose working directory holds only this session's points, adds its rows to
    the committed table this way instead of replacing the rows of earlier sessions."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        rows = [{k: parse_cell(v) for k, v in r.items()} for r in csv.DictReader(f)]
    return [r for r in rows if keep(r)]


def log(message):
    print(message, flush=True)
    sys.stdout.flush()
