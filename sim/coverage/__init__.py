"""Coverage of the verification campaign: functional bins (:mod:`.bins`) and code coverage of
the RTL (Verilator line, branch and toggle points mapped to the Amaranth source,
``dptbd verify --coverage``)."""
