"""Formal proofs of ``dptbd_axi``'s interfaces and invariants (``dptbd verify --formal``).

- :mod:`~dptbd.sim.formal.properties`: the interface rule sets (AXI4-Stream manager /
  subordinate, AXI4-Lite subordinate with outstanding counters, open packets);
- :mod:`~dptbd.sim.formal.harness`: the harness base (clock, reset, free inputs) and
  :class:`~dptbd.sim.formal.harness.Elaborated` (inner signals for induction invariants);
- :mod:`~dptbd.sim.formal.harnesses`: one harness per component, the top, the known-bad
  ones (a module per concept: streams, flow, registers, top, known_bad);
- :mod:`~dptbd.sim.formal.tasks`: what is proven, in which mode, to which depth;
- :mod:`~dptbd.sim.formal.runner`: RTLIL, SBY files, ``yowasp-sby`` with Boolector, the verdicts.

``docs/gateware.md`` ("Formal proofs") states the properties; ``docs/simulation.md`` has
today's depths and times.
"""
