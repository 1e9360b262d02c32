// The `ldaec` command line: every option, parsed by CLI11 into one struct.
#pragma once

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
  std::string emit;                       // --emit flat|reduced|llvm|c
  bool emitMain = false;                  // --main (with --emit c)
  std::string outputFile;                 // -o
  std::optional<double> startTime, stopTime, rtol, atol, interval;
  passes::Method method = passes::Method::DummyDerivatives; // --method
  std::string causalize = "on";           // --causalize on|off
  std::string outputs;                    // --outputs x,y
  std::string plotFile;                   // --plot out.svg|png
  bool stats = false;                     // --stats
  bool everyStep = false;                 // --every-step
  std::vector<double> outputTimes;        // --output-times 0.4,4,40
  std::string algebraicErrorTest = "auto";// --algebraic-error-test on|off|auto
  std::string integrator = "auto";        // --integrator
  std::string jit = "auto";               // --jit on|off|auto
  bool timePasses = false;                // --time-passes
  bool compileOnly = false;               // --compile-only
  std::vector<std::string> printAfter;    // --print-after PASS
  bool noProgress = false;                // --no-progress
};

/// Declares every option on `app`, writing into `opts`.
void defineOptions(CLI::App &app, Options &opts);

} // namespace ldae::driver
