import os

import numpy as np
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


@pytest.fixture(scope="session")
def far_apart_weights():
    """SciPy's gh-1375 data: (x, y, w) with weights 1e12 at the ends against 1e2 to 1e3."""
    x = np.array([-1.0, -0.65016502, -0.58856235, -0.26903553, -0.17370892, -0.10011001, 0.0,
                  0.10011001, 0.17370892, 0.26903553, 0.58856235, 0.65016502, 1.0])
    y = np.array([1.0, 0.62928599, 0.5797223, 0.39965815, 0.36322694, 0.3508061, 0.35214793,
                  0.3508061, 0.36322694, 0.39965815, 0.5797223, 0.62928599, 1.0])
    w = np.array([1e12, 688.875973, 489.314737, 426.864807, 607.74677, 451.341444,
                  317.48021, 451.341444, 607.74677, 426.864807, 489.314737, 688.875973, 1e12])
    return x, y, w
