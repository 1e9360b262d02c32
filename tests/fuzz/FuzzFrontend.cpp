// The in-process fuzz target: bytes in as a model source, the frontend
// (parse, lookup, flatten, balance check) and the analysis pipeline (alias
// elimination through initialization) over it, the reports built but the
// diagnostics printed nowhere. Built for libFuzzer with -DLDAEC_LIBFUZZER=ON
// (scripts/fuzz-libfuzzer.sh) and, in every build, with FuzzReplay.cpp as a
// plain program that replays files (the findings, the seed corpus).
#include "frontend/Frontend.h"
#include "passes/Pipeline.h"
#include "support/Diagnostics.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

using namespace ldae;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  SourceManager sources;
  DiagnosticEngine diags(sources);
  // As the driver does: a mutant with thousands of errors must not spend
  // the fuzzer's time formatting them.
  diags.setErrorLimit(50);
  frontend::FrontendOptions opts;
  std::unique_ptr<ir::Model> model = frontend::compileSource(
      "fuzz.lsd", std::string(reinterpret_cast<const char *>(data), size),
      opts, sources, diags);
  if (model) {
    // `--emit flat`, the balance check and `--analyze --json`, in process.
    (void)model->print();
    frontend::checkBalance(*model, diags);
    passes::PipelineOptions passOpts;
    passes::AnalysisResult result;
    passes::runPipeline(*model, passOpts, diags, result);
    (void)passes::analysisToJson(result).dump();
    if (result.system)
      (void)passes::printReduced(*result.system);
  }
  // Drawing a diagnostic reads the source line under its location: a bad
  // location must not read out of bounds.
  for (const Diagnostic &d : diags.diagnostics())
    (void)diags.render(d);
  return 0;
}
