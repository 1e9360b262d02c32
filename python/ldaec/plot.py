"""Readable plots of a result: one panel per unit (curves of different
units never share an axis), axis labels with units, a legend per panel,
the model's name as title, and at most ``max_curves`` curves unless the
names are given. Saving to a file needs no display (matplotlib's Agg
canvas); without a path the figure is made with pyplot, on Agg when there
is no display."""
import os
import sys
import warnings


def _groups(result, names):
    """[(unit, [names])] in the order the units first appear."""
    groups = {}
    for name in names:
        groups.setdefault(result.units.get(name, ""), []).append(name)
    return list(groups.items())


def _default_names(result, max_curves):
    names = result.plot_default or [
        n for n in result.names if result.kinds.get(n) != "parameter"]
    if len(names) > max_curves:
        warnings.warn(
            f"plotting the first {max_curves} of {len(names)} variables; "
            "pass names=[...] (or outputs= when simulating) for others",
            stacklevel=3)
        names = names[:max_curves]
    return names


def _figure(path, panels):
    size = (7.0, 1.0 + 2.2 * panels)
    if path is not None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        fig = Figure(figsize=size)
        FigureCanvasAgg(fig)
        return fig
    import matplotlib
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        if "matplotlib.pyplot" not in sys.modules:
            matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt.figure(figsize=size)


def plot_result(result, names=None, path=None, max_curves=12):
    if names is None:
        names = _default_names(result, max_curves)
    elif isinstance(names, str):
        names = [names]
    for name in names:
        result[name]  # a KeyError naming close names for a typo
    groups = _groups(result, names)
    fig = _figure(path, max(1, len(groups)))
    axes = fig.subplots(max(1, len(groups)), 1, sharex=True, squeeze=False)
    for ax, (unit, members) in zip(axes[:, 0], groups):
        for name in members:
            ax.plot(result.time, result[name], label=name)
        ax.set_ylabel(f"[{unit}]" if unit else "(no unit)")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
    axes[-1, 0].set_xlabel("time [s]")
    title = result.model
    if result.status != 0:
        title += f" (failed at t = {result.time[-1]:g})" if len(result) else \
            " (failed)"
    fig.suptitle(title)
    fig.tight_layout()
    if path is not None:
        fig.savefig(os.fspath(path))
    return fig
