"""Built-in closed-loop mechanisms, loadable by name with :func:`mechatron.load`.

Each entry builds a :class:`~mechatron.model.Mechanism` from keyword parameters (SI units); ``load(name, l1=0.12)``
passes overrides through. Each module documents where its geometry comes from.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..model.mechanism import Mechanism
from . import bucket, excavator, grab, seven_bar, textbook


@dataclass(frozen=True)
class Builtin:
    build: Callable[..., Mechanism]
    description: str


BUILTINS: dict[str, Builtin] = {
    "crank_slider": Builtin(textbook.crank_slider, textbook.crank_slider.__doc__.splitlines()[0]),
    "scotch_yoke": Builtin(textbook.scotch_yoke, textbook.scotch_yoke.__doc__.splitlines()[0]),
    "slotted_link": Builtin(textbook.slotted_link, textbook.slotted_link.__doc__.splitlines()[0]),
    "front_shovel": Builtin(excavator.front_shovel, excavator.front_shovel.__doc__.splitlines()[0]),
    "grab": Builtin(grab.grab, grab.grab.__doc__.splitlines()[0]),
    "six_bar_bucket": Builtin(bucket.six_bar_bucket, bucket.six_bar_bucket.__doc__.splitlines()[0]),
    "seven_bar": Builtin(seven_bar.seven_bar, seven_bar.seven_bar.__doc__.splitlines()[0]),
}
