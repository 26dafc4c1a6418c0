#!/usr/bin/env python3
"""DEM side by side: fluidbed, LAMMPS (lmp) and LIGGGHTS (liggghts) on the same settled particles, with the same
contact law, parameters, time step and neighbour-list policy (scripts/bench_peers.sh drives it; docs/performance.md
"DEM against LAMMPS and LIGGGHTS" has the results).

For each bed (an examples/dem options file and the particles.csv fluidbed settled it to):
  1. the settled positions, velocities and spins go into one LAMMPS data file that both peers read (ids + 1, y
     vertical as in fluidbed, gravity along -y);
  2. every code runs --warmup steps from them, then --steps timed steps: fluidbed warms up once (on the largest
     rank count) into a checkpoint, contact history included, that each timed fluidbed run restarts from (exactly
     the state an uninterrupted run would have); a peer runs its warm-up in the timed process (one "run" each);
  3. each repetition times every code on each rank count, the three codes interleaved (the order rotates between
     repetitions), with the load (/proc/loadavg) and the processes' CPU share recorded for every run;
  4. after every timed run the final state of each code is analysed the same way (kinetic energy, mean height,
     contacts per particle recounted from the positions) and compared with fluidbed's: a bed that moved or flew
     apart in one code makes the benchmark fail (exit status 1), as does any failed run.

Timings: fluidbed's summary.json wall_time_run (the step loop, set-up and final files excluded); the peers'
"Loop time of T on P procs for S steps with N atoms" (set-up excluded). Particle-steps per second per core =
N S / (T P).

The parameter mapping (docs/dem.md has fluidbed's law): fluidbed takes k_n, k_t, e and mu and derives
eta = 2 zeta sqrt(m_eff k) with zeta = -ln e / sqrt(pi^2 + ln^2 e), m_eff = m_i m_j / (m_i + m_j) for a pair and
m_eff = m against a wall. LAMMPS's gran/hooke/history and LIGGGHTS's hooke/stiffness take a damping rate
gamma with force m_eff gamma v, so gamma = 2 zeta sqrt(k / m_eff): for the pairs gamma_n = gamma_t (k_t = k_n, the
same damping ratio in both directions, as fluidbed) from m_eff = m/2; both peers use m_eff = m at a wall, so the
wall's gamma is the pair's divided by sqrt(2) (a wall type of its own in LIGGGHTS), which gives the walls e as in
fluidbed instead of about 0.86.
"""
import argparse
import datetime
import json
import math
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np

from fluidbed_tools.reference import damping_ratio  # fluidbed's eq. 3.3 (docs/dem.md)
from fluidbed_tools.run import ROOT, machine

CODES = ("fluidbed", "lammps", "liggghts")
G = 9.81

# Agreement of the final states with fluidbed's (checked after every timed run). A settled bed barely moves in a
# few thousand steps: these catch a bed that slumps, explodes or lifts off, or a contact law that differs (a
# stiffer or softer bed changes the coordination and the height), not the last digits.
TOL = {
    "y_mean_d": 0.01,          # mean particle height (= centre of mass) within 0.01 d of fluidbed's
    "contacts_rel": 0.03,      # particle-pair contacts per particle within 3% of fluidbed's
    "ke_per_mgd": 1e-3,        # kinetic energy (translation + rotation) per particle below 1e-3 m g d: at rest
    "max_overlap_d": 0.02,     # largest overlap below 2% of d
}


# ---------------------------------------------------------------------------------------------------------------
# Scene and contact parameters



def common_tail():
    """The lines both peers' inputs end with: gravity, the integrator and the thermo output the results are read from."""
    return ["fix gravity all gravity %.10g vector 0.0 -1.0 0.0" % G,
            "fix integrate all nve/sphere",
            "compute rot all erotate/sphere",
            "compute contacts all contact/atom",
            "compute contacts_sum all reduce sum c_contacts",
            "thermo_style custom step atoms ke c_rot c_contacts_sum",
            "thermo_modify norm no"]

def read_opts(path):
    """An options file as {name: value} (the last occurrence wins, as in PETSc); comments and blank lines skipped."""
    opts = {}
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            parts = line.split(None, 1)
            opts[parts[0].lstrip("-")] = parts[1].strip() if len(parts) > 1 else ""
    return opts


def sphere_mass(d, rho):
    return rho * math.pi / 6.0 * d ** 3


def gamma_rate(k, e, m_eff):
    """The peers' damping rate: force m_eff gamma v with gamma = 2 zeta sqrt(k / m_eff) (1/s) damps a linear spring
    k on m_eff to restitution e, the same force as fluidbed's eta = 2 zeta sqrt(m_eff k)."""
    return 2.0 * damping_ratio(e) * math.sqrt(k / m_eff)


def contact_duration(k, gamma, m_eff):
    """Duration of a linear spring-dashpot contact, force -k delta - m_eff gamma v: pi / sqrt(k/m_eff - gamma^2/4)."""
    return math.pi / math.sqrt(k / m_eff - 0.25 * gamma * gamma)


