"""The exceptions of the ldaec module: one per exit code of the command
(docs/exit-codes.md), each carrying the diagnostics text the command
prints (``file:line:col: error: ...`` with the source line and caret)."""


class LdaecError(Exception):
    """Base class; ``str(e)`` and ``e.diagnostics`` are the command's text.
    ``e.kind`` says what went wrong for code to decide by, never the text:
    "model-error", "bad-option", "needs-recompile" (a run value only a
    model compiled for it takes; a UsageError) or "numerical-failure"."""

    exit_code = 1
    kind = "model-error"

    @property
    def diagnostics(self):
        return self.args[0] if self.args else ""


class ModelError(LdaecError):
    """The model is wrong (the command exits 1)."""

    exit_code = 1


class UsageError(LdaecError):
    """A bad option: an unknown name, a bad value (the command exits 2)."""

    exit_code = 2
    kind = "bad-option"


class SimulationError(LdaecError):
    """A numerical failure (the command exits 3). Raised by
    ``simulate(check=True)``; ``e.result`` holds the rows up to the failure."""

    exit_code = 3
    kind = "numerical-failure"

    def __init__(self, text, result=None):
        super().__init__(text)
        self.result = result


class ModelWarning(UserWarning):
    """A warning of the compiler (the balance of equations and unknowns)."""
