"""The cocotb benches that :func:`dptbd.sim.icarus.simulate` runs on Icarus (4-state), one
module per design (:mod:`.benches.dp`, :mod:`.benches.segmenter`, :mod:`.benches.axi`,
:mod:`.benches.dp_axi`, :mod:`.benches.axi_store`), with their shared drivers
(:mod:`.benches.drivers`; the cocotbext-axi ones of the ``dptbd_axi`` benches:
:mod:`.benches.bus_drivers`) and the soft-reset checks (:mod:`.benches.soft_reset_check`).
"""
