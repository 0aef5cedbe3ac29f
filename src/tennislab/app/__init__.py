"""``tennislab app``: a local web application (FastAPI + vanilla JS, works offline).

Pages: serve explorer, launcher planner, line-call replay and a flight page.
:func:`tennislab.app.server.create_app` builds the application (FastAPI is
imported only there); :mod:`tennislab.app.fields` defines every form field
(validated in the page and on the server) and :mod:`tennislab.app.services` /
:mod:`tennislab.app.features` call the physics.  See ``docs/app.md``.
"""
