// Range-checked PETSc options with units in their help text.
//
// PETSc 3.18 has no PetscOptionsBoundedReal, and its bounded integer options report "Newly set value 7 greater
// than allowed bound 5" without naming the option. These helpers read an option inside a
// PetscOptionsBegin/End block and stop with a message that names the option, its value and the allowed range.
#pragma once

#include <petscsys.h>

namespace fluidbed {

// A closed or open interval; use PETSC_MAX_REAL / PETSC_MIN_REAL for no bound.
struct RealRange {
  PetscReal lo, hi;
  bool      lo_open = false, hi_open = false;
};

inline RealRange Positive(PetscReal hi = PETSC_MAX_REAL)
{
  return {0.0, hi, true, false};
}
inline RealRange NonNegative(PetscReal hi = PETSC_MAX_REAL)
{
  return {0.0, hi, false, false};
}
inline RealRange Closed(PetscReal lo, PetscReal hi)
{
  return {lo, hi, false, false};
}

// Real option -<prefix><name>: "text [unit], range ..." in -help; error PETSC_ERR_ARG_OUTOFRANGE outside range.
PetscErrorCode OptionsReal(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char unit[], RealRange range,
                           PetscReal *value, PetscBool *set);
// Integer option with an inclusive range [lo, hi].
PetscErrorCode OptionsInt(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], PetscInt lo, PetscInt hi,
                          PetscInt *value, PetscBool *set);
// Array of exactly n reals (or up to n when exact is false: *n returns the count read), each within range.
PetscErrorCode OptionsRealArray(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char unit[],
                                RealRange range, PetscReal values[], PetscInt *n, PetscBool exact, PetscBool *set);

// Enumerated option (PETSc's list format: names, type name, prefix, NULL); a value not in the list stops with a
// message naming the option and the allowed values (PETSc's own check raises PETSC_ERR_USER with a traceback).
PetscErrorCode OptionsEnum(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char *const list[],
                           PetscEnum *value, PetscBool *set);

// The option name with the block's prefix, e.g. "-dem_kn", for messages.
const char *OptionName(PetscOptionItems *PetscOptionsObject, const char name[]);

} // namespace fluidbed
