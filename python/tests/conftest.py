"""Fixtures the Python tests share."""

import pytest

from relight_support import TRANSPORT, cli


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    """The fixture transport compressed (adaptive-quad, f16 coefficients)."""
    path = str(tmp_path_factory.mktemp("model") / "plant.h5")
    cli("compress", TRANSPORT, "--method", "adaptive-quad", "--coeffs", "f16", "--out", path)
    return path
