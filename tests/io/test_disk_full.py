"""A write that fails during a run (a file-size limit, a full disk) stops the run with exit status 3 and one line
naming the file and the reason, on 1 and 2 ranks, with no traceback, no crash and no rank left waiting, and what was
complete before stays intact: monitor.csv ends with its last complete row, no temporary file is left, the previous
checkpoint is unchanged and loads with -restart, summary.json is absent or the previous run's complete one.

The limit is a file-size limit (RLIMIT_FSIZE, as `ulimit -f`) set for the run and sized from unlimited reference runs,
so that it hits a chosen file: monitor.csv mid-run, the first snapshot, a checkpoint, particles.csv, summary.json.
Where this machine lets the test mount a tmpfs, a small one is filled as well (No space left on device); elsewhere
that part is skipped."""
import json
import os
import resource
import shutil
import subprocess
import sys

import h5py

from fluidbed_tools import testing as t

SCENE = ["-insert_count", 300, "-t_final", 0.01]
HDF5 = ["-output_interval", 0.002, "-checkpoint_interval", 0.005]
# Open MPI keeps shared-memory files of its own (PMIx's store, the shared-memory transport) that a file-size limit
# breaks before fluidbed starts: the hash store and the TCP transport keep the limit to fluidbed's own files.
ENV = dict(os.environ, PMIX_MCA_gds="hash", OMPI_MCA_btl="self,tcp")
TOO_LARGE, NO_SPACE = os.strerror(27), os.strerror(28)  # EFBIG, ENOSPC
CRASH = ("PETSC ERROR", "Segmentation", "Caught signal", "core dumped", "Traceback", "HDF5-DIAG", "MPI_ABORT")


def run(args, nprocs, outdir, limit=None, clean=True, expect_fail=True):
    preexec = (lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))) if limit else None
    try:
        return t.run(None, args=SCENE + args, nprocs=nprocs, outdir=outdir, expect_fail=expect_fail, timeout=120, clean=clean, env=ENV,
                     preexec_fn=preexec)[1]
    except subprocess.TimeoutExpired:
        t.fail("%s: the run did not end within 120 s (a rank waits for another)" % outdir)


def check_failed(p, label, name, reason, allow=()):
    """Exit status 3, the first error line names the file and the reason, nothing crashed."""
    text = p.stdout + p.stderr
    errors = [line for line in text.splitlines() if line.startswith("fluidbed: error:")]
    crash = [s for s in CRASH if s in text and s not in allow]
    t.check(p.returncode == 3 and errors and name in errors[0] and reason in errors[0] and not crash,
            "%s: exit %d, %s%s" % (label, p.returncode, errors[0] if errors else "(no error line)", " CRASH %s" % crash if crash else ""))


def check_rows(path, label):
    """monitor.csv: ends with a newline, every row has the header's columns, the steps increase. Returns the rows."""
    text = open(path).read()
    lines = text.split("\n")
    width = len(lines[0].split(","))
    rows = [line.split(",") for line in lines[1:-1]]
    steps = [int(r[0]) for r in rows]
    t.check(text.endswith("\n") and all(len(r) == width for r in rows) and steps == sorted(set(steps)),
            "%s: %s holds %d complete rows of %d columns, steps increasing" % (label, os.path.basename(path), len(rows), width))
    return rows


def no_temporaries(outdir, label):
    tmp = [f for f in os.listdir(outdir) if f.endswith(".tmp")]
    t.check(not tmp, "%s: no temporary file left %s" % (label, tmp or ""))


def size(path):
    return os.path.getsize(path)


