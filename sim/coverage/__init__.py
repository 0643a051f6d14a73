"""Code coverage of the RTL (Verilator line and toggle points mapped to the Amaranth source, ``dptbd verify --coverage``)."""
