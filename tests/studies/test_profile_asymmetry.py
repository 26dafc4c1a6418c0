"""scripts/profile_asymmetry.py on snapshots with a known answer: a bed whose left half is wetter by 0.04 plus
independent noise (rms 0.02 per cell and snapshot) reports a left-minus-right difference D within three standard
errors of 0.04 on the longest window, and the error it states is near the noise's (0.02 / sqrt(cells x samples));
a mirror-symmetric bed with the same noise reports a D within three standard errors of 0 and an asymmetry that falls
as the window grows (noise averages out). A bed whose roll switches sides (left wetter by 0.08 over 0-5 s and 12-20 s,
right wetter over 5-12 s) reports two sign changes of D over 1 s blocks, the left half wetter in 13 of 20 blocks, and
a blocking analysis whose error over 4 s blocks is more than twice the one over 0.25 s blocks (the short blocks miss
the seconds-long correlation)."""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

from fluidbed_tools import testing as t


def write_run(path, left_excess, seed, count=81):
    """Snapshots every 0.05 s; left_excess is a number or a function of time."""
    os.makedirs(path, exist_ok=True)
    rng = np.random.default_rng(seed)
    nx, ny, nz, ly = 12, 32, 2, 0.16
    with open(os.path.join(path, "command.txt"), "w") as f:
        f.write("fluidbed -domain_lx 0.044 -domain_ly %g\n" % ly)
    for k in range(count):  # t = 0 .. 4 s every 0.05 s by default
        eps = 0.55 + 0.02 * rng.standard_normal((nz, ny, nx))
        eps[:, :, : nx // 2] += left_excess(0.05 * k) if callable(left_excess) else left_excess
        with h5py.File(os.path.join(path, "snapshot_%05d.h5" % k), "w") as f:
            f.attrs["time"] = 0.05 * k
            f["fluid/void_fraction"] = eps


def run(path, extra=()):
    out = path + ".json"
    p = subprocess.run([sys.executable, os.path.join(t.SRC, "scripts", "profile_asymmetry.py"), path, "--start", "0",
                        "--windows", "0.5,1,2,4", "--block", "0.25", "--json", out] + list(extra), capture_output=True, text=True,
                       timeout=300)
    print(p.stdout, p.stderr)
    t.check(p.returncode == 0, "profile_asymmetry.py ran on %s (exit %d)" % (path, p.returncode))
    return json.load(open(out))["windows"] if not extra else json.load(open(out))


write_run("asym_left", 0.04, 1)
write_run("asym_none", 0.0, 2)
w = run("asym_left")
last = w[-1]
t.check([x["window_s"] for x in w] == [0.5, 1, 2, 4], "four windows reported: %s" % [x["window_s"] for x in w])
t.check(abs(last["left_minus_right"] - 0.04) < 3 * last["left_minus_right_std_err"],
        "left-wet bed: D = %.4f +- %.4f over 4 s, expected 0.04" % (last["left_minus_right"], last["left_minus_right_std_err"]))
noise = 0.02 * np.sqrt(2.0 / (6 * 2 * last["samples"]))  # the difference of two half means over the window
t.check(0.3 * noise < last["left_minus_right_std_err"] < 3 * noise,
        "its standard error %.5f is near the noise's %.5f" % (last["left_minus_right_std_err"], noise))
t.check(abs(last["mirror_asymmetry"] - 0.04 / 2) < 0.01, "mirror asymmetry %.4f, expected 0.02" % last["mirror_asymmetry"])
w = run("asym_none")
last = w[-1]
t.check(abs(last["left_minus_right"]) < 3 * last["left_minus_right_std_err"],
        "symmetric bed: D = %.4f +- %.4f, consistent with 0" % (last["left_minus_right"], last["left_minus_right_std_err"]))
t.check(w[-1]["mirror_asymmetry"] < w[0]["mirror_asymmetry"],
        "its asymmetry falls as the window grows: %s" % ", ".join("%.4f" % x["mirror_asymmetry"] for x in w))

write_run("asym_switch", lambda time: 0.08 if time < 5 or time >= 12 else -0.08, 3, count=401)  # 0-20 s
r = run("asym_switch", ["--roll-block", "1", "--plot", "asym_switch.png"])
roll = r["roll"]
t.check(len(roll["left_minus_right"]) == 20, "20 roll blocks of 1 s over 0-20 s: %d" % len(roll["left_minus_right"]))
t.check(roll["sign_changes"] == 2, "the roll switches twice: %d sign changes" % roll["sign_changes"])
t.check(abs(roll["share_left_wetter"] - 0.65) < 1e-9, "left wetter in 13 of 20 blocks: %.3f" % roll["share_left_wetter"])
se = {b["block_s"]: b["left_minus_right_std_err"] for b in r["error_blocks"]}
t.check(se[4.0] > 2 * se[0.25], "blocking analysis: error %.4f over 4 s blocks against %.4f over 0.25 s" % (se[4.0], se[0.25]))
t.check(os.path.getsize("asym_switch.png") > 1000, "the timeline was drawn")
print("ok")
