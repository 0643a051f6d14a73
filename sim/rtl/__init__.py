"""The golden model's check of a compiled RTL run (:mod:`.rtl.check`) and the Monte Carlo
trials on the compiled RTL (:mod:`.rtl.trials`).
"""
