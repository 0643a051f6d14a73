"""The formal harnesses: each wraps one component (or the ``dptbd_axi`` top) with the rules
of its environment (``Assume``), the properties it must keep (``Assert``) and cover
statements that show the properties are not vacuous (``Cover``). ``docs/gateware.md``
("Formal proofs") states each property and the build it is proven on.

Modules: ``tiny`` (the small build the proofs run on), ``streams`` (the AXI4-Stream output
adapters, ``m_axis_cand`` and ``m_axis_state``), ``flow`` (the flow control: credit, pipeline
and FIFO; the DP pipeline), ``registers`` (the AXI4-Lite port and the register block),
``top`` (the whole ``dptbd_axi``), ``axi_store`` (the AXI4 manager port of
``dptbd_dp --state-store axi``), ``write_behind`` and ``prefetcher`` (its write-behind and
its read prefetcher alone, with the invariants of their induction, which ``axi_store`` states
too), ``known_bad`` (broken components whose proofs must FAIL).
"""
