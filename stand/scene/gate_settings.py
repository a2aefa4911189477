"""Settings of the photo-gate (``[instruments.photogate]``, monograph 4.3, FPM-09): plain data
read with the scene; its passes and the natural-frequency test are
:mod:`stand.instruments.photogate`."""
from __future__ import annotations

import math
from dataclasses import dataclass

from stand.scene.model import SceneError
from stand.scene.instrument_settings import (check, choice, integer, keys, number, read_table, rebased)

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0
PATH = "instruments.photogate"
AXES = ("x", "y", "radial")
TRIGGERS = ("enter", "centre")


@dataclass(frozen=True)
class PhotoGate:
    """Settings of the photo-element and pulse counter.

    Parameters
    ----------
    size : float
        Width of the detector on the screen along ``axis`` [m].
    position : float
        Centre of the detector on the screen axis [m]; 0 = the undeflected spot.
    axis : {"x", "y", "radial"}
        Screen coordinate the detector is across: X, Y, or the signed
        coordinate along the line through the rest position at angle
        ``direction`` ("radial": the line of the initial deflection).
    direction : float
        Angle of the "radial" line from the X axis [rad]; TOML: degrees.
    trigger : {"enter", "centre"}
        Counter input: the spot entering the detector (real, leading edge) or
        crossing its centre (ideal).
    start_pass, stop_pass : int
        Passes that start and stop the counter (FPM-09 method: 1 and 3).
    """

    size: float = number(0.5e-3, "m", gt=0)
    position: float = number(0.0, "m")
    axis: str = choice("x", AXES)
    direction: float = number(0.0, "rad", toml=("deg", DEG))
    trigger: str = choice("enter", TRIGGERS)
    start_pass: int = integer(1, 1)
    stop_pass: int = integer(3, 2)

    def __post_init__(self):
        check(self, PATH)
        if self.stop_pass <= self.start_pass:
            raise SceneError(f"{PATH}.stop_pass = {self.stop_pass}: must be > start_pass = "
                             f"{self.start_pass}")

    @property
    def unit_vector(self) -> tuple[float, float]:
        """Direction of the screen axis in the X, Y plane."""
        if self.axis == "x":
            return 1.0, 0.0
        if self.axis == "y":
            return 0.0, 1.0
        return math.cos(self.direction), math.sin(self.direction)

    @classmethod
    def from_table(cls, t) -> "PhotoGate":
        """Build from a validated ``[instruments.photogate]`` table.

        Keys (all optional): ``size``, ``position`` [m], ``axis``
        ("x"/"y"/"radial"), ``direction`` [deg], ``trigger``
        ("enter"/"centre"), ``start_pass``, ``stop_pass``.
        """
        t.allow(PHOTOGATE_KEYS)
        return rebased(cls, read_table(t, cls), PATH, t.path)


#: keys of ``[instruments.photogate]`` (the fields of :class:`PhotoGate`)
PHOTOGATE_KEYS = keys(PhotoGate)
