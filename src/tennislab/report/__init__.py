"""The coach-facing report (``tennislab report --out DIR``): one self-contained HTML file with its figures
embedded; :func:`build_report` builds it, one section per use case (:data:`SECTION_KEYS`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.report.build import SECTION_KEYS, build_report, index_path

__all__ = ["SECTION_KEYS", "build_report", "index_path"]
__getattr__, __dir__ = attach_stub(__name__, __file__)