def restitution(k, gamma, m_eff):
    """Normal restitution of that contact: exp(-gamma/2 t_c)."""
    return math.exp(-0.5 * gamma * contact_duration(k, gamma, m_eff))


def bed_params(opts_path):
    """Geometry and contact law of a bed, as fluidbed reads them from its options file and as the peers take them."""
    o = read_opts(opts_path)
    num = lambda name, default: float(o.get(name, default))
    d = num("particle_diameter", 1e-3)
    rho = num("particle_density", 2500.0)
    kn = num("dem_kn", 800.0)
    kt = num("dem_kt", -1.0)
    kt = kn if kt < 0 else kt
    e = num("dem_e", 0.9)
    mu = num("dem_mu", 0.3)
    wkn, wkt, we, wmu = (num("wall_" + s, -1.0) for s in ("kn", "kt", "e", "mu"))
    wkn = kn if wkn < 0 else wkn
    wkt = kt if wkt < 0 else wkt
    we = e if we < 0 else we
    wmu = mu if wmu < 0 else wmu
    m = sphere_mass(d, rho)
    pair_meff, wall_meff = m / 2.0, m
    p = {
        "box": [num("domain_lx", 0.02), num("domain_ly", 0.04), num("domain_lz", 0.02)],
        "d": d, "rho": rho, "mass": m, "kn": kn, "kt": kt, "e": e, "mu": mu,
        "wall_kn": wkn, "wall_kt": wkt, "wall_e": we, "wall_mu": wmu,
        # pair: m_eff = m/2; the peers' gamma_t multiplies m_eff v_t like gamma_n, so the same damping ratio
        # (fluidbed's eta_t = 2 zeta sqrt(m_eff k_t)) is gamma_t = 2 zeta sqrt(k_t / m_eff)
        "gamma_n": gamma_rate(kn, e, pair_meff), "gamma_t": gamma_rate(kt, e, pair_meff),
        # wall: the peers take m_eff = m (as fluidbed does); a gamma of its own keeps the wall's e
        "wall_gamma_n": gamma_rate(wkn, we, wall_meff), "wall_gamma_t": gamma_rate(wkt, we, wall_meff),
    }
    p["t_cr"] = contact_duration(kn, p["gamma_n"], pair_meff)
    p["t_cr_wall"] = contact_duration(wkn, p["wall_gamma_n"], wall_meff)
    p["dt"] = num("dem_dt_factor", 0.1) * min(p["t_cr"], p["t_cr_wall"])
    return p


# ---------------------------------------------------------------------------------------------------------------
# Particle files


