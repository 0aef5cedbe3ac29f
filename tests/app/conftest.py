"""One running app (with its worker processes) shared by the API and security tests."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def client():
    pytest.importorskip("fastapi")
    pytest.importorskip("httpx")
    from fastapi.testclient import TestClient

    from tennislab.app.server import create_app

    with TestClient(create_app(allowed_hosts=["testserver"])) as c:
        yield c
