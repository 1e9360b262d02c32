"""A model compiled once and run many times (docs/python.md).

A parameter that does not fix the model's structure, and the start value
of an unknown of the compiled model, change at run time: the compiled
code evaluates again what reads them (ldae_model::bind), with no new
analysis or code generation. A structural parameter (an array size, a
branch chosen, a subscript) or the start value of a variable the compiled
model computes from others needs a model compiled for that value: it is
compiled with overrides (``--override`` of the command), kept per set of
overrides, and the result says ``recompiled``.
"""
import collections
import json
import os
import threading
import warnings

from . import _ldaec
from .errors import ModelError, ModelWarning, SimulationError, UsageError
from .result import Result

# Models compiled for structural values kept per Model, the least recently
# used dropped first (a sweep over an array size would otherwise keep one
# compiled model per member).
MAX_RECOMPILED = 16


def format_value(value):
    """A number as an override's text: integers exact, reals round-trip."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return value
    return repr(float(value))


def _name_list(names):
    """A comma-separated string or a list of names as a list."""
    if not names:
        return []
    if isinstance(names, str):
        return [n.strip() for n in names.split(",") if n.strip()]
    return list(names)


def override_list(overrides):
    """``{"R": 10, "x.start": 1}``, ``["R=10", ...]`` or ``"R=10,x.start=1"``
    as the command's ``name=value`` strings."""
    if not overrides:
        return []
    if isinstance(overrides, str):
        return _name_list(overrides)
    if isinstance(overrides, dict):
        return [f"{k}={format_value(v)}" for k, v in overrides.items()]
    return [str(o) for o in overrides]


def _jit_spelling(jit):
    if jit is None or jit == "auto":
        return "auto"
    if jit is True or jit == "on":
        return "on"
    if jit is False or jit == "off":
        return "off"
    raise UsageError(f"error: jit must be 'on', 'off' or 'auto', not {jit!r}\n")


def _cache_dir(cache):
    if cache is True:
        return _ldaec.default_cache_dir()
    if not cache:
        return ""
    return os.fspath(cache)


