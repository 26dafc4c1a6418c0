"""-output_dir and -checkpoint_file are checked at start-up, on 1 and 2 ranks: a directory that cannot be created or
written in, or a checkpoint file whose directory does not exist or takes no file, ends the run before it starts with
exit status 3 and one line naming the option and the reason; no traceback, no rank left waiting.

The unwritable paths lie under a regular file, which refuses them whoever runs the test; a directory without write
permission is tried as well when the test does not run as root (root writes there anyway)."""
import os
import stat
import subprocess

from fluidbed_tools import testing as t

SCENE = ["-insert_count", 100, "-max_steps", 20]
CRASH = ("PETSC ERROR", "Segmentation", "Caught signal", "core dumped", "Traceback")

afile = os.path.abspath("a_regular_file")
open(afile, "w").write("not a directory\n")
missing = os.path.abspath("no_such_directory")
cases = [
    (["-output_dir", afile + "/out"], "-output_dir", os.strerror(20)),  # ENOTDIR
    (["-output_dir", afile], "-output_dir", os.strerror(20)),
    (["-checkpoint_interval", 0.0001, "-checkpoint_file", missing + "/ck.h5"], "-checkpoint_file", os.strerror(2)),  # ENOENT
    (["-checkpoint_interval", 0.0001, "-checkpoint_file", afile + "/ck.h5"], "-checkpoint_file", os.strerror(20)),
]
if os.geteuid() != 0:
    locked = os.path.abspath("locked")
    os.makedirs(locked, exist_ok=True)
    os.chmod(locked, stat.S_IRUSR | stat.S_IXUSR)  # 0500
    cases += [(["-output_dir", locked], "-output_dir", os.strerror(13)),  # EACCES
              (["-checkpoint_interval", 0.0001, "-checkpoint_file", locked + "/ck.h5"], "-checkpoint_file", os.strerror(13))]
else:
    print("note: running as root, where a directory's permissions do not stop writes: the mode 0500 cases are left out")

for n in (1, 2):
    for args, option, reason in cases:
        # the output directory given explicitly last wins over the one testing.run passes
        try:
            _, p = t.run(None, args=SCENE + args, nprocs=n, outdir="paths_out", expect_fail=True, timeout=60)
        except subprocess.TimeoutExpired:
            t.fail("%d rank(s) %s: no exit within 60 s" % (n, " ".join(map(str, args))))
        text = p.stdout + p.stderr
        errors = [line for line in text.splitlines() if line.startswith("fluidbed: error:")]
        crash = [s for s in CRASH if s in text]
        t.check(p.returncode == 3 and errors and option in errors[0] and reason in errors[0] and not crash and "Running" not in p.stdout,
                "%d rank(s) %s: exit %d, %s" % (n, " ".join(map(str, args)), p.returncode, errors[0] if errors else "(no error line)"))
    # -checkpoint_file is only checked when checkpoints are written
    _, p = t.run(None, args=SCENE + ["-checkpoint_file", missing + "/ck.h5"], nprocs=n, outdir="paths_ok", timeout=60)
    t.check(p.returncode == 0 and not os.path.exists(missing), "%d rank(s): without -checkpoint_interval an unusable -checkpoint_file is not an error" % n)
    # a directory that does not exist yet is created, with its parents, and holds no probe file afterwards
    deep = os.path.abspath("made/by/the/run_%d" % n)
    _, p = t.run(None, args=SCENE, nprocs=n, outdir=deep, timeout=60)
    t.check(sorted(os.listdir(deep)) == ["monitor.csv", "particles.csv", "summary.json"],
            "%d rank(s): a new nested -output_dir is created and holds only the run's files: %s" % (n, sorted(os.listdir(deep))))
