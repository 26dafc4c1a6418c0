"""The input side of scripts/bench_peers.py, without LAMMPS or LIGGGHTS: the parameter mapping (gamma_n from e
reproduces fluidbed's t_cr and e, for pairs with m_eff = m/2 and for walls with m_eff = m; the pair's gamma at a
wall would give about 0.86), the time step against fluidbed's own, the data file the peers read (positions,
velocities and spins of a fluidbed particles.csv round-trip bit for bit, ids + 1), the peers' inputs (the mapped
numbers, y vertical, the process grid that never splits y), the log and dump readers, the contact recount and the
physics check that makes the benchmark fail. No timing: speed targets live in the benchmark."""
import math
import os

import numpy as np

import bench_peers as bp
from fluidbed_tools import reference
from fluidbed_tools import testing as t

# --- the contact law: 0.75 mm glass, k_n 800 N/m, e 0.9 (docs/dem.md, /work/shared/peer-benchmarks.md) ---
p = bp.bed_params(t.example("dem/bed750.opts"))
m = p["mass"]
t.check(abs(p["gamma_n"] - 3608.38) < 0.01, "pair gamma_n = %.2f 1/s (3608.38 expected)" % p["gamma_n"])
t.check(p["gamma_t"] == p["gamma_n"], "gamma_t = gamma_n (k_t = k_n, one damping ratio)")
t.check(abs(p["t_cr"] - 5.840e-5) < 0.0005e-5, "t_cr = %.4e s (5.840e-5)" % p["t_cr"])
zeta = reference.damping_ratio(0.9)
t_cr_fluidbed = reference.contact_time(800, 0.9, m / 2)  # docs/dem.md eq. 3.2
t.check(t.rel(p["t_cr"], t_cr_fluidbed) < 1e-12, "the peers' contact duration is fluidbed's eq. 3.2 (rel. %.1e)" % t.rel(p["t_cr"], t_cr_fluidbed))
e_pair = bp.restitution(800, p["gamma_n"], m / 2)
e_wall = bp.restitution(800, p["wall_gamma_n"], m)
e_wall_pair_gamma = bp.restitution(800, p["gamma_n"], m)
t.check(abs(e_pair - 0.9) < 1e-12 and abs(e_wall - 0.9) < 1e-12, "restitution %.12f between particles, %.12f at a wall (0.9)" % (e_pair, e_wall))
t.check(abs(p["wall_gamma_n"] * math.sqrt(2) - p["gamma_n"]) < 1e-9, "wall gamma_n = pair gamma_n / sqrt(2) = %.2f 1/s" % p["wall_gamma_n"])
t.check(0.85 < e_wall_pair_gamma < 0.87, "the pair's gamma at a wall (m_eff = m) would give e = %.3f" % e_wall_pair_gamma)
# the force the peers apply, m_eff gamma v, is fluidbed's eta v with eta = 2 zeta sqrt(m_eff k)
t.check(t.rel(m / 2 * p["gamma_n"], 2 * zeta * math.sqrt(m / 2 * 800)) < 1e-12, "m_eff gamma_n = fluidbed's eta_n")

# --- the time step and contact durations against fluidbed's, on a few particles of the same glass ---
pos = [0.001, 0.0004, 0.001, 0.0018, 0.0004, 0.001, 0.001, 0.00112, 0.001, 0.0035, 0.003, 0.0035]
out, _ = t.run(None, args=["-domain_lx", "0.005", "-domain_ly", "0.005", "-domain_lz", "0.005", "-particle_diameter", "7.5e-4",
                           "-particle_density", "2500", "-dem_kn", "800", "-dem_e", "0.9", "-dem_mu", "0.1", "-dem_dt_factor", "0.1",
                           "-insert_type", "list", "-insert_positions", ",".join(map(str, pos)),
                           "-insert_velocities", "0.01,-0.02,0.003,0,0,0,-0.001,0.002,0,0.05,0.01,-0.04",
                           "-insert_omegas", "1,2,3,0,0,0,-4,5,-6,0.5,0,0", "-max_steps", "3"], outdir="peers_small")
s = t.summary(out)
t.check(t.rel(p["dt"], s["dt"]) < 1e-9 and t.rel(p["t_cr_wall"], s["t_cr_wall"]) < 1e-9,
        "dt %.10e s and wall t_cr %.6e s as fluidbed's (%.10e, %.6e)" % (p["dt"], p["t_cr_wall"], s["dt"], s["t_cr_wall"]))

# --- the data file: fluidbed's particles.csv in, the same doubles out ---
parts = bp.read_particles_csv(os.path.join(out, "particles.csv"))
data = os.path.join(out, "test.data")
bp.write_data(data, parts, [0.005, 0.005, 0.005], 2500.0, "test")
back = bp.read_data(data)
same = all(np.array_equal(parts[c], back[c]) for c in ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "d"))
t.check(same and np.array_equal(back["id"], parts["id"]), "data file round-trips positions, velocities, spins, diameters and ids of %d particles bit for bit"
        % len(parts["x"]))
text = open(data).read().splitlines()
first_atom = text[text.index("Atoms") + 2].split()
t.check("4 atoms" in text and "2 atom types" in text and "0 0.005 ylo yhi" in text and first_atom[:4] == ["1", "1", "0.00075", "2500.0"],
        "header (atoms, 2 types, box) and Atoms rows 'id type diameter density x y z' with ids from 1: %s" % " ".join(first_atom))
