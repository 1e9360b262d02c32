// One typed request for both front ends of the driver, the ldaec command
// line (Options.h) and the Python module (python/src/Module.cpp): the
// option values they take as text are parsed here once, into enums, with
// the messages each front end has always printed; runOptions() is the one
// mapping of a run's request onto the runtime's SimOptions.
#pragma once

#include "Compilation.h"

#include "ldae/Simulation.h"
#include "passes/Method.h"
#include "support/Expected.h"

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ldae::driver {

/// An option that is on, off, or left to a rule (--jit,
/// --algebraic-error-test; --causalize takes on and off only).
enum class SwitchChoice { Auto, On, Off };

/// What `--emit` prints: nothing, or one intermediate form.
enum class EmitKind { None, Flat, Reduced, Llvm, C };

/// An enum value and the word the user writes for it.
template <typename E> struct Spelling {
  const char *name;
  E value;
};

inline constexpr Spelling<SwitchChoice> kSwitchSpellings[] = {
    {"on", SwitchChoice::On},
    {"off", SwitchChoice::Off},
    {"auto", SwitchChoice::Auto}};
inline constexpr Spelling<EmitKind> kEmitSpellings[] = {
    {"flat", EmitKind::Flat},
    {"reduced", EmitKind::Reduced},
    {"llvm", EmitKind::Llvm},
    {"c", EmitKind::C}};

/// The value spelled `text` in `table`, or nothing.
template <typename E, size_t N>
std::optional<E> parseSpelling(const Spelling<E> (&table)[N],
                               std::string_view text) {
  for (const Spelling<E> &s : table)
    if (text == s.name)
      return s.value;
  return std::nullopt;
}

/// Every word of `table`, in its order (CLI11's IsMember check).
template <typename E, size_t N>
std::vector<std::string> spellings(const Spelling<E> (&table)[N]) {
  std::vector<std::string> names;
  for (const Spelling<E> &s : table)
    names.push_back(s.name);
  return names;
}

/// What a switch sets: unset for Auto (the rule decides).
std::optional<bool> switchSetting(SwitchChoice choice);
/// The switch that sets `setting` (Python's True, False and None).
SwitchChoice switchChoice(std::optional<bool> setting);

/// The text options of the Python module, with the messages it raises
/// (the command line refuses the same words through CLI11's checks).
Expected<passes::Method> parseMethodOption(const std::string &text);
Expected<SwitchChoice> parseJitOption(const std::string &text);
Expected<runtime::IntegratorChoice>
parseIntegratorOption(const std::string &text);

/// The compile options both front ends take alike.
struct CompileChoices {
  passes::Method method = passes::Method::DummyDerivatives;
  SwitchChoice jit = SwitchChoice::Auto;
  std::string cacheDir; ///< "": no object cache
};

/// Writes `choices` into `request` (the method of its passes, the JIT and
/// the cache of its codegen).
void applyCompileChoices(const CompileChoices &choices,
                         CompileRequest &request);

/// One run of a compiled model: unset values fall back to the model's
/// experiment annotation, then to the runtime's defaults.
struct RunRequest {
  std::optional<double> start, stop, rtol, atol, interval;
  bool everyStep = false;
  std::vector<double> times;
  /// The columns by name; empty: those the compile selected.
  std::vector<std::string> outputs;
  runtime::IntegratorChoice integrator = runtime::IntegratorChoice::Auto;
  SwitchChoice algebraicErrorTest = SwitchChoice::Auto;
  std::map<std::string, double> params, starts;
  bool progress = false;
};

/// An Error, with the command line's message, for a value that is not a
/// finite number (NaN and inf were run as given).
Expected<bool> checkFinite(const RunRequest &run);

/// The runtime's options for `run` of the model `compile` made; the log,
/// the interrupt poll and the row sink are the caller's to set.
runtime::SimOptions runOptions(const RunRequest &run,
                               const CompileRequest &compile);

} // namespace ldae::driver
