"""One run's results as numpy arrays: ``r.time``, ``r["x"]``, the
parameters the run used, units, descriptions, the solver's counters, and
conversions (a result file, a pandas DataFrame, a matplotlib figure)."""
from .errors import SimulationError


class Result:
    """What ``Model.simulate`` returns.

    ``r.time`` and ``r[name]`` are 1-D float arrays (one value per output
    row); ``r.names`` the reported variables in model order; ``r.units``
    and ``r.descriptions`` map names to the model's text ("" when it gives
    none); ``r.params`` maps every parameter to the value of this run.
    ``r.status`` is 0, or 3 after a numerical failure (the rows up to it
    are kept; ``r.failure`` says why, ``r.diagnostics`` is the command's
    text). ``r.recompiled`` is True when the run needed a model compiled
    for its structural parameters or start values (docs/python.md).
    """

    def __init__(self, raw, recompiled=False, states=None):
        self._raw = raw
        self.data = raw.data
        cols = raw.columns
        self.columns = [c[0] for c in cols]
        self.kinds = {c[0]: c[1] for c in cols}
        self.units = {c[0]: c[2] for c in cols}
        self.descriptions = {c[0]: c[3] for c in cols}
        self._index = {name: j for j, name in enumerate(self.columns)}
        # What plot() draws by default: the states when no outputs were
        # asked for (every other variable follows from them), else all.
        self.plot_default = [n for n in states or [] if n in self._index]
        params = raw.params
        self.params = {p[0]: p[1] for p in params}
        self.param_units = {p[0]: p[2] for p in params}
        self.param_descriptions = {p[0]: p[3] for p in params}
        self.status = raw.status
        self.failure = raw.failure
        self.diagnostics = raw.diagnostics
        self.log = raw.log
        self.stats = raw.stats
        self.model = raw.model
        self.recompiled = recompiled

    @property
    def names(self):
        """The reported variables (every column but time)."""
        return self.columns[1:]

    @property
    def time(self):
        return self.data[:, 0]

    def __getitem__(self, name):
        try:
            return self.data[:, self._index[name]]
        except KeyError:
            raise KeyError(_unknown(name, self.columns)) from None

    def __contains__(self, name):
        return name in self._index

    def keys(self):
        return list(self.columns)

    def __len__(self):
        return self.data.shape[0]

    def __repr__(self):
        state = "ok" if self.status == 0 else f"status {self.status}"
        span = (f", t = {self.time[0]:g}..{self.time[-1]:g}"
                if len(self) else "")
        return (f"<ldaec.Result {self.model}: {len(self)} rows x "
                f"{len(self.names)} variables{span}, {state}>")

    def check(self):
        """Raises SimulationError (carrying this result) after a failure."""
        if self.status != 0:
            raise SimulationError(self.diagnostics, result=self)
        return self

    def write(self, path, format=None):
        """Writes the result file the command writes with ``-o path``: CSV,
        or OpenModelica's .mat layout (docs/results.md); the format by the
        extension unless ``format`` ("csv", "mat") says."""
        self._raw.write(str(path), format or "")

    def to_pandas(self):
        """A DataFrame indexed by time with one column per variable."""
        try:
            import pandas
        except ImportError:
            raise ImportError(
                "Result.to_pandas() needs pandas, which is not installed "
                "(pip install pandas, or apt install python3-pandas); "
                "r.time and r[name] are numpy arrays without it") from None
        frame = pandas.DataFrame(self.data[:, 1:], columns=self.names,
                                 index=pandas.Index(self.time, name="time"))
        frame.attrs["units"] = {n: self.units[n] for n in self.names}
        frame.attrs["params"] = dict(self.params)
        return frame

    def plot(self, names=None, path=None, max_curves=12):
        """A matplotlib figure, one panel per unit (docs/python.md, "Plots").
        ``path`` saves it (PNG, SVG, PDF by extension)."""
        from .plot import plot_result
        return plot_result(self, names, path, max_curves)


def _unknown(name, available):
    import difflib
    close = difflib.get_close_matches(name, available, n=5, cutoff=0.6)
    text = f"no variable '{name}' in the result"
    if close:
        text += "; did you mean " + ", ".join(f"'{c}'" for c in close) + "?"
    return text