class Model:
    """What ``ldaec.compile`` returns; see the module's doc string."""

    def __init__(self, path, model=None, method="dd", outputs=None,
                 jit="auto", overrides=None, cache=True):
        self.path = os.fspath(path)
        self.model_name = model or ""
        self.method = method
        self.outputs = _name_list(outputs)
        self.jit = _jit_spelling(jit)
        self.overrides = override_list(overrides)
        self.cache_dir = _cache_dir(cache)
        self.compile_count = 0
        self._lock = threading.Lock()
        self._compiled = collections.OrderedDict()
        self._report = None
        self._base = self._model_for(())[0]

    # ---- compiled models -------------------------------------------------

    def _model_for(self, extra):
        """The compiled model for the base overrides plus `extra` (a sorted
        tuple of name=value), compiled on first use; (model, is new)."""
        key = tuple(extra)
        with self._lock:
            if key in self._compiled:
                self._compiled.move_to_end(key)
                return self._compiled[key], False
            compiled = _ldaec.Model(self.path, self.model_name, self.method,
                                    self.outputs, self.jit,
                                    self.overrides + list(key),
                                    self.cache_dir)
            self.compile_count += 1
            self._compiled[key] = compiled
            if len(self._compiled) > MAX_RECOMPILED + 1:
                # The base model (key ()) stays: it answers `parameters`.
                oldest = next(k for k in self._compiled if k)
                del self._compiled[oldest]
        if compiled.warnings:
            warnings.warn(compiled.warnings.rstrip("\n"), ModelWarning,
                          stacklevel=3)
        return compiled, True

    @property
    def name(self):
        return self._base.name

    @property
    def parameters(self):
        """Every parameter of the compiled model and its default value."""
        return self._base.parameters

    @property
    def structural(self):
        """The parameters that fix the structure: a new value recompiles."""
        return list(self._base.structural)

    @property
    def unknowns(self):
        """The compiled model's unknowns (their start values change at
        run time) and their start values."""
        return self._base.starts

    @property
    def output_names(self):
        """What a run can report, in model order."""
        return list(self._base.output_names)

    @property
    def compile_seconds(self):
        """Code generation time of the first compile (the object cache's
        hits make it small)."""
        return self._base.compile_seconds

    @property
    def backend(self):
        return self._base.backend

    def __repr__(self):
        return (f"<ldaec.Model {self.name} from {self.path}: "
                f"{len(self._base.starts)} unknowns, "
                f"{len(self.parameters)} parameters>")

    # ---- analysis ---------------------------------------------------------

    def analyze(self):
        """The ``ldaec --analyze --json`` report as a dict. A model the
        analysis rejects raises ModelError with the report in ``e.report``."""
        if self._report is None:
            self._report = analyze(self.path, self.model_name, self.method,
                                   self.overrides)
        return json.loads(json.dumps(self._report))  # the caller's copy

    # ---- runs -------------------------------------------------------------

    def _split(self, params, starts, base):
        """(run-time params, run-time starts, overrides needing a compile)."""
        structural = set(base.structural)
        known = base.parameters
        unknowns = base.starts
        runtime_params, runtime_starts, extra = {}, {}, []
        for name, value in params.items():
            # A parameter folded away at compile time (an array size) is
            # no entry of the parameter vector: an override too (and a
            # name the model lacks gets the frontend's error with close
            # names).
            if name in structural or name not in known:
                extra.append(f"{name}={format_value(value)}")
            else:
                runtime_params[name] = float(value)
        for name, value in starts.items():
            if name in unknowns:
                runtime_starts[name] = float(value)
            else:
                extra.append(f"{name}.start={format_value(value)}")
        return runtime_params, runtime_starts, sorted(extra)

    def simulate(self, stop=None, *, start=None, t0=None, start_time=None,
                 start_values=None, rtol=None, atol=None, interval=None,
                 params=None, outputs=None, integrator="auto",
                 every_step=False, times=None, algebraic_error_test=None,
                 check=False):
        """Runs the model; see docs/python.md for every argument.

        ``start`` (or ``start_values``) is a dict of start values by name
        (``{"x": 1}`` for ``x.start``), as the issue and Modelica's
        ``--override x.start=1`` spell it; the start time is ``t0`` (or
        ``start_time``). Returns a Result; a numerical failure returns the
        rows up to it with ``status`` 3, or raises SimulationError when
        ``check`` is true."""
        if start is not None and not isinstance(start, dict):
            raise UsageError(
                "error: start= takes start values ({name: value}); the "
                "start time is t0=\n")
        if start is not None and start_values is not None:
            raise UsageError("error: give start values once: start= or "
                             "start_values=\n")
        if t0 is not None and start_time is not None:
            raise UsageError("error: give the start time once: t0= or "
                             "start_time=\n")
        starts = dict(start if start is not None else start_values or {})
        params = dict(params or {})
        t0 = t0 if t0 is not None else start_time
        run = dict(start=t0, stop=stop, rtol=rtol, atol=atol,
                   interval=interval, every_step=every_step,
                   times=list(times or []), integrator=integrator,
                   algebraic_error_test=algebraic_error_test)

        rt_params, rt_starts, extra = self._split(params, starts, self._base)
        compiled = self._base if not extra else self._model_for(extra)[0]
        try:
            raw = compiled.simulate(
                outputs=compiled.expand_outputs(_name_list(outputs)),
                params=rt_params, starts=rt_starts, **run)
        except UsageError as e:
            if e.kind != "needs-recompile" or not (params or starts):
                raise
            # The base model's tables did not say (the model compiled for
            # the overrides has another structure): everything given
            # becomes an override.
            extra = sorted([f"{n}={format_value(v)}" for n, v in params.items()]
                           + [f"{n}.start={format_value(v)}"
                              for n, v in starts.items()])
            compiled = self._model_for(extra)[0]
            raw = compiled.simulate(
                outputs=compiled.expand_outputs(_name_list(outputs)), **run)
        states = None if (self.outputs or outputs) else compiled.unknowns
        result = Result(raw, recompiled=compiled is not self._base,
                        states=states)
        if check and result.status != 0:
            raise SimulationError(result.diagnostics, result=result)
        return result


def compile(path, model=None, method="dd", outputs=None, jit="auto",
            overrides=None, cache=True):
    """Parses, analyzes and compiles ``path`` (a .lsd file) once.

    ``model`` names the model (default: the last non-partial one);
    ``method`` is ``--method`` (dd, sga, ode, raw); ``outputs`` names and
    patterns to report (fewer outputs prune the model); ``jit`` "on",
    "off" or "auto" (``--jit``); ``overrides`` values fixed at compile time
    (``{"n": 4, "x.start": 1}``); ``cache`` the JIT's object cache (True:
    the user's cache directory, False: none, or a directory). Raises
    ModelError (the command's exit 1) or UsageError (exit 2) with the
    command's diagnostics."""
    return Model(path, model=model, method=method, outputs=outputs, jit=jit,
                 overrides=overrides, cache=cache)


def analyze(path, model=None, method="dd", overrides=None):
    """The ``ldaec --analyze --json`` report of a model that need not
    compile (a singular one says what it can). Raises ModelError when the
    analysis fails, with the report in ``e.report``."""
    text, ok, diagnostics = _ldaec.analyze(os.fspath(path), model or "",
                                           method, override_list(overrides))
    report = json.loads(text)
    if not ok:
        error = ModelError(diagnostics)
        error.report = report
        raise error
    return report
