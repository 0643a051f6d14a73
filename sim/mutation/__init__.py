"""Mutation testing of the top levels (MCY style): Yosys ``mutate`` samples mutations of a
top's netlist (:mod:`.netlist`), one Verilator build carries them all behind the port
``mutsel`` (and, for ``dptbd_axi``, presets of its counters, :mod:`.presets`), each mutant
runs the verification slice (:mod:`~dptbd.sim.mutation.run`), and a survivor may be
proven equivalent to the original (:mod:`.equivalence`; from reset, :mod:`.reachable`;
under a proven invariant, :mod:`.invariant`); the survivors shown equivalent,
proven or argued, are the registry (:mod:`.equivalents`) that MCY's score, killed / (total
- shown equivalent), leaves out. ``dptbd verify --mutants N`` is the command
(``docs/gateware.md``, "Mutation testing")."""
