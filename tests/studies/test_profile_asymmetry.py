"""scripts/profile_asymmetry.py on snapshots with a known answer: a bed whose left half is wetter by 0.04 plus
independent noise (rms 0.02 per cell and snapshot) reports a left-minus-right difference D within three standard
errors of 0.04 on the longest window, and the error it states is near the noise's (0.02 / sqrt(cells x samples));
a mirror-symmetric bed with the same noise reports a D within three standard errors of 0 and an asymmetry that falls
as the window grows (noise averages out)."""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

from fluidbed_tools import testing as t


def write_run(path, left_excess, seed):
    os.makedirs(path, exist_ok=True)
    rng = np.random.default_rng(seed)
    nx, ny, nz, ly = 12, 32, 2, 0.16
    with open(os.path.join(path, "command.txt"), "w") as f:
        f.write("fluidbed -domain_lx 0.044 -domain_ly %g\n" % ly)
    for k in range(81):  # t = 0 .. 4 s every 0.05 s
        eps = 0.55 + 0.02 * rng.standard_normal((nz, ny, nx))
        eps[:, :, : nx // 2] += left_excess
        with h5py.File(os.path.join(path, "snapshot_%05d.h5" % k), "w") as f:
            f.attrs["time"] = 0.05 * k
            f["fluid/void_fraction"] = eps


def run(path):
    out = path + ".json"
    p = subprocess.run([sys.executable, os.path.join(t.SRC, "scripts", "profile_asymmetry.py"), path, "--start", "0",
                        "--windows", "0.5,1,2,4", "--block", "0.25", "--json", out], capture_output=True, text=True, timeout=300)
    print(p.stdout, p.stderr)
    t.check(p.returncode == 0, "profile_asymmetry.py ran on %s (exit %d)" % (path, p.returncode))
    return json.load(open(out))["windows"]


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
print("ok")
