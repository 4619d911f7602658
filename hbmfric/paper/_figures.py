"""Figure files of the paper reproduction: off-screen matplotlib (imported
only when a figure is drawn) and one way of saving."""

from __future__ import annotations

from pathlib import Path


def pyplot():
    """``matplotlib.pyplot`` on the off-screen Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path, files: list[Path]) -> Path:
    """Lay out, write ``fig`` to ``path`` (PNG, 120 dpi), close it and record
    the path in ``files``."""
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    pyplot().close(fig)
    files.append(Path(path))
    return Path(path)
