"""``tennislab app``: a local web application (FastAPI + vanilla JS, works offline).

Pages: serve explorer, launcher planner, line-call replay and a flight page.
:func:`tennislab.app.server.create_app` builds the application (its security
checks are there); :mod:`tennislab.app.fields` defines every form field and its
label (validated in the page and on the server); :mod:`tennislab.app.features`
names the jobs each page runs, and :mod:`tennislab.app.pool` runs them in worker
processes with deadlines and cancellation.  See ``docs/app.md`` and
``docs/security.md``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.app.server import create_app

__all__ = ["create_app"]
__getattr__, __dir__ = attach_stub(__name__, __file__)
