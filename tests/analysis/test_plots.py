"""The plot scripts (scripts/plot_*.py) run on a tiny coupled run with a jet and pressure probes (1 rank) and a tiny
DEM-only 2D run, and each writes a non-empty PNG; each has a working --help; bad arguments stop with a message.
Skips only when matplotlib is missing."""
import os
import shutil
import subprocess
import sys

from fluidbed_tools import testing as t

try:
    import matplotlib  # noqa: F401
    import h5py  # noqa: F401
except ImportError as e:
    print("SKIP: %s (matplotlib and h5py are dependencies: apt-get install python3-matplotlib python3-h5py)" % e)
    sys.exit(0)

SCRIPTS = os.path.join(t.SRC, "scripts")
gas, _ = t.run(t.example("coupling/small_bed.opts"),
               args=["-inlet_velocity", 0.1, "-inlet_jets", "0.01,0.0066666667,4", "-couple_substeps", 5, "-t_final", 0.004,
                     "-output_interval", 0.002, "-average", "-average_interval", 5e-4, "-average_heights", "0.005,0.015"], outdir="plots_gas")
dem, _ = t.run(None, args=["-domain_dim", 2, "-domain_lz", 1e-3, "-insert_count", 200, "-t_final", 0.004, "-output_interval", 0.002,
                           "-average", "-average_interval", 5e-4], outdir="plots_dem")


def script(name, *args, fail=False):
    p = subprocess.run([sys.executable, os.path.join(SCRIPTS, name)] + [str(a) for a in args], capture_output=True, text=True, timeout=300)
    if not fail and p.returncode != 0:
        print(p.stdout[-2000:], p.stderr[-2000:])
        t.fail("%s %s exited with status %d" % (name, " ".join(map(str, args)), p.returncode))
    return p


def png(path, label):
    ok = os.path.isfile(path) and os.path.getsize(path) > 5000 and open(path, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    t.check(ok, "%s: %s is a PNG of %d bytes" % (label, os.path.basename(path), os.path.getsize(path) if os.path.isfile(path) else 0))


os.makedirs("plots", exist_ok=True)
for name in ("plot_void_fraction.py", "plot_velocity.py", "plot_profiles.py", "plot_pressure.py", "plot_bars.py", "plot_snapshots.py"):
    for f in os.listdir("plots"):
        os.remove(os.path.join("plots", f))
    p = script(name, "--help")
    t.check("usage:" in p.stdout, "%s --help prints its usage" % name)
    if name == "plot_bars.py":
        script(name, gas, dem, "-o", "plots/bars.png", "--labels", "jet,dem")
        png("plots/bars.png", name)
        # --seed: beside a run of the seed's single jet (the coupled run's analysis.h5 under that scene's name) the
        # seed's circulation bar, beside the other run none
        os.makedirs("seed_jet1", exist_ok=True)
        shutil.copy(os.path.join(gas, "analysis.h5"), "seed_jet1/analysis.h5")
        open("seed_jet1/command.txt", "w").write("fluidbed -options_file examples/spouted_550_jet1_u160.opts\n")
        script(name, "seed_jet1", dem, "-o", "plots/bars_seed.png", "--seed")
        png("plots/bars_seed.png", name + " --seed")
        continue
    script(name, gas, "plots/gas.png")
    png("plots/gas.png", name + " (coupled run)")
    if name != "plot_pressure.py":
        script(name, dem, "plots/dem.png")
        png("plots/dem.png", name + " (DEM-only 2D run)")
script("plot_profiles.py", dem, "plots/heights.png", "--heights", "0.005,0.02")
png("plots/heights.png", "plot_profiles.py --heights")
script("plot_profiles.py", gas, "plots/ch4.png", "--inlet-velocity", 4)  # the seed's chapter-4 panels at -average_heights
png("plots/ch4.png", "plot_profiles.py --inlet-velocity")
p = script("plot_profiles.py", gas, "plots/none.png", "--inlet-velocity", 0, fail=True)
t.check(p.returncode != 0 and "--inlet-velocity" in p.stderr and not os.path.exists("plots/none.png"),
        "plot_profiles.py --inlet-velocity 0: %s" % p.stderr.strip()[:120])
p = script("plot_pressure.py", dem, "plots/none.png", fail=True)
t.check(p.returncode != 0 and "no pressure" in p.stderr and not os.path.exists("plots/none.png"),
        "plot_pressure.py on a run without gas: exit %d, %s" % (p.returncode, p.stderr.strip()[:120]))
script("plot_snapshots.py", gas, "plots/two.png", "--snapshots", "0,2")
png("plots/two.png", "plot_snapshots.py --snapshots 0,2")
p = script("plot_snapshots.py", gas, "plots/none.png", "--snapshots", "99", fail=True)
t.check(p.returncode != 0 and "--snapshots" in p.stderr and not os.path.exists("plots/none.png"),
        "plot_snapshots.py --snapshots 99: %s" % p.stderr.strip()[:120])
p = script("plot_profiles.py", dem, "plots/none.png", "--heights", "1.0", fail=True)
t.check(p.returncode != 0 and "--heights" in p.stderr, "plot_profiles.py --heights 1.0 outside the bed: %s" % p.stderr.strip()[:120])
