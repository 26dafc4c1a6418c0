"""Per-phase wall times: summary.json's wall_time_phase_max_over_ranks gives each phase its own time, as -log_view's
stages do, also where one phase runs inside another (the particles' drag, a coupling phase, is added inside the
contact phase). On one rank each phase's summary time is its -log_view stage time (within 2% and 5 ms: the two clocks
are read a few calls apart), and the phases add up to no more than the run's wall time.

A small coupled bed (examples/coupling/small_bed.opts, 3000 particles, the drag added every step): 0.02 s of bed."""
import re

from fluidbed_tools import testing as t

out, p = t.run(t.example("coupling/small_bed.opts"), args=["-t_final", 0.02, "-couple_substeps", 1, "-log_view"], outdir="phases")
s = t.summary(out)
phases = s["wall_time_phase_max_over_ranks"]
stages = {}
for m in re.finditer(r"^\s*\d+:\s+([A-Za-z ]+?):\s+([0-9.eE+-]+)\s+[0-9.]+%", p.stdout, re.M):
    stages[m.group(1).strip()] = float(m.group(2))
names = {"neighbour": "Neighbour search", "contact": "Contact", "integrate": "Integrate", "migrate": "Migrate", "ghosts": "Ghosts",
         "fluid": "Fluid", "pressure": "Pressure", "coupling": "Coupling", "guards": "Guards"}
t.check(phases["coupling"] > 0 and phases["contact"] > 0, "the run timed contact (%.4f s) and coupling (%.4f s)" % (phases["contact"], phases["coupling"]))
for key, stage in names.items():
    t.check(stage in stages, "-log_view has the stage '%s'" % stage)
    a, b = phases[key], stages[stage]
    t.check(abs(a - b) <= 0.02 * b + 0.005, "%s: %.4f s in summary.json, %.4f s in -log_view" % (key, a, b))
total = sum(phases.values())
t.check(total <= s["wall_time_run"] + s.get("wall_time_setup", 0) + 0.01,
        "the phases add up to %.4f s, the run took %.4f s (set-up %.4f s)" % (total, s["wall_time_run"], s.get("wall_time_setup", 0)))
