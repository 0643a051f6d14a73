"""Numpy models: scenes, the float reference and the bit-accurate golden model of the DP."""
