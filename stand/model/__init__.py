"""The physics: structures, correction weights and bodies, drives; fixed frame, SI.

* :mod:`.planar`, :mod:`.structure`, :mod:`.weights` -- the planar rotor with n balls or
  pendulums (chapter 5), its structural part and the weights coupled to the shaft point K;
* :mod:`.rotating`  -- the rotating-frame form derived from it (steady states, Jacobians);
* :mod:`.programme` -- prescribed rotor kinematics (speed programmes, coast-down);
* :mod:`.kernels`   -- the compiled right-hand sides, selected by model kind;
* :mod:`.rotors`    -- the rotor family: one generic linear structure and its builders;
* :mod:`.balancers` -- the book weight models (two-axis pendulum, coupled pair, damper, liquid);
* :mod:`.registry`  -- named kinds and where their code lives (the one place that looks upward).
"""
