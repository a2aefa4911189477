"""The rotor family (issue 7): one generic linear structure, builders for every
rotor type of the seeds, and the coupling of correction weights to any of them."""
from .structure import LinearRotor, Unbalance, sign_changes, working_ranges

__all__ = ["LinearRotor", "Unbalance", "sign_changes", "working_ranges"]
