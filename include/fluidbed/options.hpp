// Range-checked PETSc options with units in their help text.
//
// PETSc 3.18 has no PetscOptionsBoundedReal, its bounded integer options report "Newly set value 7 greater than
// allowed bound 5" without naming the option, and a value that is not a number ("Input string abc has no numeric
// value") or an option given without a value (silently ignored) is reported without the option, or not at all.
// These helpers read an option inside a PetscOptionsBegin/End block: they first check the option's text as given
// and stop, on every rank, with one message that names the option, its value and what is allowed; then PETSc reads
// the value as it always did (the same conversion, the same -help line).
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
// Any finite number (lists checked elsewhere, e.g. particle positions against the box): no range in -help.
inline RealRange AnyReal()
{
  return {PETSC_MIN_REAL, PETSC_MAX_REAL, false, false};
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
// Array of up to *n integers (PETSc's syntax, "a-b" for a range included), each in [lo, hi]; *n returns the count.
PetscErrorCode OptionsIntArray(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], PetscInt lo, PetscInt hi,
                               PetscInt values[], PetscInt *n, PetscBool *set);
// Boolean option: alone, or with 1/0, true/false, yes/no, on/off.
PetscErrorCode OptionsBool(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], PetscBool *value, PetscBool *set);
// String option that must carry a value; `what` names the value in messages ("a directory", "an HDF5 file").
PetscErrorCode OptionsString(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char what[], char value[],
                             size_t len, PetscBool *set);

// Enumerated option (PETSc's list format: names, type name, prefix, NULL); a value not in the list stops with a
// message naming the option and the allowed values (PETSc's own check raises PETSC_ERR_USER with a traceback).
PetscErrorCode OptionsEnum(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char *const list[],
                           PetscEnum *value, PetscBool *set);

// The option name with the block's prefix, e.g. "-dem_kn", for messages.
const char *OptionName(PetscOptionItems *PetscOptionsObject, const char name[]);

// Checks every option -<prefix>...ksp_type, -<prefix>...pc_type and -<prefix>...mat_type in the database against
// PETSc's registered types before a solver reads them (PETSc's own error, PETSC_ERR_ARG_UNKNOWN_TYPE, names neither
// the option nor the choices): PETSC_ERR_USER_INPUT naming the option, the value and the registered names.
PetscErrorCode OptionsCheckSolverTypes(MPI_Comm comm, const char prefix[]);

} // namespace fluidbed
