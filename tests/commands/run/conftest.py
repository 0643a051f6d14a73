"""Fixtures of the ``dptbd run`` tests."""

import pytest

from helpers.run_command import SMALL


@pytest.fixture
def small(tmp_path):
    """A small scenario file (:data:`helpers.run_command.SMALL`) in ``tmp_path/inputs``."""
    path = tmp_path / "inputs" / "small.toml"
    path.parent.mkdir()
    path.write_text(SMALL)
    return path
