"""ldaec from Python: compile a model once, run it many times with other
parameters and start values, read results as numpy arrays, sweep on Dask.

    import ldaec
    m = ldaec.compile("rc.lsd")
    r = m.simulate(stop=1, params={"R": 50})
    r.time, r["capacitor.v"]

docs/python.md is the guide; errors are ModelError, UsageError and
SimulationError carrying the command's diagnostics.
"""
from .errors import (LdaecError, ModelError, ModelWarning, SimulationError,
                     UsageError)
from .model import Model, analyze, compile
from .result import Result
from .sweep import SweepResult, sweep
from .sweep import compile_count as sweep_compile_count

__all__ = ["compile", "analyze", "Model", "Result", "sweep", "SweepResult",
           "LdaecError", "ModelError", "UsageError", "SimulationError",
           "ModelWarning", "sweep_compile_count"]
