"""The rotor family (issue 7): one generic linear structure, builders for every
rotor type of the seeds, and the coupling of correction weights to any of them.

* :mod:`.structure` -- :class:`LinearRotor` (M, G, D, K, plane maps), the
  engineering criterion (2.15), its working ranges, Campbell data;
* builders: :mod:`.planar_supports` (2.5.1), :mod:`.two_mass` (2.5.2),
  :mod:`.grinding` (2.5.3), :mod:`.fixed_point` (2.6.1, 2.6.2, the stand of
  section 4.4), :mod:`.spatial` (2.7.1-2.7.3, Table 2.4, paper 003),
  :mod:`.flexible` (2.8), :mod:`.platform` (paper 004);
* :mod:`.cw_inertia` -- Tables 2.1/2.2 (mass-inertia of correction weights);
* :mod:`.coupled` -- weights in any planes of any rotor, compiled time integration;
* :mod:`.scene`, :mod:`.run` -- scene files and ``stand run`` / ``stand theory``.
"""
from stand.model.rotors.structure import LinearRotor, Unbalance, sign_changes, working_ranges

__all__ = ["LinearRotor", "Unbalance", "sign_changes", "working_ranges"]
