import os

import pytest

import splinegpu


@pytest.fixture(scope="session")
def gpu():
    """A GPU context (lavapipe in CI). Without an adapter the GPU tests skip, unless CI=true
    (as the crate's own GPU tests do)."""
    try:
        return splinegpu.Context("gpu")
    except RuntimeError as e:
        if os.environ.get("CI") == "true":
            raise
        pytest.skip(f"no GPU adapter: {e}")


@pytest.fixture(scope="session")
def cpu():
    return splinegpu.Context("cpu")