rng = np.random.default_rng(3)
many = {c: rng.uniform(-1, 1, 1000) * 10.0 ** rng.integers(-9, 2, 1000) for c in ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz")}
many["d"] = np.full(1000, 7.5e-4)
many["id"] = rng.permutation(1000).astype(float)
bp.write_data(data, many, [1, 1, 1], 2500.0, "random")
back = bp.read_data(data)
order = np.argsort(many["id"])
t.check(all(np.array_equal(many[c][order], back[c]) for c in ("x", "y", "vz", "wx")), "1000 random doubles over 11 decades round-trip bit for bit")

# --- the peers' inputs ---
px, pz = bp.split(2, p["box"])
t.check((px, pz) == (2, 1), "thin bed on 2 ranks: process grid %d x 1 x %d (x split, y never)" % (px, pz))
wide = bp.bed_params(t.example("dem/bed_wide.opts"))
t.check(bp.split(2, wide["box"]) == (2, 1) and bp.split(4, wide["box"]) == (2, 2), "wide bed: 2 x 1 x 1 on 2 ranks, 2 x 1 x 2 on 4")
lmp = bp.lammps_input(p, "x.data", 500, 2000, 2, 1, 0.1, "final.dump").splitlines()
want = "pair_style gran/hooke/history 800 800 %.10g %.10g 0.1 1" % (p["gamma_n"], p["gamma_t"])
t.check(want in lmp, "LAMMPS: %s" % want)
t.check("fix wall_y all wall/gran hooke/history 800 800 %.10g %.10g 0.1 1 yplane 0.0 0.28" % (p["wall_gamma_n"], p["wall_gamma_t"]) in lmp,
        "LAMMPS: the walls' own gamma (m_eff = m), y plane 0..0.28 m")
t.check("timestep %r" % p["dt"] in lmp and "fix gravity all gravity 9.81 vector 0.0 -1.0 0.0" in lmp and "processors 2 1 1" in lmp
        and "neighbor 7.5e-05 bin" in lmp and "neigh_modify delay 0 every 1 check yes" in lmp and lmp.index("run 500") < lmp.index("run 2000"),
        "LAMMPS: dt, gravity along -y, processors 2 1 1, skin 0.1 d checked every step, warm-up before the timed run")
lig = bp.liggghts_input(p, "x.data", 500, 2000, 2, 1, 0.1, "final.dump").splitlines()
t.check("fix m3 all property/global gamman peratomtypepair 2 %.10g %.10g %.10g %.10g" % ((p["gamma_n"],) + (p["wall_gamma_n"],) * 3) in lig
        and sum(1 for s in lig if "wall/gran" in s and "primitive type 2" in s) == 6 and "newton off" in lig,
        "LIGGGHTS: per-type-pair gamma_n (particles 1, walls 2), six wall planes of type 2, newton off")

# --- the readers: a peer's log and dump ---
log = """Loop time of 3.5 on 1 procs for 500 steps with 50000 atoms
Neighbor list builds = 4
Step Atoms KinEng c_rot c_contacts_sum
     500    50000 1e-9 2e-10 260000
    2500    50000 1e-9 2e-10 265000
Loop time of 14.0 on 2 procs for 2000 steps with 50000 atoms

Neighbor list builds = 1
Dangerous builds = 0
"""
r = bp.parse_peer_log(log, 500)
t.check(r["loop_s"] == 14.0 and r["ranks"] == 2 and r["steps"] == 2000 and r["rebuilds"] == 1 and r["own_contacts_per_particle"] == 5.3,
        "peer log: the timed run's loop time, ranks, steps, rebuilds (%s) and contacts (%s per particle)" % (r["rebuilds"], r["own_contacts_per_particle"]))
dump = os.path.join(out, "x.dump")
with open(dump, "w") as f:
    f.write("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: ATOMS id x y z vx vy vz omegax omegay omegaz radius\n")
    f.write("2 0.1 0.2 0.3 1 2 3 4 5 6 0.000375\n1 0.4 0.5 0.6 7 8 9 10 11 12 0.000375\n")
dd = bp.read_dump(dump)
t.check(list(dd["id"]) == [0, 1] and list(dd["y"]) == [0.5, 0.2] and list(dd["wz"]) == [12, 6] and dd["d"][0] == 7.5e-4,
        "dump: sorted by id, ids back to fluidbed's, omega and diameter read")

# --- the contact recount and the physics check ---
x = rng.uniform(0, 0.01, (3000, 3))
dm = np.full(3000, 7.5e-4)
pairs, _ = bp.pair_contacts(x, dm, [0.01] * 3)
dist = np.sqrt(((x[:, None, :] - x[None, :, :]) ** 2).sum(-1))
brute = int((np.triu(dist < 7.5e-4, 1)).sum())
t.check(pairs == brute, "cell-list recount of overlapping pairs = brute force (%d pairs among 3000)" % pairs)
state = bp.bed_state(parts, p)
t.check(state["particles"] == 4 and abs(state["y_mean_d"] - np.mean(parts["y"]) / 7.5e-4) < 1e-12, "bed state: %s" % state)
rest = {"particles": 10, "ke_per_particle_mgd": 1e-6, "y_mean_d": 20.0, "contacts_per_particle": 5.2, "wall_contacts_per_particle": 0.1,
        "max_overlap_d": 1e-3}
rec = {c: {"state": dict(rest)} for c in bp.CODES}
t.check(bp.check_physics("bed", p, 10, rec) == [], "three beds at rest in the same place agree")
rec["liggghts"]["state"].update(ke_per_particle_mgd=0.5, y_mean_d=21.0)
fails = bp.check_physics("bed", p, 10, rec)
t.check(len(fails) == 2 and all("liggghts" in f for f in fails), "a bed that moves and lifts off fails the check: %s" % fails)
