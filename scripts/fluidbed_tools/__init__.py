"""fluidbed_tools: the Python shared by scripts/ and tests/.

Modules:
  run        the fluidbed command line (serial or under mpiexec), launching a run, whether a recorded run is finished
  study      a study's points: one recorded, resumable run each, several side by side
  outputs    reading a run's files: CSV tables, summary.json, HDF5
  reference  the analytic and correlation values the tests and studies compare against (contact, drag, Ergun, U_mf,
             terminal velocity, Poiseuille), each written once
  plot       reading and drawing helpers of the plot scripts (matplotlib, Agg)
  testing    what a test script uses: running with a status check, check/fail, bad-input cases

How it is found: the package sits in scripts/, and Python puts a script's own directory first on sys.path, so every
scripts/*.py imports it (`from fluidbed_tools import study`) with nothing on its path set by hand, however it is
started (scripts/x.py, python3 scripts/x.py, from a shell script). The tests get PYTHONPATH=<source>/scripts from
tests/CMakeLists.txt (FLUIDBED_TEST_ENV), which also lets them import the scripts they test (umf_sweep, jet_fountain,
bench_peers); a test's helper beside it (tests/fluid/gas.py, tests/analysis/analysis_files.py) is found as a
script's neighbour. To run a test by hand (its outputs go to the current directory):
  cd build && PYTHONPATH=../scripts /usr/bin/python3 ../tests/dem/test_sliding_sphere.py
No file inserts paths into sys.path."""
