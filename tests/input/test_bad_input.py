"""Bad input ends with a clear message naming the option (or the offending particle) and the allowed range, a
nonzero exit status, and no crash or hang, on 1 and 2 ranks."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fbtest as t

cases = [
    (["-particle_diameter", "-1e-3"], ["-particle_diameter", "out of range", "(0, 0.1]"]),
    (["-dem_e", "1.2"], ["-dem_e", "out of range", "(0, 1]"]),
    (["-dem_dt_factor", "0"], ["-dem_dt_factor", "out of range"]),
    (["-domain_dim", "4"], ["-domain_dim", "[2, 3]"]),
    (["-gravity", "1,2"], ["-gravity", "3"]),
    (["-grid_nx", "40", "-pgrid_ratio", "1"], ["particle cell", "smaller than the largest particle diameter", "-pgrid_ratio"]),
    (["-grid_nx", "10", "-pgrid_ratio", "3"], ["non-integer grid ratio", "-grid_nx 10", "-pgrid_ratio 3", "1, 2, 5, 10"]),
    (["-insert_type", "list", "-insert_positions", "0.5,0.01,0.01"], ["particle 0", "outside the box"]),
    (["-insert_type", "foo"], ["-insert_type", "foo", "lattice random list file"]),
    (["-insert_count", "100000"], ["-insert_type lattice", "lattice sites", "100000"]),
    (["-particle_diameter_min", "2e-3", "-particle_diameter_max", "1e-3"], ["-particle_diameter_max", "-particle_diameter_min"]),
    (["-insert_type", "file", "-insert_file", "/nonexistent.csv"], ["-insert_file", "/nonexistent.csv"]),
]
t.check_bad_input(cases)
