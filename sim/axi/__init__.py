"""The AXI top level ``dptbd_axi``'s runs: :mod:`~dptbd.sim.axi.stimulus` (video beats with
frame-sync faults, the frame monitor's fault rule, the model's expected outputs),
:mod:`~dptbd.sim.axi.runs` (the campaign's random runs drawn from a seed, built, run and
checked), :mod:`~dptbd.sim.axi.actions` (their register traffic) and
:mod:`~dptbd.sim.axi.scoring` (a run's candidate words against the model's lists,
across soft resets and ``aresetn``)."""