for n in (1, 2):
    # Reference runs without a limit: the sizes the limits are placed between.
    log, h5, small = "ref_log_%d" % n, "ref_h5_%d" % n, "ref_small_%d" % n
    run(["-monitor_dt", 0], n, log, expect_fail=False)
    run(HDF5, n, h5, expect_fail=False)
    run(["-monitor_dt", 1], n, small, expect_fail=False)
    monitor, snapshot, checkpoint = size(log + "/monitor.csv"), size(h5 + "/snapshot_00000.h5"), size(h5 + "/checkpoint.h5")
    particles, summary, monitor_small = size(small + "/particles.csv"), size(small + "/summary.json"), size(small + "/monitor.csv")
    t.check(checkpoint > 2 * snapshot and particles > 2 * max(summary, monitor_small) and summary > 1.2 * monitor_small,
            "%d rank(s): sizes monitor.csv %d (every step) / %d (two rows), snapshot %d, checkpoint %d, particles.csv %d, summary.json %d"
            % (n, monitor, monitor_small, snapshot, checkpoint, particles, summary))

    # monitor.csv mid-run: it grows by a row every step
    label, out = "%d rank(s), monitor.csv mid-run" % n, "fail_monitor_%d" % n
    p = run(["-monitor_dt", 0], n, out, limit=monitor // 2)
    check_failed(p, label, "monitor.csv", TOO_LARGE)
    rows = check_rows(out + "/monitor.csv", label)
    t.check(0 < len(rows) < len(check_rows(log + "/monitor.csv", "reference")) and not os.path.exists(out + "/summary.json"),
            "%s: stopped after %d rows, no summary.json" % (label, len(rows)))

    # the first snapshot (t = 0)
    label, out = "%d rank(s), first snapshot" % n, "fail_snapshot_%d" % n
    p = run(HDF5, n, out, limit=snapshot // 2)
    check_failed(p, label, "snapshot_00000.h5", TOO_LARGE)
    t.check(not os.path.exists(out + "/snapshot_00000.h5") and not os.path.exists(out + "/particles.xmf"),
            "%s: no snapshot file, no particles.xmf naming one" % label)
    no_temporaries(out, label)
    check_rows(out + "/monitor.csv", label)

    # a checkpoint, continuing a finished run in a copy of its directory: its checkpoint and summary stay as they were
    label, out = "%d rank(s), checkpoint after a restart" % n, "fail_checkpoint_%d" % n
    shutil.rmtree(out, ignore_errors=True)
    shutil.copytree(h5, out)
    before = open(out + "/checkpoint.h5", "rb").read()
    p = run(HDF5 + ["-t_final", 0.02, "-restart", out + "/checkpoint.h5"], n, out, limit=(checkpoint + snapshot) // 2, clean=False)
    check_failed(p, label, "checkpoint.h5", TOO_LARGE)
    t.check(open(out + "/checkpoint.h5", "rb").read() == before, "%s: checkpoint.h5 unchanged" % label)
    no_temporaries(out, label)
    check_rows(out + "/monitor.csv", label)
    t.check(t.summary(out) == t.summary(h5), "%s: summary.json is the finished run's, complete" % label)
    run(["-t_final", 0.0105, "-restart", out + "/checkpoint.h5"], n, "resume_%d" % n, expect_fail=False)
    t.check(t.summary("resume_%d" % n)["steps"] > t.summary(h5)["steps"], "%s: the kept checkpoint loads with -restart and runs on" % label)

    # a checkpoint again, without the space reserved first: the failure comes from inside parallel HDF5, where the
    # job is ended (MPI_Abort with the same exit status) since ranks waiting in HDF5 cannot be released otherwise
    label, out = "%d rank(s), checkpoint, -output_reserve 0" % n, "fail_unreserved_%d" % n
    p = run(HDF5 + ["-output_reserve", 0], n, out, limit=(checkpoint + snapshot) // 2)
    check_failed(p, label, "checkpoint.h5", TOO_LARGE, allow=("MPI_ABORT",))
    snapshots = sorted(f for f in os.listdir(out) if f.startswith("snapshot_"))
    shapes = set()
    for f in snapshots:
        with h5py.File(os.path.join(out, f), "r") as h:
            shapes.add(h["particles/position"].shape)
    t.check(snapshots and shapes == {(300, 3)} and not os.path.exists(out + "/checkpoint.h5"),
            "%s: the %d snapshots written before read back whole %s, no checkpoint.h5" % (label, len(snapshots), sorted(shapes)))
    no_temporaries(out, label)

    # particles.csv at the end
    label, out = "%d rank(s), particles.csv" % n, "fail_particles_%d" % n
    p = run(["-monitor_dt", 1], n, out, limit=(particles + max(summary, monitor_small)) // 2)
    check_failed(p, label, "particles.csv", TOO_LARGE)
    t.check(not os.path.exists(out + "/particles.csv") and not os.path.exists(out + "/summary.json"), "%s: no particles.csv, no summary.json" % label)
    no_temporaries(out, label)
    check_rows(out + "/monitor.csv", label)

    # summary.json, the last file a run writes
    label, out = "%d rank(s), summary.json" % n, "fail_summary_%d" % n
    p = run(["-monitor_dt", 1, "-output_particles", 0], n, out, limit=(summary + monitor_small) // 2)
    check_failed(p, label, "summary.json", TOO_LARGE)
    t.check(not os.path.exists(out + "/summary.json") and "Done:" not in p.stdout, "%s: no summary.json, no 'Done:' line" % label)
    no_temporaries(out, label)

# A full disk: a tmpfs just larger than a finished run's files, the run continued in it.
mnt = os.path.abspath("tmpfs")
os.makedirs(mnt, exist_ok=True)
used = sum(-(-size(os.path.join("ref_h5_1", f)) // 4096) * 4096 for f in os.listdir("ref_h5_1"))
mount = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%dk" % (used // 1024 + 64), "tmpfs", mnt], capture_output=True, text=True)
if mount.returncode != 0:
    print("skipped: the full-disk part needs a tmpfs, and mounting one was refused here (%s)" % (mount.stderr.strip() or mount.returncode))
    sys.exit(0)
try:
    for n in (1, 2):
        cases = (("a snapshot", HDF5, "snapshot_"), ("monitor.csv", ["-monitor_dt", 0, "-output_interval", 0, "-checkpoint_interval", 0], "monitor.csv"))
        for what, args, name in cases:
            label, out = "%d rank(s), full disk at %s" % (n, what), os.path.join(mnt, "run")
            shutil.rmtree(out, ignore_errors=True)
            shutil.copytree("ref_h5_%d" % n, out)
            before = open(out + "/checkpoint.h5", "rb").read()
            p = run(args + ["-t_final", 0.05, "-restart", out + "/checkpoint.h5"], n, out, clean=False)
            check_failed(p, label, name, NO_SPACE)
            t.check(open(out + "/checkpoint.h5", "rb").read() == before, "%s: checkpoint.h5 unchanged" % label)
            no_temporaries(out, label)
            check_rows(out + "/monitor.csv", label)
            run(["-t_final", 0.0105, "-restart", out + "/checkpoint.h5"], n, "resume_full_%d" % n, expect_fail=False)
            t.check(t.summary("resume_full_%d" % n)["steps"] > t.summary("ref_h5_%d" % n)["steps"],
                    "%s: the kept checkpoint loads with -restart" % label)
            shutil.rmtree(out)
finally:
    subprocess.run(["umount", mnt])
