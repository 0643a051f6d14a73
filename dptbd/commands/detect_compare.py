"""The former name of :mod:`dptbd.commands.detectors` (the module is named after its command).

Kept only while ``tests/evaluation/detectors/test_interface.py`` imports it; remove it once
that test imports :mod:`dptbd.commands.detectors`.
"""

from dptbd.commands.detectors import add_arguments, main  # noqa: F401
