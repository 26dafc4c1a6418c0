"""The batch path of scripts/strong_scaling.py for real: starts a single-node SLURM (Debian slurm-wlm and munge)
configured in a temporary directory (slurm.conf with this host's name and CPU count, a munge key and socket of its
own, slurmctld and slurmd in the foreground as the current user, spool and state directories in the temporary
directory), submits the two-rank study of the 2D jetted bed through sbatch (--batch slurm --submit --wait), checks
its table (two rows, positive times, efficiency in (0, 1.5]) and shuts SLURM down. Where the packages are missing or
SLURM cannot start, it says why and exits with status 77, which ctest counts as skipped (SKIP_RETURN_CODE)."""
import csv
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

from fluidbed_tools import testing as t

SKIP = 77
procs = []


def skip(why):
    print("SKIP: " + why)
    stop()
    sys.exit(SKIP)


def stop():
    """Stops the daemons this test started (its own child processes, by their ids)."""
    for p in reversed(procs):
        if p.poll() is None:
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
    procs.clear()


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(cmd, log):
    p = subprocess.Popen(cmd, stdout=open(log, "w"), stderr=subprocess.STDOUT, env=env)
    procs.append(p)
    return p


def wait_for(check, seconds):
    t0 = time.time()
    while time.time() - t0 < seconds:
        if check():
            return True
        time.sleep(0.3)
    return False


missing = [x for x in ("munged", "mungekey", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo") if not shutil.which(x)]
if missing:
    print("SKIP: slurm-wlm and munge are not installed (missing %s; scripts/setup.sh installs them with "
          "FLUIDBED_WITH_TEST_PACKAGES=1)" % ", ".join(missing))
    sys.exit(SKIP)

tmp = tempfile.mkdtemp(prefix="fbslurm_")
host = socket.gethostname().split(".")[0]
cpus = os.cpu_count() or 1
env = dict(os.environ, SLURM_CONF=os.path.join(tmp, "slurm.conf"))
try:
    for d in ("state", "spool", "munge"):
        os.makedirs(os.path.join(tmp, d), mode=0o700)
    key = os.path.join(tmp, "munge", "munge.key")
    sock = os.path.join(tmp, "munge", "munge.socket")
    p = subprocess.run(["mungekey", "--create", "--keyfile", key], capture_output=True, text=True)
    if p.returncode != 0:
        skip("mungekey could not make a key: " + p.stderr.strip())
    os.chmod(key, 0o400)
    munged = start(["munged", "-F", "-f", "--socket", sock, "--key-file", key, "--pid-file", os.path.join(tmp, "munge", "munged.pid"),
                    "--log-file", os.path.join(tmp, "munge", "munged.log"), "--seed-file", os.path.join(tmp, "munge", "seed")],
                   os.path.join(tmp, "munged.out"))
    if not wait_for(lambda: os.path.exists(sock) or munged.poll() is not None, 10) or munged.poll() is not None:
        skip("munged did not start: " + open(os.path.join(tmp, "munged.out")).read()[-500:])
    user = subprocess.run(["id", "-un"], capture_output=True, text=True).stdout.strip()
    conf = """ClusterName=fbtest
SlurmctldHost={host}
SlurmUser={user}
SlurmdUser={user}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={sock}
SlurmctldPort={p1}
SlurmdPort={p2}
StateSaveLocation={tmp}/state
SlurmdSpoolDir={tmp}/spool
SlurmctldPidFile={tmp}/slurmctld.pid
SlurmdPidFile={tmp}/slurmd.pid
SlurmctldLogFile={tmp}/slurmctld.log
SlurmdLogFile={tmp}/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName={host} CPUs={cpus} State=UNKNOWN
PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP OverSubscribe=FORCE
""".format(host=host, user=user, sock=sock, p1=free_port(), p2=free_port(), tmp=tmp, cpus=cpus)
    with open(env["SLURM_CONF"], "w") as f:
        f.write(conf)
    ctld = start(["slurmctld", "-D", "-i", "-f", env["SLURM_CONF"]], os.path.join(tmp, "slurmctld.out"))
    slurmd = start(["slurmd", "-D", "-f", env["SLURM_CONF"], "-N", host], os.path.join(tmp, "slurmd.out"))

    def idle():
        if ctld.poll() is not None or slurmd.poll() is not None:
            return True
        p = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, env=env)
        return p.returncode == 0 and p.stdout.strip() in ("idle", "mixed")

    ok = wait_for(idle, 40)
    if not ok or ctld.poll() is not None or slurmd.poll() is not None:
        logs = ""
        for name in ("slurmctld.out", "slurmctld.log", "slurmd.out", "slurmd.log"):
            path = os.path.join(tmp, name)
            if os.path.exists(path):
                logs += "\n--- %s\n%s" % (name, open(path).read()[-800:])
        skip("SLURM did not come up (slurmctld %s, slurmd %s)%s" % ("running" if ctld.poll() is None else "exited",
                                                                    "running" if slurmd.poll() is None else "exited", logs))
    print("ok:   single-node SLURM up on %s with %d CPUs (%s)" % (host, cpus, tmp))

    out = os.path.join(tmp, "study")
    cmd = [sys.executable, os.path.join(t.SRC, "scripts", "strong_scaling.py"), "--scene", t.example("jetted_bed_2d.opts"), "--ranks", "1,2",
           "--steps", "40", "--out", out, "--exe", t.EXE, "--batch", "slurm", "--submit", "--wait", "70", "--launcher", "mpiexec",
           "--minutes", "5"]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
    print(p.stdout[-2500:], p.stderr[-2500:])
    t.check(p.returncode == 0, "strong_scaling.py --batch slurm --submit --wait ran (exit %d)" % p.returncode)
    t.check("submitted as job" in p.stdout, "the jobs went through sbatch")
    job = open(os.path.join(out, "np2", "job.sbatch")).read()
    t.check("#SBATCH --ntasks=2" in job and "#SBATCH --nodes=1" in job, "the two-rank script asks for 2 tasks on 1 node")
    rows = list(csv.DictReader(open(os.path.join(out, "scaling.csv"))))
    t.check(len(rows) == 2 and [r["ranks"] for r in rows] == ["1", "2"], "the table has the rows of 1 and 2 ranks")
    for r in rows:
        t.check(float(r["step_s"]) > 0 and float(r["contact_s"]) > 0 and float(r["pressure_s"]) > 0,
                "%s ranks: %.3g s per step, contact %.3g s, pressure %.3g s" % (r["ranks"], float(r["step_s"]), float(r["contact_s"]),
                                                                              float(r["pressure_s"])))
        t.check(0 < float(r["efficiency"]) <= 1.5, "%s ranks: efficiency %s in (0, 1.5]" % (r["ranks"], r["efficiency"]))
    t.check(rows[1]["process_grid"] == "2x1x1", "two ranks split x (process grid %s)" % rows[1]["process_grid"])
    t.check(os.path.isfile(os.path.join(out, "np2", "load_before.txt")), "the job recorded /proc/loadavg")
finally:
    stop()
    shutil.rmtree(tmp, ignore_errors=True)
