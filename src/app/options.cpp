#include "fluidbed/options.hpp"

#include <string>

namespace fluidbed {

namespace {

std::string FormatReal(PetscReal v)
{
  if (v >= PETSC_MAX_REAL) return "inf";
  if (v <= PETSC_MIN_REAL) return "-inf";
  char buf[64];
  PetscCallAbort(PETSC_COMM_SELF, PetscSNPrintf(buf, sizeof(buf), "%.6g", (double)v));
  return buf;
}

std::string FormatRange(const RealRange &r)
{
  return std::string(r.lo_open ? "(" : "[") + FormatReal(r.lo) + ", " + FormatReal(r.hi) + (r.hi_open ? ")" : "]");
}

bool InRange(const RealRange &r, PetscReal v)
{
  if (PetscIsInfOrNanReal(v)) return false;
  if (r.lo_open ? !(v > r.lo) : !(v >= r.lo)) return false;
  if (r.hi_open ? !(v < r.hi) : !(v <= r.hi)) return false;
  return true;
}

std::string HelpText(const char text[], const char unit[], const std::string &range)
{
  std::string s = text;
  if (unit && unit[0]) s += std::string(" [") + unit + "]";
  s += ", range " + range;
  return s;
}

} // namespace

const char *OptionName(PetscOptionItems *PetscOptionsObject, const char name[])
{
  static thread_local std::string full;
  full = "-";
  if (PetscOptionsObject && PetscOptionsObject->prefix) full += PetscOptionsObject->prefix;
  full += (name[0] == '-') ? name + 1 : name;
  return full.c_str();
}

PetscErrorCode OptionsReal(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char unit[], RealRange range,
                           PetscReal *value, PetscBool *set)
{
  const std::string rs   = FormatRange(range);
  const std::string help = HelpText(text, unit, rs);
  PetscBool         flg  = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal_Private(PetscOptionsObject, name, help.c_str(), "", *value, value, &flg));
  PetscCheck(InRange(range, *value), PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s = %.6g is out of range: allowed %s%s%s",
             OptionName(PetscOptionsObject, name), (double)*value, rs.c_str(), unit && unit[0] ? " " : "", unit ? unit : "");
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsInt(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], PetscInt lo, PetscInt hi,
                          PetscInt *value, PetscBool *set)
{
  const std::string rs =
    "[" + std::to_string((long long)lo) + ", " + (hi == PETSC_MAX_INT ? std::string("inf") : std::to_string((long long)hi)) + "]";
  const std::string help = std::string(text) + ", range " + rs;
  PetscBool         flg  = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsInt_Private(PetscOptionsObject, name, help.c_str(), "", *value, value, &flg, PETSC_MIN_INT, PETSC_MAX_INT));
  PetscCheck(*value >= lo && *value <= hi, PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s = %" PetscInt_FMT " is out of range: allowed %s", OptionName(PetscOptionsObject, name), *value, rs.c_str());
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsRealArray(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char unit[],
                                RealRange range, PetscReal values[], PetscInt *n, PetscBool exact, PetscBool *set)
{
  const std::string rs   = FormatRange(range);
  const std::string help = HelpText(text, unit, rs);
  const PetscInt    nmax = *n;
  PetscBool         flg  = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsRealArray_Private(PetscOptionsObject, name, help.c_str(), "", values, n, &flg));
  if (!flg) *n = nmax;
  PetscCheck(!flg || !exact || *n == nmax, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
             "%s needs %" PetscInt_FMT " comma-separated values, got %" PetscInt_FMT, OptionName(PetscOptionsObject, name), nmax, *n);
  for (PetscInt i = 0; flg && i < *n; ++i) // defaults are the caller's
    PetscCheck(InRange(range, values[i]), PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s entry %" PetscInt_FMT " = %.6g is out of range: allowed %s%s%s", OptionName(PetscOptionsObject, name), i,
               (double)values[i], rs.c_str(), unit && unit[0] ? " " : "", unit ? unit : "");
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsEnum(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char *const list[],
                           PetscEnum *value, PetscBool *set)
{
  char      buf[256];
  PetscBool given = PETSC_FALSE, found = PETSC_FALSE;
  PetscEnum e;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(PetscOptionsObject->options, PetscOptionsObject->prefix, name, buf, sizeof(buf), &given));
  if (given) {
    PetscCall(PetscEnumFind(list, buf, &e, &found));
    if (!found) {
      PetscInt n = 0;
      while (list[n]) ++n;
      std::string names;
      for (PetscInt i = 0; i < n - 2; ++i) names += (names.empty() ? "" : ", ") + std::string(list[i]);
      SETERRQ(PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s %s is not one of: %s", OptionName(PetscOptionsObject, name), buf,
              names.c_str());
    }
  }
  PetscCall(PetscOptionsEnum_Private(PetscOptionsObject, name, text, "", list, *value, value, set));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
