"""Fixtures shared by the package's tests."""

import pytest


@pytest.fixture(scope="module")
def pymeshlab():
    """pymeshlab, or the test skipped with a message when it is not importable."""
    try:
        import pymeshlab
    except ImportError as error:
        pytest.skip(f"pymeshlab is not importable ({error}); pip install pymeshlab")
    return pymeshlab
