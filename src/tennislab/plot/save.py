"""Saving figures atomically."""

from __future__ import annotations

import os

from tennislab.io.files import atomic_write


def save_figure(fig, path: str) -> None:
    """Save a Matplotlib figure to ``path`` (format from its extension, PNG by default), atomically."""

    def _w(fh):
        fig.savefig(fh, dpi=130, bbox_inches="tight", format=os.path.splitext(path)[1][1:] or "png")

    atomic_write(path, _w, mode="wb")
