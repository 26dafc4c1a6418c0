"""Run outputs: summary.json carries steps, simulated time, dt, particle count, wall time per phase,
particle-steps per second per rank and the run's processor time (positive, and at most its wall time on one rank,
with 10 ms for the clocks' ticks); monitor.csv has the global quantities; -log_view has a stage per phase;
long runs print progress lines."""
import os

from fluidbed_tools import testing as t

out, p = t.run(None, args=["-t_final", 0.02, "-insert_count", 500, "-log_view"], outdir="outputs")
s = t.summary(out)
for key in ("steps", "time", "dt", "t_cr", "particles", "ranks", "wall_time_run", "wall_time_phase_max_over_ranks", "particle_steps_per_second_per_rank"):
    t.check(key in s, "summary.json has %s = %s" % (key, s.get(key)))
cpu = s.get("cpu_time_run_sum_over_ranks", -1)
t.check(0 < cpu <= s["wall_time_run"] * s["ranks"] + 0.01, "processor time %.3f s against %.3f s of wall time on %d rank(s)" % (cpu, s["wall_time_run"], s["ranks"]))
t.check(s["particles"] == 500 and t.rel(s["steps"] * s["dt"], s["time"]) < 1e-9, "summary: %d particles, %d steps x dt = time" % (s["particles"], s["steps"]))
for phase in ("neighbour", "contact", "integrate", "migrate", "ghosts"):
    t.check(phase in s["wall_time_phase_max_over_ranks"], "summary.json times the %s phase: %.4f s" % (phase, s["wall_time_phase_max_over_ranks"][phase]))
mon = t.table(os.path.join(out, "monitor.csv"))
for col in ("time", "particles", "ke_trans", "ke_rot", "max_overlap_rel", "contacts_per_particle"):
    t.check(col in mon, "monitor.csv has column %s" % col)
for stage in ("Neighbour search", "Contact", "Integrate", "Migrate", "Ghosts"):
    t.check(stage + ":" in p.stdout, "-log_view lists the stage '%s'" % stage)
_, p = t.run(None, args=["-t_final", 0.02, "-insert_count", 500, "-progress_interval", 1e-9], outdir="outputs_progress")
progress = [line for line in p.stdout.splitlines() if "elapsed" in line and "left" in line]
t.check(len(progress) > 0, "progress lines printed: e.g. '%s'" % (progress[0].strip() if progress else ""))
