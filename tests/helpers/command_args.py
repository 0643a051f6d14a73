"""Parsing a command's arguments as ``dptbd`` does, for the command tests."""

import argparse


def parse(module, argv):
    """``module``'s arguments (its ``add_arguments``) parsed from ``argv`` (items as text)."""
    parser = argparse.ArgumentParser()
    module.add_arguments(parser)
    return parser.parse_args([str(a) for a in argv])


def parser_of(module):
    """``parse(argv)`` for ``module``: :func:`parse` with the module given."""
    return lambda argv: parse(module, argv)
