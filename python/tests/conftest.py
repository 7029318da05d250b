from pathlib import Path

import pytest

DATA = Path(__file__).resolve().parents[2] / "crates" / "sim" / "tests" / "data"


@pytest.fixture
def data():
    return DATA
