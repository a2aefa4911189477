"""Images to numbers (spot tracking, ring calibration, stroboscope frames), and
synthetic frames with known truth to test them (:mod:`vision.artificial`).

A leaf package: it imports neither ``stand`` nor ``dsp``.
"""
