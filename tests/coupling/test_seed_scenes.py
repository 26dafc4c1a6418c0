"""The seed's beds as scenes (issue: every bed of the seed a runnable scene). Each examples/*.opts scene takes two
steps; its printed set-up is checked against the seed's tables: particle count, superficial gas velocity over the
bottom (within 1%: slits are whole fluid cells, 1.611 instead of 1.6 mm), the contact time t_cr of eq. 3.2-3.3
computed here from the scene's particles, and, where the seed quotes it, t_cr itself (Table 5.1 beds: 5.838e-5 s)."""
import math
import re

from fluidbed_tools import reference
from fluidbed_tools import testing as t

# scene: (particles, superficial velocity m/s, diameter m, density kg/m^3, e, t_cr quoted by the seed or None)
SCENES = {
    "muller_bed_u060": (9240, 0.6, 1.2e-3, 1000, 0.98, None),  # Table 2.1
    "muller_bed_u090": (9240, 0.9, 1.2e-3, 1000, 0.98, None),
    "tsuji_jet": (2400, 2.6, 4.0e-3, 2700, 0.90, None),  # Table 2.2
    "spouted_550_jet1_u160": (100000, 0.388, 5.5e-4, 2500, 0.90, None),  # Table 3.1
    "spouted_550_jet1_u301": (100000, 0.725, 5.5e-4, 2500, 0.90, None),
    "spouted_550_jet2_u301": (100000, 0.725, 5.5e-4, 2500, 0.90, None),
    "spouted_550_jet3_u301": (100000, 0.725, 5.5e-4, 2500, 0.90, None),
    "spouted_550_jet2_u160": (100000, 0.388, 5.5e-4, 2500, 0.90, None),  # Table 3.5
    "spouted_550_jet3_u160": (100000, 0.388, 5.5e-4, 2500, 0.90, None),
    "twogrid_750_jet1_u160": (50000, 0.688, 7.5e-4, 2500, 0.90, 5.838e-5),  # Table 5.1
    "twogrid_750_jet1_u301": (50000, 1.294, 7.5e-4, 2500, 0.90, 5.838e-5),
    "twogrid_750_jet1_u301_wallmu050": (50000, 1.294, 7.5e-4, 2500, 0.90, 5.838e-5),
    "twogrid_750_jet1_u301_wallmu050_coarse": (50000, 1.294, 7.5e-4, 2500, 0.90, 5.838e-5),  # grid sensitivity, Fig. 5.15
    "twogrid_750_jet2_u301": (50000, 1.294, 7.5e-4, 2500, 0.90, 5.838e-5),
    "twogrid_750_jet3_u301": (50000, 1.294, 7.5e-4, 2500, 0.90, 5.838e-5),
    "ninejet_2d": (126864, 0.315, 5.5e-4, 2500, 0.90, None),  # Table 4.1, 4.3
}
KN = 800.0  # N/m, every table


def t_cr(d, rho, e):
    """Seed eq. 3.2-3.3 for a pair of equal spheres."""
    return reference.contact_time(KN, e, 0.5 * rho * math.pi / 6 * d**3)


def number(pattern, text, what):
    m = re.search(pattern, text)
    t.check(m is not None, "%s printed" % what)
    return float(m.group(1))


for scene, (count, U, d, rho, e, quoted) in SCENES.items():
    out, p = t.run(t.example(scene + ".opts"),
                   args=["-max_steps", 2, "-output_interval", 0, "-checkpoint_interval", 0, "-output_particles", 0,
                         "-fluid_output_cells", 0], outdir="scene_" + scene)
    text = p.stdout
    n = number(r"Particles: (\d+) inserted", text, scene + ": particle count")
    u = number(r"\(([0-9.e+-]+) m/s superficial over the bottom\)", text, scene + ": superficial velocity")
    tc = number(r"DEM: t_cr ([0-9.e+-]+) s \(particle pair\)", text, scene + ": t_cr")
    done = number(r"Done: \d+ steps, t = [0-9.e+-]+ s, (\d+) particles", text, scene + ": particles after two steps")
    t.check(n == count, "%s: %d particles (table: %d)" % (scene, n, count))
    t.check(done == count, "%s: %d particles after two steps" % (scene, done))
    t.check(abs(u / U - 1) <= 0.01, "%s: superficial velocity %.4f m/s (table %.4g, %+.2f%%, limit 1%%)" % (scene, u, U, 100 * (u / U - 1)))
    ref = t_cr(d, rho, e)
    t.check(abs(tc / ref - 1) <= 1e-3, "%s: t_cr %.5g s (eq. 3.2-3.3: %.5g s)" % (scene, tc, ref))
    if quoted:
        t.check(abs(tc / quoted - 1) <= 1e-3, "%s: t_cr %.5g s (seed: %.5g s, %+.3f%%)" % (scene, tc, quoted, 100 * (tc / quoted - 1)))
