// The ldaec command: the whole pipeline, top to bottom, in one place.
//   parse/flatten -> passes -> codegen -> runtime
// Exit codes: 0 success, 1 the model is wrong, 2 bad command line,
// 3 numerical failure during simulation.
#include "Options.h"

#include <CLI/CLI.hpp>

#include <iostream>

using namespace ldae;

int main(int argc, char **argv) {
  driver::Options opts;
  CLI::App app;
  app.set_version_flag("--version", std::string("ldaec ") + LDAEC_VERSION);
  driver::defineOptions(app, opts);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError &e) {
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  std::cerr << "ldaec: error: the pipeline is not built yet\n";
  return 1;
}
