// Checks of the ldaec command line that make the driver exit 2 before any
// work: first those that need nothing but the options (and the file
// system; the --outputs names are checked against the flat model by
// selectOutputs, OutputSelection.h). Every
// problem is reported through the diagnostics table (DiagnosticsDriver.def).
#pragma once

#include "Options.h"

#include "ir/Model.h"
#include "support/Diagnostics.h"

namespace CLI {
class App;
}

namespace ldae::driver {

/// Checks the options alone: the input file is a readable regular file,
/// the modes go together and every option does something in the chosen
/// mode, numbers are finite and in range, --param is name=number, output
/// directories exist, --print-after names a pass. Reports into `diags`;
/// false when anything is wrong.
bool checkCommandLine(const CLI::App &app, const Options &opts,
                      DiagnosticEngine &diags);

/// Whether the positional argument names a class on the library path
/// (`Modelica.Mechanics.Rotational.Examples.First`): a dotted name that is
/// no existing file and does not end in .lsd or .mo.
bool isClassName(const std::string &input);

/// Whether `diags` holds an error caused by the command line rather than
/// by the model (--model naming no class, --param naming no parameter):
/// the frontend finds those, the driver exits 2 for them.
bool hasCommandLineError(const DiagnosticEngine &diags);

/// The names of the comma-separated --outputs list, empty ones dropped.
std::vector<std::string> splitOutputs(const std::string &list);

} // namespace ldae::driver
