"""Kinematic accuracy (textbook chapter 8): sensitivities of a point's position to geometric parameters and joint
coordinates, the error of a given set of errors, worst-case, statistical and Monte Carlo tolerance studies."""
