// --outputs names and patterns expanded against the flat model (see
// OutputSelection.h).
#include "OutputSelection.h"
#include "ldae/ResultWriter.h"

#include "ir/Query.h"

#include <algorithm>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

namespace ldae::driver {

namespace {

/// Whether `text` matches `pattern` in full: `*` any run of characters
/// (also none), `?` one character, anything else itself (`[` too: array
/// subscripts are part of names). Iterative, with backtracking to the
/// last `*` only, so linear in practice.
bool globMatch(std::string_view pattern, std::string_view text) {
  size_t p = 0, t = 0, star = std::string_view::npos, mark = 0;
  while (t < text.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
      ++p;
      ++t;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      mark = t;
    } else if (star != std::string_view::npos) {
      p = star + 1;
      t = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*')
    ++p;
  return p == pattern.size();
}

bool isGlob(const std::string &pattern) {
  return pattern.find_first_of("*?") != std::string::npos;
}

/// The names a run can report, in model order: each variable (the event
/// inputs the compiler makes left out) with der(x) right after x where the
/// equations differentiate x, then the parameters and constants (the
/// compiled model keeps both in its parameter vector).
std::vector<std::string> reportableNames(const ir::Model &model) {
  std::unordered_set<ir::VarId> differentiated;
  for (const ir::Equation &eq : model.equations)
    for (ir::VarKey k : ir::freeVariables(eq.residual))
      if (k.order >= 1)
        differentiated.insert(k.var);
  std::vector<std::string> names;
  for (ir::VarId v = 0; v < model.variables.size(); ++v) {
    const ir::Variable &var = model.variables[v];
    if (var.input != ir::EventInput::None || var.generated)
      continue;
    names.push_back(var.name);
    if (differentiated.count(v))
      names.push_back(model.variableName(ir::VarKey{v, 1}));
  }
  for (const ir::Parameter &p : model.parameters)
    if (!p.discrete && !p.generated)
      names.push_back(p.name);
  return names;
}

} // namespace

std::optional<std::vector<std::string>>
selectOutputs(const ir::Model &model, const std::vector<std::string> &patterns,
              DiagnosticEngine &diags) {
  std::vector<std::string> names = reportableNames(model);
  std::unordered_map<std::string, size_t> position;
  for (size_t i = 0; i < names.size(); ++i)
    position.emplace(names[i], i);
  std::vector<char> picked(names.size(), 0);
  // der(x) of an x the equations do not differentiate (yet: index
  // reduction may) goes on to the passes, which name it if it never is.
  std::vector<std::string> extra;
  bool ok = true;
  for (const std::string &pattern : patterns) {
    bool any = false;
    if (auto at = position.find(pattern); at != position.end()) {
      picked[at->second] = any = true;
    } else if (isGlob(pattern)) {
      for (size_t i = 0; i < names.size(); ++i)
        if (globMatch(pattern, names[i]))
          picked[i] = any = true;
    } else if (pattern.size() > 5 && pattern.compare(0, 4, "der(") == 0 &&
               pattern.back() == ')' &&
               model.findVariable(pattern.substr(4, pattern.size() - 5))) {
      if (std::find(extra.begin(), extra.end(), pattern) == extra.end())
        extra.push_back(pattern);
      any = true;
    }
    if (any)
      continue;
    ok = false;
    std::vector<std::string> close = runtime::closeNames(names, pattern);
    if (close.empty()) {
      diags.report(DiagId::ErrUnknownOutputOption, SourceLoc{}, {pattern});
      continue;
    }
    std::string list;
    for (size_t i = 0; i < close.size(); ++i)
      list += (i ? ", '" : "'") + close[i] + "'";
    diags.report(DiagId::ErrUnknownOutputOptionSuggest, SourceLoc{},
                 {pattern, list});
  }
  if (!ok)
    return std::nullopt;
  std::vector<std::string> out;
  for (size_t i = 0; i < names.size(); ++i)
    if (picked[i])
      out.push_back(names[i]);
  out.insert(out.end(), extra.begin(), extra.end());
  return out;
}

Expected<std::vector<std::string>>
expandOutputPatterns(const std::vector<std::string> &patterns,
                     const std::vector<std::string> &available) {
  std::vector<std::string> chosen;
  auto choose = [&chosen](const std::string &name) {
    if (std::find(chosen.begin(), chosen.end(), name) == chosen.end())
      chosen.push_back(name);
  };
  for (const std::string &pattern : patterns) {
    if (!isGlob(pattern)) {
      choose(pattern);
      continue;
    }
    bool any = false;
    for (const std::string &name : available)
      if (globMatch(pattern, name)) {
        choose(name);
        any = true;
      }
    if (!any)
      return Error{"output pattern '" + pattern +
                   "' selects no variable of the compiled model"};
  }
  return chosen;
}

} // namespace ldae::driver
