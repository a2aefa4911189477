"""What the theory says of a scene (``stand.theory``): steady motions, stability, critical speeds.

* :mod:`.scene`  -- ``stand.theory(scene)`` for any scene, and why a part does not apply;
* :mod:`.planar` -- the planar rotor with n weights (chapter 5): speed bands, QP law;
* :mod:`.rotors` -- rotor-family scenes: natural frequencies, Campbell data, criterion (2.15).

(Named ``theories`` so that the package does not shadow the API function ``stand.theory``.)
"""
