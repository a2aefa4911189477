"""What the theory says of a scene (``stand.theory``): steady motions, stability, critical speeds.

* :mod:`.scene`  -- ``stand.theory(scene)`` for any scene, and why a part does not apply;
* :mod:`.planar` -- the planar rotor with n weights (chapter 5): speed bands, QP law;
* :mod:`.rotors` -- rotor-family scenes: natural frequencies, Campbell data, criterion (2.15);
  :mod:`.rotor_stability` -- Floquet stability of their main motions; :mod:`.spatial_criterion`
  -- the spatial rotor's closed forms (2.7.2-2.7.3);
* :mod:`.rotating` -- the rotating-frame form of the running kernels (steady states, Jacobians);
* :mod:`.weights` -- the book weight models: steady motions, stability, QP motions.

(Named ``theories`` so that the package does not shadow the API function ``stand.theory``.)
"""
