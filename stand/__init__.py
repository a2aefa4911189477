"""The virtual autobalancer test stand: scenes, physics, instruments, recordings."""
__version__ = "0.1.0"