def read_particles_csv(path):
    """fluidbed's particles.csv (or an -insert_file) as {column: numpy array}, sorted by id."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    cols = {n: np.atleast_1d(data[n]).astype(float) for n in data.dtype.names}
    if "d" not in cols and "diameter" in cols:
        cols["d"] = cols["diameter"]
    n = len(cols["x"])
    if "id" not in cols:
        cols["id"] = np.arange(n, dtype=float)
    for c in ("z", "vx", "vy", "vz", "wx", "wy", "wz"):
        cols.setdefault(c, np.zeros(n))
    order = np.argsort(cols["id"], kind="stable")
    return {k: v[order] for k, v in cols.items()}


def _g(x):
    return repr(float(x))  # the shortest text that reads back to the same double


def write_data(path, parts, box, rho, title):
    """A LAMMPS data file (atom_style sphere; LIGGGHTS's granular reads the same) of the particles: ids are
    fluidbed's + 1 (LAMMPS ids start at 1), type 1; type 2 is declared for LIGGGHTS's walls and holds no atoms.
    Positions and velocities are written to full precision, so they read back bit for bit."""
    n = len(parts["x"])
    lines = ["LAMMPS data file: %s" % title, "", "%d atoms" % n, "2 atom types", ""]
    for a, name in enumerate("xyz"):
        lines.append("0 %s %slo %shi" % (_g(box[a]), name, name))
    lines += ["", "Atoms", ""]
    for i in range(n):
        lines.append("%d 1 %s %s %s %s %s" % (int(parts["id"][i]) + 1, _g(parts["d"][i]), _g(rho), _g(parts["x"][i]), _g(parts["y"][i]),
                                            _g(parts["z"][i])))
    lines += ["", "Velocities", ""]
    for i in range(n):
        lines.append("%d %s" % (int(parts["id"][i]) + 1, " ".join(_g(parts[c][i]) for c in ("vx", "vy", "vz", "wx", "wy", "wz"))))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def read_data(path):
    """The Atoms and Velocities of a data file written by write_data, as particles.csv columns (ids back to 0-based)."""
    atoms, vels, section = {}, {}, None
    with open(path) as f:
        for line in f:
            s = line.split("#", 1)[0].strip()
            if not s:
                continue
            if s in ("Atoms", "Velocities"):
                section = s
                continue
            if section is None:
                continue
            w = s.split()
            if section == "Atoms":
                atoms[int(w[0])] = [float(v) for v in (w[2], w[3], w[4], w[5], w[6])]
            else:
                vels[int(w[0])] = [float(v) for v in w[1:7]]
    ids = sorted(atoms)
    a = np.array([atoms[i] for i in ids])
    v = np.array([vels.get(i, [0.0] * 6) for i in ids])
    out = {"id": np.array(ids, dtype=float) - 1, "d": a[:, 0], "rho": a[:, 1], "x": a[:, 2], "y": a[:, 3], "z": a[:, 4]}
    for k, c in enumerate(("vx", "vy", "vz", "wx", "wy", "wz")):
        out[c] = v[:, k]
    return out


def read_dump(path):
    """The last snapshot of a LAMMPS/LIGGGHTS text dump (id x y z vx vy vz omegax omegay omegaz [radius]) as
    particles.csv columns, sorted by id (ids back to 0-based)."""
    with open(path) as f:
        lines = f.read().splitlines()
    start = max(i for i, s in enumerate(lines) if s.startswith("ITEM: ATOMS"))
    names = lines[start].split()[2:]
    rows = np.array([[float(v) for v in s.split()] for s in lines[start + 1:] if s.strip()])
    col = {n: rows[:, k] for k, n in enumerate(names)}
    out = {"id": col["id"] - 1, "x": col["x"], "y": col["y"], "z": col["z"], "vx": col["vx"], "vy": col["vy"], "vz": col["vz"],
           "wx": col["omegax"], "wy": col["omegay"], "wz": col["omegaz"]}
    if "radius" in col:
        out["d"] = 2.0 * col["radius"]
    order = np.argsort(out["id"], kind="stable")
    return {k: v[order] for k, v in out.items()}


# ---------------------------------------------------------------------------------------------------------------
# The same analysis of every code's final state


def pair_contacts(x, d, box):
    """Particle pairs closer than the sum of their radii (overlapping), from positions only: the number of such
    pairs and the largest overlap (m). A cell list of the largest diameter."""
    n = len(x)
    h = float(np.max(d))
    lo = np.min(x, axis=0)
    ncell = np.maximum(1, np.floor((np.max(x, axis=0) - lo) / h).astype(int) + 1)
    c = np.minimum(((x - lo) / h).astype(int), ncell - 1)
    flat = (c[:, 0] * ncell[1] + c[:, 1]) * ncell[2] + c[:, 2]
    order = np.argsort(flat, kind="stable")
    sorted_flat = flat[order]
    starts = np.searchsorted(sorted_flat, np.arange(ncell.prod()), side="left")
    counts = np.searchsorted(sorted_flat, np.arange(ncell.prod()), side="right") - starts
    cap = int(counts.max())
    pairs, max_ov = 0, 0.0
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                nc = c + np.array([dx, dy, dz])
                inside = np.all((nc >= 0) & (nc < ncell), axis=1)
                nflat = (nc[:, 0] * ncell[1] + nc[:, 1]) * ncell[2] + nc[:, 2]
                nflat[~inside] = 0
                for k in range(cap):
                    has = inside & (counts[nflat] > k)
                    i = np.nonzero(has)[0]
                    j = order[starts[nflat[i]] + k]
                    keep = j > i  # each pair once
                    i, j = i[keep], j[keep]
                    dist = np.sqrt(np.sum((x[j] - x[i]) ** 2, axis=1))
                    ov = 0.5 * (d[i] + d[j]) - dist
                    touching = ov > 0
                    pairs += int(np.count_nonzero(touching))
                    if np.any(touching):
                        max_ov = max(max_ov, float(ov[touching].max()))
    return pairs, max_ov


def bed_state(parts, p):
    """Kinetic energy, mean height, contacts and overlaps of a bed, the same way for every code."""
    x = np.stack([parts["x"], parts["y"], parts["z"]], axis=1)
    d = parts["d"] if "d" in parts else np.full(len(x), p["d"])
    m = p["rho"] * math.pi / 6.0 * d ** 3
    v2 = parts["vx"] ** 2 + parts["vy"] ** 2 + parts["vz"] ** 2
    w2 = parts["wx"] ** 2 + parts["wy"] ** 2 + parts["wz"] ** 2
    ke = float(np.sum(0.5 * m * v2) + np.sum(0.5 * (m * d * d / 10.0) * w2))
    pairs, max_ov = pair_contacts(x, d, p["box"])
    r = 0.5 * d
    walls = 0
    for a in range(3):
        walls += int(np.count_nonzero(x[:, a] < r)) + int(np.count_nonzero(p["box"][a] - x[:, a] < r))
        max_ov = max(max_ov, float(np.max(r - x[:, a])), float(np.max(r - (p["box"][a] - x[:, a]))))
    n = len(x)
    return {
        "particles": n,
        "ke_per_particle_mgd": ke / n / (p["mass"] * G * p["d"]),
        "y_mean_d": float(np.mean(x[:, 1])) / p["d"],
        "contacts_per_particle": 2.0 * pairs / n,  # coordination: each pair counts for both particles
        "wall_contacts_per_particle": walls / n,
        "max_overlap_d": max_ov / p["d"],
    }


# ---------------------------------------------------------------------------------------------------------------
# Inputs of the peers


def split(ranks, box):
    """Process grid px x 1 x pz: the bed lies at the bottom of a tall box, so y is never split (a 2-rank split of y
    would leave the upper rank empty); px * pz = ranks with the squarest subdomains of the footprint."""
    best = None
    for px in range(ranks, 0, -1):  # on a tie (a square footprint) split x, as the thin bed
        if ranks % px:
            continue
        pz = ranks // px
        aspect = max(box[0] / px, box[2] / pz) / min(box[0] / px, box[2] / pz)
        if best is None or aspect < best[0] - 1e-12:
            best = (aspect, px, pz)
    return best[1], best[2]


def lammps_input(p, data, warmup, steps, px, pz, skin, dump):
    """LAMMPS: gran/hooke/history between particles, wall/gran hooke/history on the six box faces, velocity Verlet
    with rotation (nve/sphere). Reads the data file, runs the warm-up, then the timed run (its own "Loop time"
    line), then dumps the final state outside the timed loop."""
    g = lambda x: "%.10g" % x
    wall = "%s %s %s %s %s 1" % (g(p["wall_kn"]), g(p["wall_kt"]), g(p["wall_gamma_n"]), g(p["wall_gamma_t"]), g(p["wall_mu"]))
    L = ["# fluidbed benchmark peer (scripts/bench_peers.py): LAMMPS",
         "units si", "atom_style sphere", "atom_modify map array", "dimension 3", "boundary f f f", "newton on",
         "processors %d 1 %d" % (px, pz),
         "read_data %s" % data,
         "comm_modify vel yes",
         "neighbor %s bin" % g(skin * p["d"]),
         "neigh_modify delay 0 every 1 check yes",
         "pair_style gran/hooke/history %s %s %s %s %s 1" % (g(p["kn"]), g(p["kt"]), g(p["gamma_n"]), g(p["gamma_t"]), g(p["mu"])),
         "pair_coeff * *"]
    for a, name in enumerate("xyz"):
        L.append("fix wall_%s all wall/gran hooke/history %s %splane 0.0 %s" % (name, wall, name, g(p["box"][a])))
    L += common_tail() + [
          "timestep %s" % repr(p["dt"])]
    if warmup > 0:
        L += ["thermo %d" % warmup, "run %d" % warmup]
    L += ["thermo %d" % steps, "run %d" % steps,
          "write_dump all custom %s id x y z vx vy vz omegax omegay omegaz radius modify sort id format float %%.17g" % dump]
    return "\n".join(L) + "\n"


def liggghts_input(p, data, warmup, steps, px, pz, skin, dump):
    """LIGGGHTS: hooke/stiffness with tangential history; the material pairs as per-type-pair properties (type 1
    particles, type 2 the walls, so the walls take their own damping); one wall/gran fix per box face. Warm-up,
    timed run and final dump as for LAMMPS."""
    g = lambda x: "%.10g" % x
    pairs = lambda pp, pw: "%s %s %s %s" % (g(pp), g(pw), g(pw), g(pw))  # 1-1, 1-2, 2-1, 2-2
    L = ["# fluidbed benchmark peer (scripts/bench_peers.py): LIGGGHTS",
         "atom_style granular", "atom_modify map array", "boundary f f f", "newton off", "communicate single vel yes",
         "units si", "processors %d 1 %d" % (px, pz),
         "read_data %s" % data,
         "neighbor %s bin" % g(skin * p["d"]),
         "neigh_modify delay 0 every 1 check yes",
         "fix m1 all property/global kn peratomtypepair 2 %s" % pairs(p["kn"], p["wall_kn"]),
         "fix m2 all property/global kt peratomtypepair 2 %s" % pairs(p["kt"], p["wall_kt"]),
         "fix m3 all property/global gamman peratomtypepair 2 %s" % pairs(p["gamma_n"], p["wall_gamma_n"]),
         "fix m4 all property/global gammat peratomtypepair 2 %s" % pairs(p["gamma_t"], p["wall_gamma_t"]),
         "fix m5 all property/global coefficientFriction peratomtypepair 2 %s" % pairs(p["mu"], p["wall_mu"]),
         "pair_style gran model hooke/stiffness tangential history",
         "pair_coeff * *",
         "timestep %s" % repr(p["dt"])]
    for a, name in enumerate("xyz"):
        for side, pos in (("lo", 0.0), ("hi", p["box"][a])):
            L.append("fix wall_%s%s all wall/gran model hooke/stiffness tangential history primitive type 2 %splane %s"
                     % (name, side, name, g(pos)))
    L += common_tail()
    if warmup > 0:
        L += ["thermo %d" % warmup, "run %d" % warmup]
    L += ["thermo %d" % steps, "run %d" % steps,
          # a dump written at the set-up of a zero-step run, outside the timed loop; full precision: the default %g
          # rounds a height of 10 mm to 1e-8 m, a tenth of a typical overlap
          "dump final all custom 1 %s id x y z vx vy vz omegax omegay omegaz radius" % dump,
          "dump_modify final sort id format \"%d" + " %.17g" * 10 + "\"",
          "run 0"]
    return "\n".join(L) + "\n"


_LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def parse_peer_log(text, warmup):
    """The timed run's figures from a LAMMPS/LIGGGHTS screen log: loop time, ranks, steps, atoms, neighbour-list
    builds, and the last thermo row (contacts summed by compute contact/atom)."""
    loops = list(_LOOP.finditer(text))
    timed = 1 if warmup > 0 else 0  # the run after the warm-up's (a later "run 0" only dumps)
    if len(loops) <= timed:
        raise RuntimeError("no 'Loop time' line of the timed run in the log")
    lp = loops[timed]
    after = text[lp.end():loops[timed + 1].start() if len(loops) > timed + 1 else len(text)]  # up to the dump's run 0
    nb = re.search(r"Neighbor list builds\s*=\s*(\d+)", after)
    dang = re.search(r"Dangerous builds\s*=\s*(\d+)", after)
    cpu = re.search(r"([0-9.]+)% CPU use with", after)  # LAMMPS's share of a core during the loop
    # the loop's time per section (average over ranks): LAMMPS's "MPI task timing breakdown" table, LIGGGHTS's
    # "Pair  time (%) = T (P)" lines
    sections = {}
    for name, avg in re.findall(r"^(Pair|Neigh|Comm|Output|Modify|Other)\s*\|\s*\S*\s*\|\s*([0-9.eE+-]+)", after, re.M):
        sections[name.lower()] = float(avg)
    for name, tm in re.findall(r"^(Pair|Neigh|Comm|Outpt|Modfy|Other)\s+time \(%\) = ([0-9.eE+-]+)", after, re.M):
        sections[{"outpt": "output", "modfy": "modify"}.get(name.lower(), name.lower())] = float(tm)
    before = text[loops[timed - 1].end() if timed else 0:lp.start()]
    rows = [s.split() for s in before.splitlines() if re.match(r"^\s*\d+\s+\d+\s+[-0-9.eE+]+\s+[-0-9.eE+]+\s+[-0-9.eE+]+\s*$", s)]
    last = rows[-1] if rows else None
    return {"loop_s": float(lp.group(1)), "ranks": int(lp.group(2)), "steps": int(lp.group(3)), "atoms": int(lp.group(4)),
            "rebuilds": int(nb.group(1)) if nb else None, "dangerous": int(dang.group(1)) if dang else None,
            "loop_cpu_use": float(cpu.group(1)) / 100 if cpu else None, "sections_s": sections,
            "own_contacts_per_particle": float(last[4]) / float(last[1]) if last else None}


# ---------------------------------------------------------------------------------------------------------------
# Running


def loadavg():
    return [round(x, 2) for x in os.getloadavg()]  # as /proc/loadavg writes them


def mpirun(ranks, cmd):
    return ["mpiexec", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-n", str(ranks)] + cmd


def sh(cmd, log, cwd=None, timeout=3600):
    """Runs a command with its output to log; raises with the log's tail when it fails. Returns the wall seconds of
    the whole command and the CPU seconds (user + system) of its processes, whose ratio over the ranks says how
    much of a core each rank got on a shared machine."""
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, cwd=cwd, timeout=timeout)
    wall = time.time() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        tail = open(log).read()[-3000:]
        raise RuntimeError("%s exited with status %d (log %s):\n%s" % (" ".join(cmd), r.returncode, log, tail))
    return wall, (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)


class Bed:
    def __init__(self, name, opts, settled, workdir, args):
        self.name, self.opts, self.settled = name, opts, settled
        self.dir = os.path.join(workdir, name)
        self.p = bed_params(opts)
        self.args = args
        os.makedirs(self.dir, exist_ok=True)
        self.data = os.path.join(self.dir, "settled.data")
        self.parts0 = read_particles_csv(settled)

    def fluidbed_cmd(self, ranks, out, extra):
        px, pz = split(ranks, self.p["box"])
        return mpirun(ranks, [self.args.exe, "-options_file", self.opts, "-output_dir", out, "-progress_interval", "0",
                              "-pgrid_processors", "%d,1,%d" % (px, pz)] + extra)

    def peer_cmd(self, code, ranks, inp):
        exe = self.args.lmp if code == "lammps" else self.args.liggghts
        return mpirun(ranks, [exe, "-in", inp, "-log", "none"])

    def warmup(self):
        """fluidbed's warm-up: --warmup steps from the settled particles on the largest rank count, ending in a
        checkpoint (contact history included) that every timed fluidbed run restarts from; fluidbed's restarts
        continue bit for bit. Reused while the settled file, the step count, the skin and the executable are the
        same. The data file the peers read is written here too."""
        W, ranks = self.args.warmup, max(self.args.ranks)
        write_data(self.data, self.parts0, self.p["box"], self.p["rho"], "%s settled by fluidbed (%s), y vertical" % (self.name, self.settled))
        wd = os.path.join(self.dir, "warmup", "fluidbed")
        stamp = os.path.join(wd, "key.json")
        key = {"settled": os.path.abspath(self.settled), "mtime": os.path.getmtime(self.settled), "warmup": W, "skin": self.args.skin,
               "exe": self.args.exe, "exe_mtime": os.path.getmtime(self.args.exe)}
        if os.path.isfile(stamp) and json.load(open(stamp)) == key:
            print("%s: fluidbed's warm-up checkpoint reused (%s)" % (self.name, wd), flush=True)
            return
        shutil.rmtree(wd, ignore_errors=True)
        os.makedirs(wd)
        t0 = time.time()
        sh(self.fluidbed_cmd(ranks, wd, ["-insert_type", "file", "-insert_file", os.path.abspath(self.settled), "-max_steps", str(W),
                                         "-dem_skin", str(self.args.skin), "-checkpoint_interval", "1e6",
                                         "-checkpoint_file", os.path.join(wd, "checkpoint.h5"), "-output_particles", "0"]),
           os.path.join(wd, "log.txt"))
        json.dump(key, open(stamp, "w"))
        print("%s: fluidbed warmed up (%d steps, %d ranks, %.0f s)" % (self.name, W, ranks, time.time() - t0), flush=True)

    def timed(self, code, ranks, rep):
        """One timed run of --steps steps after the warm-up; returns its figures and the analysed final state.
        fluidbed restarts from its warm-up checkpoint; a peer reads the data file and runs its warm-up in the same
        process (a restart of LIGGGHTS 3.8 does not continue its run exactly), each loop timed on its own."""
        N, W = self.args.steps, self.args.warmup
        wd = os.path.join(self.dir, "runs", "%s_np%d_rep%d" % (code, ranks, rep))
        shutil.rmtree(wd, ignore_errors=True)
        os.makedirs(wd)
        px, pz = split(ranks, self.p["box"])
        load0 = loadavg()
        if code == "fluidbed":
            ckpt = os.path.join(self.dir, "warmup", "fluidbed", "checkpoint.h5")
            wall, cpu = sh(self.fluidbed_cmd(ranks, wd, ["-restart", ckpt, "-max_steps", str(N), "-dem_skin", str(self.args.skin),
                                                         "-log_view", "ascii:%s" % os.path.join(wd, "log_view.txt")]),
                           os.path.join(wd, "log.txt"))
            s = json.load(open(os.path.join(wd, "summary.json")))
            if s.get("status") != "ok" or s.get("steps_this_run") != N:
                raise RuntimeError("fluidbed run %s: status %s, %s steps" % (wd, s.get("status"), s.get("steps_this_run")))
            final = read_particles_csv(os.path.join(wd, "particles.csv"))
            # fluidbed counts the list built at set-up; the peers count the builds during the run only
            r = {"loop_s": s["wall_time_run"], "ranks": s["ranks"], "steps": s["steps_this_run"], "atoms": s["particles"],
                 "rebuilds": s["neighbour_rebuilds"] - 1, "own_contacts_per_particle": s["contacts_per_particle"],
                 "phases_s": s["wall_time_phase_max_over_ranks"]}
        else:
            make = lammps_input if code == "lammps" else liggghts_input
            with open(os.path.join(wd, "in.bench"), "w") as f:
                f.write(make(self.p, os.path.abspath(self.data), W, N, px, pz, self.args.skin, "final.dump"))
            wall, cpu = sh(self.peer_cmd(code, ranks, "in.bench"), os.path.join(wd, "log.txt"), cwd=wd)
            r = parse_peer_log(open(os.path.join(wd, "log.txt")).read(), W)
            if r["steps"] != N or r["ranks"] != ranks:
                raise RuntimeError("%s run %s: %d steps on %d ranks" % (code, wd, r["steps"], r["ranks"]))
            final = read_dump(os.path.join(wd, "final.dump"))
        load1 = loadavg()
        r["rate_per_core"] = r["atoms"] * r["steps"] / (r["loop_s"] * ranks)
        r["load_before"], r["load_after"] = load0, load1
        r["process_wall_s"], r["process_cpu_s"] = wall, cpu
        r["cpu_share"] = cpu / (wall * ranks)  # of the whole command, set-up included: about 1 on a quiet machine
        r["process_grid"] = [px, 1, pz]
        r["state"] = bed_state(final, self.p)
        return r


def check_physics(bed, p, runs0, rec):
    """The final states of one (bed, ranks, repetition) against fluidbed's and against a bed at rest; returns the
    list of failures (empty when the codes agree)."""
    fails = []
    ref = rec["fluidbed"]["state"]
    for code in CODES:
        s = rec[code]["state"]
        where = "%s %s" % (bed, code)
        if s["particles"] != runs0:
            fails.append("%s: %d particles, started with %d" % (where, s["particles"], runs0))
        if not s["ke_per_particle_mgd"] < TOL["ke_per_mgd"]:
            fails.append("%s: kinetic energy %.3g m g d per particle (at rest: < %g)" % (where, s["ke_per_particle_mgd"], TOL["ke_per_mgd"]))
        if not s["max_overlap_d"] < TOL["max_overlap_d"]:
            fails.append("%s: largest overlap %.3g d (< %g)" % (where, s["max_overlap_d"], TOL["max_overlap_d"]))
        if not abs(s["y_mean_d"] - ref["y_mean_d"]) < TOL["y_mean_d"]:
            fails.append("%s: mean height %.4f d, fluidbed %.4f d (within %g d)" % (where, s["y_mean_d"], ref["y_mean_d"], TOL["y_mean_d"]))
        if not abs(s["contacts_per_particle"] / ref["contacts_per_particle"] - 1) < TOL["contacts_rel"]:
            fails.append("%s: %.3f contacts per particle, fluidbed %.3f (within %g%%)" % (where, s["contacts_per_particle"],
                                                                                        ref["contacts_per_particle"], 100 * TOL["contacts_rel"]))
    return fails


def med_range(xs):
    return {"median": statistics.median(xs), "min": min(xs), "max": max(xs), "values": xs}


def versions(args):
    v = {}
    try:
        v["fluidbed_commit"] = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    except OSError:
        pass
    for code, exe in (("lammps", args.lmp), ("liggghts", args.liggghts)):
        r = subprocess.run(["dpkg-query", "-W", "-f=${Version}", code], capture_output=True, text=True)
        v[code] = r.stdout.strip() or exe
    return v


def report(res):
    """The markdown tables of a result."""
    L = []
    m = res["machine"]
    L.append("Machine: %s, %s cores; load (1, 5, 15 min) %s before, %s after; %s; OMP_NUM_THREADS=1" %
             (m["cpu"], m["cores"], res["load_start"], res["load_end"], res["date"]))
    L.append("Command: `%s`; %d warm-up steps, then %d timed steps, %d repetitions (codes interleaved), skin %g d" %
             (res["command"], res["warmup"], res["steps"], res["repetitions"], res["skin"]))
    L.append("")
    L.append("| bed | ranks | process grid | fluidbed | LAMMPS | LIGGGHTS | fluidbed/LAMMPS | fluidbed/LIGGGHTS | load (1-min) | CPU share F / L / G |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    for key, e in res["cases"].items():
        rate = lambda c: "%.2fM (%.2f-%.2f)" % (e["rate"][c]["median"] / 1e6, e["rate"][c]["min"] / 1e6, e["rate"][c]["max"] / 1e6)
        ratio = lambda c: "%.2f (%.2f-%.2f)" % (e["ratio"][c]["median"], e["ratio"][c]["min"], e["ratio"][c]["max"])
        L.append("| %s | %d | %s | %s | %s | %s | %s | %s | %.2f-%.2f | %s |" % (e["bed"], e["ranks"], " x ".join(map(str, e["process_grid"])),
                 rate("fluidbed"), rate("lammps"), rate("liggghts"), ratio("lammps"), ratio("liggghts"), e["load_min"], e["load_max"],
                 " / ".join("%.2f" % e["cpu_share"][c] for c in CODES)))
    L.append("")
    L.append("Particle-steps per second per core: median (range) over the repetitions; ratios per repetition. Load: the "
             "1-minute load average before and after each run (2 cores: above 2 means other work shared them). CPU share: "
             "median over the repetitions of the CPU time of a code's processes over their wall time and ranks (1: each "
             "rank had a core; MPI ranks that busy-wait count as busy).")
    L.append("")
    L.append("| bed | ranks | code | contacts per particle (own count) | recounted from positions | wall contacts | neighbour rebuilds | KE / (N m g d) | mean height (d) | largest overlap (d) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    for key, e in res["cases"].items():
        for c in CODES:
            r = e["runs"][0][c]
            s = r["state"]
            L.append("| %s | %d | %s | %.3f | %.3f | %.4f | %s | %.2e | %.4f | %.2e |" % (e["bed"], e["ranks"], c, r["own_contacts_per_particle"] or float("nan"),
                     s["contacts_per_particle"], s["wall_contacts_per_particle"], r["rebuilds"], s["ke_per_particle_mgd"], s["y_mean_d"], s["max_overlap_d"]))
    L.append("")
    L.append("(First repetition; fluidbed's own count includes wall contacts, the peers' compute contact/atom counts particle pairs only.)")
    L.append("")
    L.append("| bed | ranks | fluidbed phases (s, max over ranks, first repetition): contact / integrate / ghosts / neighbour / migrate / guards / output | wall s |")
    L.append("|---|---|---|---|")
    for key, e in res["cases"].items():
        r = e["runs"][0]["fluidbed"]
        ph = r["phases_s"]
        L.append("| %s | %d | %s | %.2f |" % (e["bed"], e["ranks"], " / ".join("%.2f" % ph.get(k, 0) for k in
                                                                           ("contact", "integrate", "ghosts", "neighbour", "migrate", "guards", "output")), r["loop_s"]))
    L.append("")
    L.append("| bed | ranks | LAMMPS loop (s, mean over ranks, first repetition): pair / neigh / comm / modify / output / other | LIGGGHTS: pair / neigh / comm / output / other |")
    L.append("|---|---|---|---|")
    for key, e in res["cases"].items():
        sec = lambda c, names: " / ".join("%.2f" % e["runs"][0][c]["sections_s"].get(k, float("nan")) for k in names)
        L.append("| %s | %d | %s | %s |" % (e["bed"], e["ranks"], sec("lammps", ("pair", "neigh", "comm", "modify", "output", "other")),
                                            sec("liggghts", ("pair", "neigh", "comm", "output", "other"))))
    L.append("")
    L.append("Physics: %s" % ("all final states agree within the tolerances %s" % json.dumps(TOL) if not res["failures"] else
                              "DISAGREE: " + "; ".join(res["failures"])))
    return "\n".join(L)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bed", action="append", metavar="NAME:OPTS:SETTLED_CSV", required=True,
                    help="a bed: its name, its options file and the particles.csv of its settled state (repeat for several)")
    ap.add_argument("--steps", type=int, default=2000, help="timed steps per run")
    ap.add_argument("--warmup", type=int, default=500, help="warm-up steps from the settled particles before the timed steps")
    ap.add_argument("--repetitions", type=int, default=3)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--skin", type=float, default=0.1, help="Verlet skin in diameters, the same in all three codes (fluidbed's default)")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fluidbed"))
    ap.add_argument("--lmp", default="lmp")
    ap.add_argument("--liggghts", default="liggghts")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "peers"), help="working directory and results")
    ap.add_argument("--command", default=" ".join(sys.argv), help="the command to quote in the report")
    args = ap.parse_args()
    args.exe = os.path.abspath(args.exe)
    os.makedirs(args.out, exist_ok=True)

    beds = []
    for spec in args.bed:
        name, opts, settled = spec.split(":")
        beds.append(Bed(name, opts, settled, args.out, args))
    res = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "command": args.command, "machine": machine(),
           "versions": versions(args), "steps": args.steps, "warmup": args.warmup, "repetitions": args.repetitions, "skin": args.skin,
           "tolerances": TOL, "load_start": loadavg(), "beds": {}, "cases": {}, "failures": []}
    failed = []
    try:
        for b in beds:
            res["beds"][b.name] = {"options": b.opts, "settled": b.settled, "particles": len(b.parts0["x"]), "params": b.p,
                                   "initial_state": bed_state(b.parts0, b.p)}
            b.warmup()
        for rep in range(args.repetitions):
            for b in beds:
                for ranks in args.ranks:
                    key = "%s_np%d" % (b.name, ranks)
                    e = res["cases"].setdefault(key, {"bed": b.name, "ranks": ranks, "runs": []})
                    order = CODES[rep % 3:] + CODES[:rep % 3]  # the first code of a repetition rotates
                    rec = {}
                    for code in order:
                        rec[code] = b.timed(code, ranks, rep)
                        r = rec[code]
                        print("rep %d %-8s np %d %-8s %.3e particle-steps/s/core, %.2f s, load %.2f -> %.2f, CPU share %.2f, %s contacts/particle, %s rebuilds"
                              % (rep, b.name, ranks, code, r["rate_per_core"], r["loop_s"], r["load_before"][0], r["load_after"][0], r["cpu_share"],
                                 "%.3f" % r["state"]["contacts_per_particle"], r["rebuilds"]), flush=True)
                    e["process_grid"] = rec["fluidbed"]["process_grid"]
                    e["runs"].append(rec)
                    fails = check_physics(b.name, b.p, len(b.parts0["x"]), rec)
                    for f in fails:
                        print("DISAGREE: " + f, flush=True)
                    res["failures"] += ["rep %d np %d: %s" % (rep, ranks, f) for f in fails]
    except (RuntimeError, subprocess.TimeoutExpired, OSError, ValueError) as ex:
        failed.append(str(ex))
        print("FAILED: %s" % ex, file=sys.stderr, flush=True)
    res["load_end"] = loadavg()
    for key, e in res["cases"].items():
        runs = e["runs"]
        if not runs or any(c not in r for r in runs for c in CODES):
            continue
        e["rate"] = {c: med_range([r[c]["rate_per_core"] for r in runs]) for c in CODES}
        e["ratio"] = {c: med_range([r["fluidbed"]["rate_per_core"] / r[c]["rate_per_core"] for r in runs]) for c in ("lammps", "liggghts")}
        loads = [x for r in runs for c in CODES for x in (r[c]["load_before"][0], r[c]["load_after"][0])]
        e["load_min"], e["load_max"] = min(loads), max(loads)
        e["cpu_share"] = {c: statistics.median([r[c]["cpu_share"] for r in runs]) for c in CODES}
    res["cases"] = {k: e for k, e in res["cases"].items() if "rate" in e}
    res["run_failures"] = failed
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    for path in (os.path.join(args.out, "results.json"), os.path.join(args.out, "results-%s.json" % stamp)):
        with open(path, "w") as f:
            json.dump(res, f, indent=1)
    text = report(res) if res["cases"] else "(no complete case)"
    with open(os.path.join(args.out, "results.md"), "w") as f:
        f.write(text + "\n")
    print()
    print(text)
    print()
    print("results: %s/results.json, results.md" % args.out)
    if failed or res["failures"]:
        print("bench_peers: FAILED (%s)" % ("; ".join(failed) if failed else "the codes' final states disagree"), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
