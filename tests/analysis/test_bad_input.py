"""Bad averaging options end with a message naming the option and its allowed range, a nonzero exit status and
no crash, on 1 and 2 ranks (default box: 40 mm high)."""
from fluidbed_tools import testing as t

cases = [
    (["-average_interval", "-1e-3"], ["-average_interval", "out of range", "(0, 1e+06] s"]),
    (["-average_interval", "0"], ["-average_interval", "out of range"]),
    (["-average_start", "-0.1"], ["-average_start", "out of range", "[0, 1e+06] s"]),
    (["-average_heights", "0.01,0.05"], ["-average_heights", "entry 1 = 0.05", "out of range", "[0, 0.04] m"]),
    (["-average_heights", "-0.001"], ["-average_heights", "entry 0", "out of range"]),
    (["-average_pressure_heights", "0.03,0.01"], ["-average_pressure_heights", "lower"]),
    (["-average_pressure_heights", "0.01"], ["-average_pressure_heights", "needs 2"]),
    (["-average_jet_void_fraction", "1.5"], ["-average_jet_void_fraction", "out of range", "(0, 1)"]),
    (["-average_temperature_min_count", "1"], ["-average_temperature_min_count", "out of range", "[2, 1000000]"]),
    (["-average_output_interval", "-1"], ["-average_output_interval", "out of range"]),
]
t.check_bad_input(cases, common=["-average"], outdir="avg_bad_input")
