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
