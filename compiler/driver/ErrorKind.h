// The kinds of failure the driver's stages report to a front end, each
// with the exit code the command gives for it (docs/exit-codes.md). The
// Python module hands the kind across its seam (the `kind` of the
// exceptions of ldaec/errors.py), so that the package decides by the kind
// (whether a run needs a model compiled for its values), never by the
// text of a message.
#pragma once

#include "RunRequest.h"

#include "ldae/model.h"

namespace ldae::driver {

enum class ErrorKind {
  ModelError,       ///< the model is wrong (exit 1)
  BadOption,        ///< an option or a value the run cannot take (exit 2)
  NeedsRecompile,   ///< a run value only a recompiled model takes (exit 2)
  NumericalFailure, ///< the integration failed (exit 3)
};

/// The command's exit code for `kind`.
int exitCode(ErrorKind kind);

/// The kind of a stage's exit code (Compilation::exitCode(); 0, a stage
/// that failed without one, is a model error).
ErrorKind errorKindOfExitCode(int code);

/// The kind's name as the Python package spells it ("needs-recompile").
const char *errorKindName(ErrorKind kind);

/// Whether the first of `run`'s parameter and start values that the
/// compiled model `m` refuses at run time (the runtime's bindValues checks
/// them in this order) is one a model compiled for it takes: a parameter
/// that fixes the structure (not a constant), or the start value of a
/// variable the model computes from others.
bool needsRecompile(const ldae_model &m, const RunRequest &run);

} // namespace ldae::driver
