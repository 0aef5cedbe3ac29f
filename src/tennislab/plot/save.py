"""Saving figures: to a file atomically, or as PNG bytes / a data URI for the self-contained report."""

from __future__ import annotations

import base64
import io
import os

from tennislab.io.files import atomic_write, check_output_path

#: File extensions ``--plot`` accepts: Matplotlib's formats that need no external program
#: (``.pgf`` needs LaTeX) and no optional Pillow codec; raw pixel dumps left out.  A plain tuple, not
#: asked of Matplotlib's backends at import (0.2 s of every command's start-up); a test checks that
#: Matplotlib supports each.
FIGURE_SUFFIXES: tuple[str, ...] = tuple(
    f".{ext}" for ext in ("png", "pdf", "svg", "svgz", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp")
)

DPI = 130  #: resolution of raster figures [dots per inch]


def check_figure_path(param: str, path) -> str:
    """Validate a figure's output path before the work (:func:`tennislab.io.files.check_output_path`
    with :data:`FIGURE_SUFFIXES`); returns it."""
    return check_output_path(param, path, FIGURE_SUFFIXES)


def save_figure(fig, path: str) -> None:
    """Save a Matplotlib figure to ``path`` (format from its extension, one of :data:`FIGURE_SUFFIXES`),
    atomically and with the user's default permissions."""
    check_figure_path("plot", path)
    fmt = os.path.splitext(path)[1][1:].lower()

    def _w(fh):
        fig.savefig(fh, dpi=DPI, bbox_inches="tight", format=fmt)

    atomic_write(path, _w, mode="wb")


def figure_png(fig, dpi: int = DPI) -> bytes:
    """The figure as PNG bytes."""
    buf = io.BytesIO()
    fig.savefig(buf, dpi=dpi, bbox_inches="tight", format="png")
    return buf.getvalue()


def figure_data_uri(fig, dpi: int = DPI) -> str:
    """The figure as a ``data:image/png;base64,...`` URI (embedded in an HTML page: no file beside it)."""
    return "data:image/png;base64," + base64.b64encode(figure_png(fig, dpi)).decode("ascii")


def close_figure(fig) -> None:
    """Release a figure drawn with pyplot (once it is saved: a long session or a report drawing dozens
    keeps no memory of them)."""
    import matplotlib.pyplot as plt

    plt.close(fig)
