"""Paths shared by the module's tests: the repository's models and this
folder's own. ctest sets PYTHONPATH to the build's python/ folder,
LDAEC_BINARY to the ldaec command and LDAEC_CACHE_DIR to a scratch cache."""
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RC = os.path.join(ROOT, "tests", "models", "rc_circuit.lsd")
PENDULUM = os.path.join(ROOT, "examples", "pendulum.lsd")


def model(name):
    return os.path.join(HERE, "models", name)


@pytest.fixture
def rc():
    import ldaec
    return ldaec.compile(RC, cache=False)
