"""Weight LUTs for the configuration's tests."""

from dptbd.weights import plain_weights


def lut_with(value, radius=1):
    """Plain DP's LUT of ``radius`` with its entry ``[0, 0]`` set to ``value``."""
    w = plain_weights(radius)
    w[0, 0] = value
    return w
