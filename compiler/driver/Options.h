// The `ldaec` command line: every option, parsed by CLI11 into one struct.
#pragma once

#include "RunRequest.h"

#include "ldae/Simulation.h"
#include "passes/Method.h"

#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace ldae::driver {

struct Options {
  std::string input;                      // model.lsd
  std::string modelName;                  // --model
  std::vector<std::string> libraries;     // --lib DIR (repeatable)
  std::vector<std::string> paramOverrides;// --param name=value
  std::vector<std::string> overrides;     // --override a=1,x.start=2
  std::string format;                     // --format csv|mat ("": by -o)
  bool noCache = false;                   // --no-cache
  std::vector<std::string> sweep;         // --sweep R=1:10:100 (repeatable)
  int jobs = 0;                           // --jobs N (0: the cores)
  bool analyze = false;                   // --analyze
  bool json = false;                      // --json
  bool simulate = false;                  // --simulate
  EmitKind emit = EmitKind::None;         // --emit flat|reduced|llvm|c
  bool emitMain = false;                  // --main (with --emit c)
  std::string outputFile;                 // -o
  /// --start, --stop, --rtol, --atol, --interval, --every-step,
  /// --output-times, --algebraic-error-test, --integrator.
  RunRequest run;
  passes::Method method = passes::Method::DummyDerivatives; // --method
  bool causalize = true;                  // --causalize on|off
  std::string outputs;                    // --outputs x,y
  std::string plotFile;                   // --plot out.svg|png
  bool stats = false;                     // --stats
  SwitchChoice jit = SwitchChoice::Auto;  // --jit on|off|auto
  bool timePasses = false;                // --time-passes
  bool compileOnly = false;               // --compile-only
  std::vector<std::string> printAfter;    // --print-after PASS
  bool noProgress = false;                // --no-progress
};

/// Declares every option on `app`, writing into `opts`.
void defineOptions(CLI::App &app, Options &opts);

} // namespace ldae::driver
