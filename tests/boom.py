"""A small mechanism file for tests: a boom turning about O on the ground, lifted by a hydraulic cylinder from the
ground pin B0 to the boom's pin E, 0.5 m long in the drawing (stroke 0.4 … 0.7 m), its tip T further out."""

from __future__ import annotations


def boom(*, top: str = "", points: str = "T = [1.0, 0.2]", carried: str = '"O", "E", "T"', body: str = "mass = 20.0",
         tail: str = "") -> str:
    """The boom's file: ``top`` lines after ``actuated`` (e.g. input rates), the drawn ``points`` after O, B0 and E,
    the boom's ``carried`` points and its ``body`` fields (mass, centre, inertia), and a ``tail`` (e.g. lengths)."""
    return f"""name = "boom"
actuated = ["lift"]
{top}[points]
O = [0.0, 0.0]
B0 = [0.2, -0.3]
E = [0.5, 0.1]
{points}
[[bodies]]
name = "ground"
points = ["O", "B0"]
[[bodies]]
name = "boom"
points = [{carried}]
{body}
[[joints]]
type = "revolute"
body = "boom"
at = "O"
[[joints]]
type = "cylinder"
name = "lift"
base = "B0"
eye = "E"
stroke = [0.4, 0.7]
{tail}"""
