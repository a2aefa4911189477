"""Integration: the compiled DOP853 driver and scipy's methods for every model (:mod:`.driver`)."""
