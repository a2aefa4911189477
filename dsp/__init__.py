"""Identification from signals (natural frequency, damping, unbalance, components).

A leaf package: plain arrays in, results out.  It imports neither ``stand`` nor
``vision`` so that it works on real recordings with no simulator.
"""
