"""Amaranth 0.5 gateware of the streaming DP pipeline."""
