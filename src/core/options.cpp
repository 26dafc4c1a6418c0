#include "fluidbed/options.hpp"

#include <petscksp.h>

#include <cstring>
#include <set>
#include <string>
#include <vector>

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

bool Unbounded(const RealRange &r)
{
  return r.lo <= PETSC_MIN_REAL && r.hi >= PETSC_MAX_REAL;
}

std::string FormatRange(const RealRange &r)
{
  return std::string(r.lo_open ? "(" : "[") + FormatReal(r.lo) + ", " + FormatReal(r.hi) + (r.hi_open ? ")" : "]");
}

std::string FormatIntRange(PetscInt lo, PetscInt hi)
{
  return "[" + (lo == PETSC_MIN_INT ? std::string("-inf") : std::to_string((long long)lo)) + ", " +
         (hi == PETSC_MAX_INT ? std::string("inf") : std::to_string((long long)hi)) + "]";
}

bool InRange(const RealRange &r, PetscReal v)
{
  if (PetscIsInfOrNanReal(v)) return false;
  if (r.lo_open ? !(v > r.lo) : !(v >= r.lo)) return false;
  if (r.hi_open ? !(v < r.hi) : !(v <= r.hi)) return false;
  return true;
}

std::string HelpText(const char text[], const char unit[], const RealRange &range)
{
  std::string s = text;
  if (unit && unit[0]) s += std::string(" [") + unit + "]";
  if (!Unbounded(range)) s += ", range " + FormatRange(range);
  return s;
}

// "a number in (0, 1e+12] N/m": what a real option allows, for messages.
std::string AllowedReal(const RealRange &range, const char unit[])
{
  std::string s = Unbounded(range) ? "a finite number" : "a number in " + FormatRange(range);
  if (unit && unit[0]) s += std::string(" ") + unit;
  return s;
}

std::string AllowedInt(PetscInt lo, PetscInt hi)
{
  return (lo == PETSC_MIN_INT && hi == PETSC_MAX_INT) ? std::string("a whole number") : "a whole number in " + FormatIntRange(lo, hi);
}

const char kAllowedBool[] = "1, 0, true, false, yes, no, on, off (or the option alone, meaning true)";

// The option's text as given: *given, and *value (NULL or empty when the option stands without a value, as when it
// is the last word or followed by another option).
PetscErrorCode RawValue(PetscOptionItems *PetscOptionsObject, const char name[], const char **value, PetscBool *given)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsFindPair(PetscOptionsObject->options, PetscOptionsObject->prefix, name, value, given));
  PetscFunctionReturn(0);
}

bool Empty(const char *value)
{
  return !value || !value[0];
}

// PETSc's own conversion of an option's text, with its error handler silenced: the caller reports a failure with
// the option's name (PETSc's message names the text only).
template <class T>
PetscErrorCode Converts(PetscErrorCode (*convert)(const char[], T *), const char *text, bool *ok)
{
  T v;
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  const PetscErrorCode ierr = convert(text, &v);
  PetscCall(PetscPopErrorHandler());
  *ok = ierr == 0;
  PetscFunctionReturn(0);
}

