"""Images to numbers (spot tracking, ring calibration, stroboscope frames).

A leaf package: it imports neither ``stand`` nor ``dsp``.
"""
