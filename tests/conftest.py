import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(autouse=True, scope="session")
def _clean_working_folder(tmp_path_factory):
    """Every test runs from an empty folder: a developer's ``./tennislab.toml`` cannot change the
    results (the CLI reads it from the working folder), and no test writes into the checkout."""
    old = os.getcwd()
    os.chdir(tmp_path_factory.mktemp("cwd"))
    yield
    os.chdir(old)


@pytest.fixture(scope="session")
def client():
    """One running web app (with its worker processes) shared by every test that talks to it."""
    pytest.importorskip("fastapi")
    pytest.importorskip("httpx")
    from fastapi.testclient import TestClient

    from tennislab.app.server import create_app

    with TestClient(create_app(allowed_hosts=["testserver"])) as c:
        yield c
