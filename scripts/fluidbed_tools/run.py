"""Running the fluidbed executable: the one place that builds its command line, serial or under mpiexec, and that
tells whether a recorded run (a study point) is finished.

The executable is $FLUIDBED_EXE (default <source>/build/fluidbed), the launcher $FLUIDBED_MPIEXEC (default
mpiexec), the source tree $FLUIDBED_SOURCE (default the checkout holding this package); CMake sets all three for
the tests."""
import json
import os
import shutil
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # the checkout holding scripts/
SRC = os.environ.get("FLUIDBED_SOURCE", ROOT)
EXE = os.environ.get("FLUIDBED_EXE", os.path.join(SRC, "build", "fluidbed"))
MPIEXEC = os.environ.get("FLUIDBED_MPIEXEC", "mpiexec")
# the environment of a study's runs: Open MPI as root and oversubscribed, one OpenMP thread
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1",
           OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))


def machine():
    """The CPU model and the cores a run may use (nproc, not limited by OMP_NUM_THREADS), for a benchmark's record."""
    model = "unknown"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_NUM_THREADS", "OMP_THREAD_LIMIT")}
    cores = subprocess.run(["nproc"], capture_output=True, text=True, env=env).stdout.strip()
    return {"cpu": model, "cores": int(cores) if cores.isdigit() else cores}


def example(path):
    """An options file of examples/ by its path there."""
    return os.path.join(SRC, "examples", path)


def launcher(ranks, mpiexec=MPIEXEC):
    """The mpiexec prefix that starts a command on `ranks` ranks (as root, oversubscribed, unbound: Open MPI binds
    every job's ranks to the first cores, so jobs run side by side (a study's --jobs, ctest -j) would share them)."""
    return [mpiexec, "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-n", str(ranks)]


def command(options, ranks=1, exe=EXE):
    """The command line of fluidbed with these options (each turned into a string): under mpiexec above one rank."""
    cmd = [exe] + [str(a) for a in options]
    if ranks > 1:
        cmd = launcher(ranks) + cmd
    return cmd


def execute(options_file=None, args=(), nprocs=1, outdir="out", timeout=1200, clean=True, env=None, preexec_fn=None):
    """Runs fluidbed on an options file (or none) and further options into outdir, its output captured; returns
    (outdir, completed process, command). The output directory is emptied first unless clean is False (a restart
    continuing in place); -progress_interval 0 unless args set it. env and preexec_fn go to subprocess.run (e.g. a
    resource limit for the run)."""
    if clean and os.path.isdir(outdir):
        shutil.rmtree(outdir)
    options = ["-options_file", options_file] if options_file else []
    options += ["-output_dir", outdir] + ([] if "-progress_interval" in [str(a) for a in args] else ["-progress_interval", "0"]) + list(args)
    cmd = command(options, nprocs)
    return outdir, subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, preexec_fn=preexec_fn), cmd


def point_command(args, outdir, ranks=1, exe=EXE):
    """The command line of a study point: fluidbed with the options `args` into outdir, without progress lines."""
    return command(list(args) + ["-output_dir", outdir, "-progress_interval", "0"], ranks, exe)


def finished_run(outdir, tail):
    """Whether outdir holds a finished run of this command tail (the executable and its options): its command.json
    (written by study.run) has the same options and a non-negative exit status, and the run was refused at start-up
    (exit 2) or left a summary.json. A record without an exit status (study.run writes it before the run and completes
    it after) is a run whose driver stopped first: it counts as finished if the run wrote its summary.json."""
    try:
        with open(os.path.join(outdir, "command.json")) as f:
            meta = json.load(f)
        # the options make the point; the executable that ran it (a copy kept aside while the sources change) is recorded
        if meta["args"][1:] != tail[1:]:
            return False
        if meta["exit_status"] is None:
            return os.path.isfile(os.path.join(outdir, "summary.json"))
        if meta["exit_status"] < 0:
            return False
        return meta["exit_status"] == 2 or os.path.isfile(os.path.join(outdir, "summary.json"))
    except (OSError, ValueError, KeyError, TypeError):
        return False


def done(args, outdir, ranks=1, exe=EXE):
    """Whether the point's run is finished in outdir (without running it)."""
    cmd = point_command(args, outdir, ranks, exe)
    return finished_run(outdir, cmd[cmd.index(exe):])