// The comma-separated entries of an array option as PETSc splits them (empty entries are skipped).
std::vector<std::string> Entries(const char *value)
{
  std::vector<std::string> out;
  std::string              s = value ? value : "", cur;
  for (char c : s + ",") {
    if (c == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else cur += c;
  }
  return out;
}

// The first entry of an array option that PETSc cannot read as a number (reals) or a whole number or range a-b
// (integers); empty when every entry reads.
PetscErrorCode BadEntry(const char *value, bool integer, std::string *bad)
{
  PetscFunctionBeginUser;
  bad->clear();
  for (const std::string &e : Entries(value)) {
    bool ok = false;
    if (integer) {
      PetscCall(Converts<PetscInt>(PetscOptionsStringToInt, e.c_str(), &ok));
      const std::size_t dash = e.find('-', 1);
      if (!ok && dash != std::string::npos && dash + 1 < e.size()) { // PETSc's "a-b": a, a+1, ..., b-1
        bool ok_lo = false, ok_hi = false;
        PetscCall(Converts<PetscInt>(PetscOptionsStringToInt, e.substr(0, dash).c_str(), &ok_lo));
        PetscCall(Converts<PetscInt>(PetscOptionsStringToInt, e.substr(dash + 1).c_str(), &ok_hi));
        ok = ok_lo && ok_hi;
      }
    } else PetscCall(Converts<PetscReal>(PetscOptionsStringToReal, e.c_str(), &ok));
    if (!ok) {
      *bad = e;
      break;
    }
  }
  PetscFunctionReturn(0);
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

// A given option has a value that converts to T: else an input error naming the option, what it is not (kind) and what
// is allowed.
template <class T>
PetscErrorCode CheckGivenValue(PetscOptionItems *PetscOptionsObject, const char name[], PetscErrorCode (*convert)(const char[], T *),
                               const char *kind, const std::string &allowed)
{
  PetscBool   given;
  const char *raw;
  bool        ok = true;

  PetscFunctionBeginUser;
  PetscCall(RawValue(PetscOptionsObject, name, &raw, &given));
  PetscCheck(!given || !Empty(raw), PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s is given without a value; allowed: %s",
             OptionName(PetscOptionsObject, name), allowed.c_str());
  if (given) PetscCall(Converts<T>(convert, raw, &ok));
  PetscCheck(ok, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s %s is not %s; allowed: %s", OptionName(PetscOptionsObject, name), raw,
             kind, allowed.c_str());
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsReal(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char unit[], RealRange range,
                           PetscReal *value, PetscBool *set)
{
  const std::string rs      = FormatRange(range);
  const std::string help    = HelpText(text, unit, range);
  const std::string allowed = AllowedReal(range, unit);
  PetscBool         flg     = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(CheckGivenValue<PetscReal>(PetscOptionsObject, name, PetscOptionsStringToReal, "a number", allowed));
  PetscCall(PetscOptionsReal_Private(PetscOptionsObject, name, help.c_str(), "", *value, value, &flg));
  PetscCheck(InRange(range, *value), PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s = %.6g is out of range: allowed %s%s%s",
             OptionName(PetscOptionsObject, name), (double)*value, rs.c_str(), unit && unit[0] ? " " : "", unit ? unit : "");
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsInt(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], PetscInt lo, PetscInt hi,
                          PetscInt *value, PetscBool *set)
{
  const std::string rs      = FormatIntRange(lo, hi);
  const std::string help    = std::string(text) + ", range " + rs;
  const std::string allowed = AllowedInt(lo, hi);
  PetscBool         flg     = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(CheckGivenValue<PetscInt>(PetscOptionsObject, name, PetscOptionsStringToInt, "a whole number", allowed));
  PetscCall(PetscOptionsInt_Private(PetscOptionsObject, name, help.c_str(), "", *value, value, &flg, PETSC_MIN_INT, PETSC_MAX_INT));
  PetscCheck(*value >= lo && *value <= hi, PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s = %" PetscInt_FMT " is out of range: allowed %s", OptionName(PetscOptionsObject, name), *value, rs.c_str());
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

namespace {

// Checks an array option's text before PETSc reads it: a value is given, every entry converts, and there are at
// most nmax entries (PETSc stops reading at nmax and drops the rest without a word). `allowed` describes the
// entries for messages.
PetscErrorCode CheckArrayText(PetscOptionItems *PetscOptionsObject, const char name[], bool integer, PetscInt nmax,
                              const std::string &allowed)
{
  const char *raw;
  PetscBool   given, flg;
  PetscInt    n = nmax + 1;
  std::string bad;

  PetscFunctionBeginUser;
  PetscCall(RawValue(PetscOptionsObject, name, &raw, &given));
  if (!given) PetscFunctionReturn(0);
  PetscCheck(!Empty(raw), PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s is given without a value; allowed: %s",
             OptionName(PetscOptionsObject, name), allowed.c_str());
  PetscCall(BadEntry(raw, integer, &bad));
  PetscCheck(bad.empty(), PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s %s: %s is not %s; allowed: %s",
             OptionName(PetscOptionsObject, name), raw, bad.c_str(), integer ? "a whole number" : "a number", allowed.c_str());
  // PETSc's own count (its a-b ranges included), read silently: an integer range that does not fit fails here
  PetscErrorCode ierr;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  if (integer) {
    std::vector<PetscInt> scratch((std::size_t)n);
    ierr = PetscOptionsGetIntArray(PetscOptionsObject->options, PetscOptionsObject->prefix, name, scratch.data(), &n, &flg);
  } else {
    std::vector<PetscReal> scratch((std::size_t)n);
    ierr = PetscOptionsGetRealArray(PetscOptionsObject->options, PetscOptionsObject->prefix, name, scratch.data(), &n, &flg);
  }
  PetscCall(PetscPopErrorHandler());
  PetscCheck(!ierr && n <= nmax, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
             "%s %s has more than %" PetscInt_FMT " values; allowed: %s", OptionName(PetscOptionsObject, name), raw, nmax, allowed.c_str());
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode OptionsRealArray(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char unit[],
                                RealRange range, PetscReal values[], PetscInt *n, PetscBool exact, PetscBool *set)
{
  const std::string rs      = FormatRange(range);
  const std::string help    = HelpText(text, unit, range);
  const PetscInt    nmax    = *n;
  PetscBool         flg     = PETSC_FALSE;
  const std::string allowed = (exact ? std::to_string((long long)nmax) : "up to " + std::to_string((long long)nmax)) + " comma-separated " +
                              (Unbounded(range) ? std::string("finite numbers") : "numbers in " + rs) +
                              (unit && unit[0] ? std::string(" ") + unit : std::string());

  PetscFunctionBeginUser;
  PetscCall(CheckArrayText(PetscOptionsObject, name, false, nmax, allowed));
  PetscCall(PetscOptionsRealArray_Private(PetscOptionsObject, name, help.c_str(), "", values, n, &flg));
  if (!flg) *n = nmax;
  if (flg && exact && *n != nmax) {
    const char *raw;
    PetscBool   given;
    PetscCall(RawValue(PetscOptionsObject, name, &raw, &given));
    SETERRQ(PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
            "%s %s needs %" PetscInt_FMT " comma-separated values, got %" PetscInt_FMT "; allowed: %s",
            OptionName(PetscOptionsObject, name), raw, nmax, *n, allowed.c_str());
  }
  for (PetscInt i = 0; flg && i < *n; ++i) // defaults are the caller's
    PetscCheck(InRange(range, values[i]), PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s entry %" PetscInt_FMT " = %.6g is out of range: allowed %s%s%s", OptionName(PetscOptionsObject, name), i,
               (double)values[i], rs.c_str(), unit && unit[0] ? " " : "", unit ? unit : "");
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsIntArray(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], PetscInt lo, PetscInt hi,
                               PetscInt values[], PetscInt *n, PetscBool *set)
{
  const bool        full = lo == PETSC_MIN_INT && hi == PETSC_MAX_INT;
  const std::string rs   = FormatIntRange(lo, hi);
  const std::string help = full ? std::string(text) : std::string(text) + ", range " + rs;
  const PetscInt    nmax = *n;
  const std::string allowed =
    "up to " + std::to_string((long long)nmax) + " comma-separated whole numbers" + (full ? std::string() : " in " + rs);
  PetscBool flg = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(CheckArrayText(PetscOptionsObject, name, true, nmax, allowed));
  PetscCall(PetscOptionsIntArray_Private(PetscOptionsObject, name, help.c_str(), "", values, n, &flg));
  if (!flg) *n = nmax;
  for (PetscInt i = 0; flg && i < *n; ++i)
    PetscCheck(values[i] >= lo && values[i] <= hi, PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s entry %" PetscInt_FMT " = %" PetscInt_FMT " is out of range: allowed %s", OptionName(PetscOptionsObject, name), i,
               values[i], rs.c_str());
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsBool(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], PetscBool *value, PetscBool *set)
{
  const char *raw;
  PetscBool   given;
  bool        ok = true;

  PetscFunctionBeginUser;
  PetscCall(RawValue(PetscOptionsObject, name, &raw, &given));
  if (given && !Empty(raw)) PetscCall(Converts<PetscBool>(PetscOptionsStringToBool, raw, &ok));
  PetscCheck(ok, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s %s is not a boolean; allowed: %s",
             OptionName(PetscOptionsObject, name), raw, kAllowedBool);
  PetscCall(PetscOptionsBool_Private(PetscOptionsObject, name, text, "", *value, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsString(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char what[], char value[],
                             size_t len, PetscBool *set)
{
  const char *raw;
  PetscBool   given;

  PetscFunctionBeginUser;
  PetscCall(RawValue(PetscOptionsObject, name, &raw, &given));
  PetscCheck(!given || !Empty(raw), PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s is given without a value; allowed: %s",
             OptionName(PetscOptionsObject, name), what);
  PetscCheck(!given || strlen(raw) < len, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
             "%s %s is too long; allowed: %s of at most %d characters", OptionName(PetscOptionsObject, name), raw, what, (int)len - 1);
  PetscCall(PetscOptionsString_Private(PetscOptionsObject, name, text, "", value, value, len, set));
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsEnum(PetscOptionItems *PetscOptionsObject, const char name[], const char text[], const char *const list[],
                           PetscEnum *value, PetscBool *set)
{
  const char *raw;
  PetscBool   given = PETSC_FALSE, found = PETSC_FALSE;
  PetscEnum   e;
  PetscInt    n = 0;
  std::string names;

  PetscFunctionBeginUser;
  while (list[n]) ++n;
  for (PetscInt i = 0; i < n - 2; ++i) names += (names.empty() ? "" : ", ") + std::string(list[i]);
  PetscCall(RawValue(PetscOptionsObject, name, &raw, &given));
  PetscCheck(!given || !Empty(raw), PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s is given without a value; allowed: %s",
             OptionName(PetscOptionsObject, name), names.c_str());
  if (given) PetscCall(PetscEnumFind(list, raw, &e, &found));
  PetscCheck(!given || found, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "%s %s is not one of: %s",
             OptionName(PetscOptionsObject, name), raw, names.c_str());
  PetscCall(PetscOptionsEnum_Private(PetscOptionsObject, name, text, "", list, *value, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsCheckSolverTypes(MPI_Comm comm, const char prefix[])
{
  struct Kind {
    const char       *suffix, *what;
    PetscFunctionList list;
  };
  char *all = NULL;

  PetscFunctionBeginUser;
  PetscCall(KSPInitializePackage()); // registers the KSP, PC and Mat types
  PetscCall(PCInitializePackage());
  PetscCall(MatInitializePackage());
  const Kind kinds[] = {
    {"ksp_type", "KSP type (Krylov method)", KSPList}, {"pc_type", "PC type (preconditioner)", PCList}, {"mat_type", "Mat type", MatList}};
  // The names in the database as "-name value -name ..." (without marking any of them used: an option that no
  // solver reads must still be reported as unused at the end of the run)
  PetscCall(PetscOptionsGetAll(NULL, &all));
  std::vector<std::string> words;
  {
    std::string s = all ? all : "", w;
    for (char c : s + " ") {
      if (c == ' ') {
        if (!w.empty()) words.push_back(w);
        w.clear();
      } else w += c;
    }
  }
  PetscCall(PetscFree(all));
  const std::string head = std::string("-") + prefix;
  for (std::size_t i = 0; i < words.size(); ++i) {
    PetscBool key;
    PetscCall(PetscOptionsValidKey(words[i].c_str(), &key));
    if (!key || words[i].compare(0, head.size(), head) != 0) continue;
    for (const Kind &k : kinds) {
      const std::string &w  = words[i];
      const std::size_t  ls = strlen(k.suffix);
      // -<prefix>ksp_type, or -<prefix>..._ksp_type (level smoothers, sub-solvers)
      if (w.size() < head.size() + ls || w.compare(w.size() - ls, ls, k.suffix) != 0) continue;
      if (w.size() > head.size() + ls && w[w.size() - ls - 1] != '_') continue;
      PetscBool next_key = PETSC_TRUE;
      if (i + 1 < words.size()) PetscCall(PetscOptionsValidKey(words[i + 1].c_str(), &next_key));
      PetscCheck(!next_key, comm, PETSC_ERR_USER_INPUT, "%s is given without a value; allowed: a %s", w.c_str(), k.what);
      const char **names = NULL;
      int          nn    = 0;
      PetscCall(PetscFunctionListGet(k.list, &names, &nn));
      std::set<std::string> known;
      for (int j = 0; j < nn; ++j) // the array ends with NULL (counted in nn)
        if (names[j]) known.insert(names[j]);
      PetscCall(PetscFree(names));
      if (k.list == MatList) // MatSetType also takes the root of a seq/mpi pair: aij for seqaij and mpiaij
        for (const std::string &m : std::set<std::string>(known))
          if (m.compare(0, 3, "seq") == 0 && known.count("mpi" + m.substr(3))) known.insert(m.substr(3));
      if (known.count(words[i + 1])) continue;
      std::string list;
      for (const std::string &s : known) list += (list.empty() ? "" : ", ") + s;
      SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s %s is not a registered %s; allowed: %s", w.c_str(), words[i + 1].c_str(), k.what,
              list.c_str());
    }
  }
  PetscFunctionReturn(0);
}

} // namespace fluidbed
