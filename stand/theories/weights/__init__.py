"""What the theory says of the books' weight models (chapters 6-7, paper 001, thesis 002):
steady motions and their stability (``*_steady``), the two-axis pendulum's critical speeds
and quasi-periodic motions (:mod:`.two_axis_theory`), the coupled pair's quasi-periodic
family (:mod:`.gravity_pair_qp`), the liquid chamber's quasi-static model
(:mod:`.liquid_chamber_quasi_static`), all evaluated on the one model's rotating frame
(:mod:`.one_model`, :mod:`stand.theories.rotating`); :mod:`.weight_theory` gathers them for
one model kind.  The models themselves are in :mod:`stand.model.balancers`.
"""
