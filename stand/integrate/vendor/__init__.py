"""Third-party code kept verbatim (with its licence header): the DOP853 coefficients of SciPy."""
