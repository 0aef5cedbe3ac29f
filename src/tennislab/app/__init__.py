"""``tennislab app``: a local web application (FastAPI + vanilla JS, works offline).

Pages: serve explorer, launcher planner, line-call replay and a flight page.
:func:`tennislab.app.server.create_app` builds the application (its security
checks are there); :mod:`tennislab.app.fields` defines every form field and its
label (validated in the page and on the server); :mod:`tennislab.app.features`
names the jobs each page runs, and :mod:`tennislab.app.pool` runs them in worker
processes with deadlines and cancellation.  See ``docs/app.md`` and
``docs/security.md``.
"""
