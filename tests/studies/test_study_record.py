"""A study's record of each point (fluidbed_tools.study.run, run.finished_run): written before the run without an
exit status and completed after it, so that a point whose run outlived its driver (the driver killed, the run going on
to write its summary.json) is found finished and reused with the run's own exit status and wall time, while a point
whose run never ended (no summary.json) is run again; a finished point is reused; another command is not."""
import json
import os
import shutil

from fluidbed_tools import run, study
from fluidbed_tools import testing as t

args = ["-options_file", t.example("dem/bounce_e090.opts"), "-t_final", 0.01]
out = os.path.abspath("study_record")
if os.path.isdir(out):
    shutil.rmtree(out)
s, status, wall, reused = study.run(args, out, 1, t.EXE)
meta = json.load(open(os.path.join(out, "command.json")))
t.check(s is not None and status == 0 and not reused and meta["exit_status"] == 0 and meta["wall_s"] > 0,
        "a fresh point runs and completes its record: exit %s, %.2f s" % (meta["exit_status"], meta["wall_s"]))
s2, status2, _, reused2 = study.run(args, out, 1, t.EXE)
t.check(reused2 and status2 == 0 and s2["time"] == s["time"], "run again, the finished point is reused")

# the driver stopped before the run ended: the record has no exit status, the run wrote its summary.json
json.dump(dict(meta, exit_status=None, wall_s=None), open(os.path.join(out, "command.json"), "w"))
cmd = run.point_command(args, out, 1, t.EXE)
t.check(run.finished_run(out, cmd[cmd.index(t.EXE):]), "a record without an exit status and a summary.json: finished")
s3, status3, wall3, reused3 = study.run(args, out, 1, t.EXE)
t.check(reused3 and status3 == s["exit_code"] and abs(wall3 - (s["wall_time_setup"] + s["wall_time_run"])) < 1e-9,
        "reused with the run's own exit status %d and wall time %.3f s" % (status3, wall3))
other = run.point_command(args[:-1] + [0.02], out, 1, t.EXE)
t.check(not run.finished_run(out, other[other.index(t.EXE):]), "another -t_final is another point")

# the run never ended: no summary.json, so the point is run again
json.dump(dict(meta, exit_status=None, wall_s=None), open(os.path.join(out, "command.json"), "w"))
os.remove(os.path.join(out, "summary.json"))
t.check(not run.finished_run(out, cmd[cmd.index(t.EXE):]), "a record without an exit status and no summary.json: not finished")
s4, status4, _, reused4 = study.run(args, out, 1, t.EXE)
t.check(not reused4 and status4 == 0 and json.load(open(os.path.join(out, "command.json")))["exit_status"] == 0, "so it runs again")
print("ok")
