#!/usr/bin/env python3
"""The layers of the source tree (docs/architecture.md): each module includes only its own headers and those of the
modules below it, so that no include runs back up, and a module's private headers in src/ only from its own files. Reads every #include "fluidbed/..." of include/ and src/; fails
naming the file, the header and both modules when one runs up or sideways, or when a file or header belongs to no
module (a new one must be placed in a layer here and in docs/architecture.md)."""
import os
import re
import sys

SRC = os.environ.get("FLUIDBED_SOURCE", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

# module: (layer, public headers in include/fluidbed/, source folders in src/)
MODULES = {
    "kernels": (0, ["kernels/"], []),
    "core": (1, ["options.hpp", "phases.hpp", "dmda_field.hpp", "registry.hpp", "files.hpp", "status.hpp"], ["core"]),
    "grids": (2, ["domain.hpp", "grids.hpp"], ["grids"]),
    "particles": (3, ["particles.hpp", "particle_motion.hpp", "particle_system.hpp"], ["particles"]),
    "fluid": (3, ["fluid.hpp", "inlets.hpp", "fast_poisson.hpp"], ["fluid"]),
    "contact": (4, ["dem.hpp", "contact_model.hpp"], ["contact"]),
    "coupling": (4, ["coupling.hpp", "drag_laws.hpp"], ["coupling"]),
    "io": (5, ["io.hpp", "hdf5io.hpp", "outputs.hpp", "checkpoint_check.hpp"], ["io"]),
    "analysis": (6, ["averaging.hpp", "probes.hpp"], ["analysis"]),
    "guards": (6, ["guards.hpp"], ["guards"]),
    "app": (7, ["simulation.hpp", "scene_model.hpp", "option_report.hpp", "default_scene.inc"], ["app", "main.cpp"]),
}

# Public headers meant for a few modules only: the particles' motion in full is the DEM's own (particles, and the
# contact stage that extends it); the modules above see it through particle_motion.hpp and dem.hpp.
RESTRICTED = {"particle_system.hpp": ["particles", "contact"]}


def header_module(name):
    for m, (_, headers, _) in MODULES.items():
        if any(name == h or (h.endswith("/") and name.startswith(h)) for h in headers):
            return m
    return None


def file_module(rel):
    if rel.startswith("include/fluidbed/"):
        return header_module(rel[len("include/fluidbed/"):])
    parts = rel.split("/")
    for m, (_, _, folders) in MODULES.items():
        if parts[0] == "src" and parts[1] in folders:
            return m
    return None


def main():
    errors, files = [], 0
    for top in ("include/fluidbed", "src"):
        for d, _, names in os.walk(os.path.join(SRC, top)):
            for n in sorted(names):
                if not n.endswith((".hpp", ".cpp", ".inc")):
                    continue
                rel = os.path.relpath(os.path.join(d, n), SRC)
                if n.endswith(".inc"):
                    continue  # generated data included by main
                files += 1
                mod = file_module(rel)
                if mod is None:
                    errors.append("%s belongs to no module: place it in a layer (tests/layout/test_layers.py, docs/architecture.md)" % rel)
                    continue
                layer = MODULES[mod][0]
                text = open(os.path.join(d, n)).read()
                if mod == "kernels" and re.search(r"#include\s*<petsc", text):
                    errors.append("%s: a kernel includes PETSc (kernels are plain functions)" % rel)
                # a module's private headers (src/<module>/*.hpp) are its own
                for inc in re.findall(r'#include\s*"((?!fluidbed/)[^"]+\.hpp)"', text):
                    target = os.path.relpath(os.path.normpath(os.path.join(d, inc)), SRC)
                    tm = file_module(target)
                    if tm != mod:
                        errors.append("%s (%s) includes %s, a private header of %s" % (rel, mod, target, tm))
                for inc in re.findall(r'#include\s*"fluidbed/([^"]+)"', text):
                    im = header_module(inc)
                    if im is None:
                        errors.append("%s includes fluidbed/%s, which belongs to no module" % (rel, inc))
                    elif inc in RESTRICTED and mod not in RESTRICTED[inc]:
                        errors.append("%s (%s) includes fluidbed/%s, which only %s may include" % (rel, mod, inc, " and ".join(RESTRICTED[inc])))
                    elif im != mod and MODULES[im][0] >= layer:
                        errors.append("%s (%s, layer %d) includes fluidbed/%s (%s, layer %d): includes must run down the layers" %
                                      (rel, mod, layer, inc, im, MODULES[im][0]))
    print("%d files checked against %d modules" % (files, len(MODULES)))
    for e in errors:
        print("FAIL:", e)
    if files < 50:
        print("FAIL: only %d source files found under %s" % (files, SRC))
        return 1
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
