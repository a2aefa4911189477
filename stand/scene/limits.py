"""Size limits every scene form is held to (memory and run length), in one place.

A scene within these limits can never ask for a run that exhausts memory or takes
days; :mod:`stand.scene.parse`, the book and family scene forms and the instruments'
settings checks (:mod:`stand.scene.placement`) all read them from here.
"""
from __future__ import annotations

__all__ = ["MAX_SAMPLES", "MAX_WEIGHTS", "MAX_STATE_BYTES", "MAX_CYCLES", "MAX_IMAGE_PIXELS"]

MAX_SAMPLES = 5e7  #: largest duration * sample_rate accepted (memory)
MAX_WEIGHTS = 10_000  #: largest balancer.count accepted
MAX_STATE_BYTES = 4e9  #: largest sample buffer (samples x state width x 8 bytes) accepted
MAX_CYCLES = 1e8  #: largest number of rotor revolutions or natural periods in one run
MAX_IMAGE_PIXELS = 16e6  #: largest instrument image (width x height) accepted
