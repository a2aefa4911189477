"""Theory of the planar rotor with n weights: steady motions, stability,
critical speeds, quasi-periodic (stuck-ball) motions, speed maps.

Modules (one idea each):

* :mod:`.main_motion`  -- main (balancing) motions: characteristic polynomial
  (5.90), conservative form (5.98), critical speeds, closed forms (5.103)-(5.127);
* :mod:`.steady`       -- side motions (5.51)-(5.75) and the e0 > 1 main motion;
  :mod:`.steady_stability` their stability from the rotating-frame Jacobian;
* :mod:`.qp`           -- quasi-periodic motions: frequency equation (5.181),
  stability (5.210)-(5.216), escape speed, laser-spot law (5.237);
* :mod:`.speedmap`     -- a scene's speed bands and chart; ``stand theory``.

All functions work in the book's dimensionless units (digest ch5 section 2.2):
speed ratio R = omega/omega_1, R~_m (``Rt``), h, H, e0, d.
"""
