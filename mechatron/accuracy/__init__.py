"""Kinematic accuracy [Egorov, chapter 8]: sensitivities of a point's position to geometric parameters and joint
coordinates [Egorov, 8.3–8.5], the error of a given set of errors [Egorov, 8.4–8.6], worst-case, statistical and Monte
Carlo tolerance studies (:func:`~mechatron.accuracy.study.analyse_tolerances`, returning a
:class:`~mechatron.accuracy.result.ToleranceResult`)."""
