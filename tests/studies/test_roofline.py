"""scripts/roofline.py counts what it says:
- the flops of single instructions (scalar 1 per operation, packed 2/4/8 lanes for xmm/ymm/zmm, an FMA 2 per lane,
  moves and conversions 0);
- stage costs from a hand-written callgrind profile: inclusive instructions through the call records, and a callee's
  flops shared among its callers in proportion to the instructions of each call; the gas predictor is the gas step
  less its pressure solve, and the stages with "other" add up to the loop;
- where valgrind is installed: the flops of a C loop with a known count (n iterations of 3 scalar operations plus
  one 2-lane packed add) within 1%, read from its executed instructions."""
import os
import shutil
import subprocess
import tempfile

import roofline  # scripts/, on PYTHONPATH like the package
from fluidbed_tools import testing as t

cases = [("addsd", "%xmm1,%xmm0", 1), ("vmulsd", "%xmm2,%xmm1,%xmm0", 1), ("addpd", "%xmm1,%xmm0", 2),
         ("vaddpd", "%ymm1,%ymm2,%ymm0", 4), ("vfmadd231pd", "%zmm1,%zmm2,%zmm0", 16), ("vfmadd213sd", "%xmm1,%xmm2,%xmm0", 2),
         ("sqrtsd", "%xmm1,%xmm0", 1), ("divss", "%xmm1,%xmm0", 1), ("mulps", "%xmm1,%xmm0", 4), ("movsd", "%xmm1,%xmm0", 0),
         ("cvtsi2sd", "%eax,%xmm0", 0), ("add", "$0x1,%rax", 0), ("ucomisd", "%xmm1,%xmm0", 0)]
for m, ops, want in cases:
    got = roofline.flops_of(m, ops)
    t.check(got == want, "flops of %s %s: %d (expected %d)" % (m, ops, got, want))

# A profile: SimulationRun (self 100 Ir) calls LsdForces (self 1000 Ir) and FluidStep (self 300), which calls
# FluidPressureSolve (self 600). LsdForces has 4 instructions at 0x10 executed 100 times each, 2 flops apiece (a
# made-up table), FluidPressureSolve 50 executions of a 1-flop instruction at 0x40.
profile = """# callgrind format
version: 1
positions: instr
events: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw

ob=(1) /bin/fake
fn=(1) fluidbed::SimulationRun(fluidbed::Simulation*)
0x1000 100 0 0 0 2 0 0 1 0
cfn=(2) fluidbed::(anonymous namespace)::LsdForces(fluidbed::Dem*)
calls=1 0x10
0x1004 1000 0 0 0 20 0 0 10 0
cfn=(3) fluidbed::FluidStep(fluidbed::Fluid*, double)
calls=1 0x30
0x1008 900 0 0 0 9 0 0 3 0

fn=(2)
0x10 400 0 0 0 20 0 0 10 0
+4 600

fn=(3)
0x30 300 0 0 0 3 0 0 1 0
cfn=(4) fluidbed::FluidPressureSolve(fluidbed::Fluid*, double)
calls=1 0x40
+2 600 0 0 0 6 0 0 2 0

fn=(4)
0x40 50
+1 550 0 0 0 6 0 0 2 0
"""
d = tempfile.mkdtemp(prefix="roofline_test_")
path = os.path.join(d, "cg.out")
open(path, "w").write(profile)
events, funcs = roofline.parse_callgrind(path)
t.check(len(funcs) == 4, "4 functions parsed (got %d)" % len(funcs))
fp = {"/bin/fake": {0x10: 2, 0x40: 1}}
st = roofline.stage_costs(events, funcs, fp)
print(st)
t.check(st["contact"]["instructions"] == 1000, "contact: the inclusive 1000 instructions of LsdForces (%d)" % st["contact"]["instructions"])
t.check(st["contact"]["flops"] == 800, "contact: 400 executions x 2 flops (%g)" % st["contact"]["flops"])
t.check(st["contact"]["l2_miss_bytes"] == 640, "contact: 10 L2 misses x 64 B (%d)" % st["contact"]["l2_miss_bytes"])
t.check(st["pressure solve"]["instructions"] == 600 and st["pressure solve"]["flops"] == 50,
        "pressure solve: 600 instructions, 50 flops (%s)" % st["pressure solve"])
g = st["gas step less the pressure solve"]
t.check(g["instructions"] == 300 and g["flops"] == 0, "gas step less the pressure solve: 300 instructions, no flops (%s)" % g)
total = sum(s["instructions"] for s in st.values())
t.check(total == 2000, "the stages and other add up to the loop's 2000 instructions (%d)" % total)
t.check(st["other (output, monitor, guards, loop)"]["instructions"] == 100, "other: the loop's own 100 instructions")

# A loop with a known flop count, through valgrind
if shutil.which("valgrind") and shutil.which("gcc"):
    n = 200000
    src = r"""
#include <stdio.h>
#include <stdlib.h>
#include <emmintrin.h>
int main(int argc, char **argv) {
  long n = atol(argv[1]);
  volatile double seed = 1.0000001;
  double a = seed, b = 0.5 * seed, c = 0.25 * seed;
  __m128d v = _mm_set1_pd(seed), w = _mm_set1_pd(1e-9);
  for (long i = 0; i < n; ++i) {
    a = a * b + c;          /* 2 */
    c = c - 1e-12;          /* 1 */
    v = _mm_add_pd(v, w);   /* 2 lanes */
    __asm__ volatile("" : "+x"(v), "+x"(a), "+x"(c));
  }
  double o[2]; _mm_storeu_pd(o, v);
  printf("%g %g %g\n", a, c, o[0] + o[1]);
  return 0;
}
"""
    c, exe = os.path.join(d, "k.c"), os.path.join(d, "k")
    open(c, "w").write(src)
    subprocess.run(["gcc", "-O2", "-fno-tree-vectorize", c, "-o", exe], check=True)
    cg = os.path.join(d, "k.out")
    subprocess.run(["valgrind", "--tool=callgrind", "--dump-instr=yes", "--dump-line=no", "--callgrind-out-file=" + cg, exe, str(n)],
                   check=True, capture_output=True)
    events, funcs = roofline.parse_callgrind(cg)
    fp = {exe: roofline.disassemble(exe)}
    flops = sum(n_ * fp[exe].get(a, 0) for (ob, fn), e in funcs.items() if ob == exe for a, n_ in e["addr"].items())
    want = 5 * n
    print("counted %d flops, expected %d" % (flops, want))
    t.check(abs(flops - want) <= 0.01 * want, "the C loop's flops within 1%%: %d against %d" % (flops, want))
else:
    print("valgrind or gcc not installed: the executed-instruction check is not run")
shutil.rmtree(d, ignore_errors=True)
print("PASS")
