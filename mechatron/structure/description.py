"""Structural descriptions: links, kinematic pairs with their classes [Egorov, table 3.1], loops — from a plain data
file or from a :class:`~mechatron.model.Mechanism`'s model.

A description file (TOML)::

    name = "ICE crank-slider, fig. 3.10 a"
    planar = true                  # the planar formulas (Chebyshev) apply
    frame = "0"                    # the fixed link (default "0")
    links = ["1", "2", "3"]        # the moving links

    [[pairs]]
    name = "A"
    class = 5                      # 1…5: the number of constraints; or give only the kind
    kind = "R"                     # R В, P П, H Ви, HB Вш, C Ц, SP Сп, S С, L Л, T Т ([Egorov, table 3.1])
    links = ["0", "1"]             # optional when the figure is lost
    actuated = true                # a "degree of mobility" (a driven pair)

    [[loops]]
    pairs = ["A", "B", "C", "C'"]
    closed_by = "group"            # or "link" (A_j = 2 or 1 in [Egorov, 3.18])
    redundant_links = 0            # Z_j: links of the loop that do not affect the output (a cam roller)
    repeated = false               # a loop of repeated links, left out of H (the planetary train, [Egorov, fig. 3.17])
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.schema import FieldReader
from ..model.mechanism import Mechanism


@dataclass(frozen=True)
class PairKind:
    """A kind of kinematic pair of [Egorov, table 3.1]: class (constraints), mobilities, names and the Pinocchio
    joints that model it."""

    code: str
    russian: str
    cls: int
    name: str
    pinocchio: str

    @property
    def mobilities(self) -> int:
        """f = 6 − i, the relative mobilities the pair leaves."""
        return 6 - self.cls


PAIR_KINDS = {k.code: k for k in (
    PairKind("R", "В", 5, "revolute", "JointModelRX/RY/RZ, RevoluteUnaligned, RUBx"),
    PairKind("P", "П", 5, "prismatic", "JointModelPX/PY/PZ, PrismaticUnaligned"),
    PairKind("H", "Ви", 5, "screw", "JointModelHx/Hy/Hz, HelicalUnaligned"),
    PairKind("HB", "Вш", 5, "ball screw", "JointModelHelical (pitch = lead / 2π)"),
    PairKind("C", "Ц", 4, "cylindrical", "composite P + R on one axis"),
    PairKind("SP", "Сп", 4, "spherical with pin", "JointModelUniversal"),
    PairKind("S", "С", 3, "spherical", "JointModelSpherical, SphericalZYX"),
    PairKind("L", "Л", 2, "line contact (higher)", "a constraint (cam, gear teeth)"),
    PairKind("T", "Т", 1, "point contact (higher)", "a constraint (point on a surface)"),
)}
_BY_RUSSIAN = {k.russian: k for k in PAIR_KINDS.values()}


def pair_kind(text: str) -> PairKind:
    """A pair kind by its Latin or Russian code [Egorov, table 3.1]."""
    key = text.strip()
    kind = PAIR_KINDS.get(key.upper()) or _BY_RUSSIAN.get(key)
    if kind is None:
        raise InputError(f"unknown pair kind {text!r}; expected one of: "
                         + ", ".join(f"{k.code} ({k.russian}, {k.name})" for k in PAIR_KINDS.values()))
    return kind


@dataclass(frozen=True)
class Pair:
    name: str
    cls: int
    kind: str | None = None
    links: tuple[str, str] | None = None
    actuated: bool = False

    @property
    def lower(self) -> bool:
        """A lower pair (classes 5, 4, 3: surface contact)."""
        return self.cls >= 3


@dataclass(frozen=True)
class Loop:
    pairs: tuple[str, ...]
    closed_by: str | None = None  # "group", "link" or unknown
    redundant_links: int = 0
    repeated: bool = False


@dataclass
class StructuralDescription:
    """Links (the frame and the moving ones), pairs and loops of a mechanism."""

    name: str
    links: list[str]
    pairs: list[Pair]
    loops: list[Loop] = field(default_factory=list)
    frame: str = "0"
    planar: bool = False
    description: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        self.validate()

    @property
    def n(self) -> int:
        """The number of moving links."""
        return len(self.links)

    def counts(self, pairs: list[Pair] | None = None) -> dict[int, int]:
        """The number of pairs (of ``pairs``, default all) by class."""
        return dict(Counter(p.cls for p in (self.pairs if pairs is None else pairs)))

    def pair(self, name: str) -> Pair:
        """The pair named ``name``."""
        return next(p for p in self.pairs if p.name == name)

    def validate(self) -> None:
        """Names unique and known, classes 1…5, no pair joining a link to itself, every loop closed, and as many
        loops as [Egorov, 3.10] gives."""
        where = f"structure {self.name}"
        known = [self.frame, *self.links]
        for dup in [k for k, c in Counter(known).items() if c > 1]:
            raise InputError(f"{where}: link {dup!r} is listed twice")
        for dup in [k for k, c in Counter(p.name for p in self.pairs).items() if c > 1]:
            raise InputError(f"{where}: pair {dup!r} is listed twice")
        for p in self.pairs:
            if p.cls not in (1, 2, 3, 4, 5):
                raise InputError(f"{where}: pair {p.name}: class must be 1…5 (constraints), got {p.cls!r}")
            if p.links is not None:
                for link in p.links:
                    if link not in known:
                        raise InputError(f"{where}: pair {p.name} joins unknown link {link!r} (links: "
                                         f"{', '.join(known)})")
                if p.links[0] == p.links[1]:
                    raise InputError(f"{where}: pair {p.name} joins link {p.links[0]!r} to itself")
        names = {p.name for p in self.pairs}
        for j, loop in enumerate(self.loops, start=1):
            missing = [n for n in loop.pairs if n not in names]
            if missing:
                raise InputError(f"{where}: loop {j} names unknown pair(s) {', '.join(missing)}")
            if loop.closed_by not in (None, "group", "link"):
                raise InputError(f"{where}: loop {j}: closed_by must be 'group' or 'link', got {loop.closed_by!r}")
            if loop.redundant_links < 0:
                raise InputError(f"{where}: loop {j}: redundant_links must be >= 0")
            ends = [p.links for p in (self.pair(n) for n in loop.pairs)]
            if all(e is not None for e in ends):
                degree = Counter(link for e in ends for link in e)
                odd = [link for link, d in degree.items() if d % 2]
                if odd:
                    raise InputError(f"{where}: loop {j} is not closed: link(s) {', '.join(odd)} meet only one of "
                                     "its pairs")
        loops = len(self.pairs) - self.n
        if self.loops and len(self.loops) != loops:
            raise InputError(f"{where}: inconsistent counts: {len(self.pairs)} pairs and {self.n} moving links make "
                             f"K = {loops} independent loops [Egorov, 3.10], but {len(self.loops)} loops are listed")
        if loops < 0:
            raise InputError(f"{where}: inconsistent counts: {len(self.pairs)} pairs cannot join {self.n} moving links "
                             "to the frame (K = Σp − n < 0)")


# ------------------------------------------------------------------------------------------------ files
def read_structure(path: str | Path) -> StructuralDescription:
    """A structural description from a TOML file (format in the module docstring)."""
    from ..io.toml import read_toml

    path = Path(path)
    top = FieldReader(read_toml(path), file=path)
    name, description, source = top.header(path.stem)
    planar = top.boolean("planar", False)
    frame = top.string("frame", "0")
    links_raw = top.raw("links")
    if not isinstance(links_raw, list) or not all(isinstance(x, (str, int)) for x in links_raw):
        raise top.error("links", "give the moving links as a list of names")
    links = [str(x) for x in links_raw]
    pairs = []
    for reader in top.tables("pairs"):
        pname = reader.string("name")
        kind_text = reader.string("kind", "")
        kind = None
        if kind_text:
            try:
                kind = pair_kind(kind_text)
            except InputError as exc:
                raise reader.error("kind", exc.message) from None
        cls = reader.raw("class", None)
        if cls is None:
            if kind is None:
                raise reader.error("class", "give the pair's class (1…5) or its kind")
            cls = kind.cls
        if isinstance(cls, bool) or not isinstance(cls, int) or not 1 <= cls <= 5:
            raise reader.error("class", f"unknown pair class {cls!r}: a class is 1…5 (the number of constraints)")
        if kind is not None and kind.cls != cls:
            raise reader.error("class", f"a {kind.name} pair ({kind.code}) is class {kind.cls}, not {cls}")
        ends = reader.raw("links", None)
        if ends is not None and (not isinstance(ends, list) or len(ends) != 2):
            raise reader.error("links", "give the two links the pair joins")
        actuated = reader.boolean("actuated", False)
        reader.finish()
        pairs.append(Pair(pname, cls, kind.code if kind else None,
                          tuple(str(e) for e in ends) if ends is not None else None, actuated))
    loops = []
    for reader in top.tables("loops") if top.has("loops") else []:
        members = reader.raw("pairs")
        if not isinstance(members, list) or not members:
            raise reader.error("pairs", "give the loop's pairs as a list of names")
        closed_by = reader.string("closed_by", "") or None
        redundant = reader.whole("redundant_links", 0, minimum=0)
        repeated = reader.boolean("repeated", False)
        reader.finish()
        loops.append(Loop(tuple(str(m) for m in members), closed_by, redundant, repeated))
    top.finish()
    try:
        return StructuralDescription(name, links, pairs, loops, frame, planar, description, source or str(path))
    except InputError as exc:
        raise InputError(exc.message, file=path) from None


# ------------------------------------------------------------------------------------------------ mechanisms
def _joint_pair(mech: Mechanism, joint: int) -> tuple[int, str | None]:
    kind = mech.joint_kind(joint)
    if kind == "revolute":
        return 5, "R"
    if kind == "prismatic":
        return 5, "P"
    short = mech.model.joints[joint].shortname()
    if "Helical" in short:
        return 5, "H"
    if "Spherical" in short:
        return 3, "S"
    if "Universal" in short:
        return 4, "SP"
    nv = mech.model.joints[joint].nv
    if not 1 <= nv <= 5:
        raise InputError(f"{mech.name}: joint {mech.model.names[joint]} ({short}) is not a kinematic pair of table "
                         "3.1 (it leaves 0 or 6 mobilities)")
    return 6 - nv, None


def _closure_pair(closure) -> tuple[int, str]:
    from ..model.closures import Gear, OnCurve, Pin, Slider

    if isinstance(closure, Pin):
        return (5, "R") if closure.planar else (3, "S")
    if isinstance(closure, Slider):
        return (5, "P") if closure.lock_angle else (2, "L")  # a pin in a slot: line contact in the plane
    if isinstance(closure, (OnCurve, Gear)):
        return 2, "L"
    raise InputError(f"closure {closure.describe()} has no pair class")  # pragma: no cover


def link_names(mech: Mechanism) -> list[str]:
    """The moving links: one per joint, named by the body frame on it (else the joint)."""
    model = mech.model
    names = []
    for j in range(1, model.njoints):
        body = next((f.name for f in model.frames if f.parentJoint == j and f.type.name == "BODY"), None)
        names.append(body or model.names[j])
    return names


def from_mechanism(mech: Mechanism) -> StructuralDescription:
    """The structural description of a model: a moving link per joint, a pair per joint (class from its joint
    type) and per closure (a planar pin: revolute, class 5; a pin in 3D: spherical; a slider with locked angle:
    prismatic; a pin in a slot, a point on a curve, a gear mesh: line contact, class 2), one loop per closure
    (the closure's pair and the tree joints between its two bodies)."""
    model = mech.model
    links = link_names(mech)
    link_of = {0: "0", **{j: links[j - 1] for j in range(1, model.njoints)}}
    actuated = set(mech.actuated)
    pairs = []
    for j in range(1, model.njoints):
        cls, kind = _joint_pair(mech, j)
        pairs.append(Pair(model.names[j], cls, kind, (link_of[model.parents[j]], link_of[j]),
                          model.names[j] in actuated))
    loops = []
    planar = bool(mech.closures) and all(getattr(c, "planar", True) for c in mech.closures)
    for k, closure in enumerate(mech.closures):
        cls, kind = _closure_pair(closure)
        joints = _closure_joints(mech, closure)
        name = f"closure{k + 1}:{closure.describe()}"
        pairs.append(Pair(name, cls, kind, (link_of[joints[0]], link_of[joints[1]])))
        path = set(model.supports[joints[0]]) ^ set(model.supports[joints[1]])
        loops.append(Loop(tuple([model.names[j] for j in sorted(path)] + [name])))
    if not mech.closures:
        planar = _planar_chain(mech)
    return StructuralDescription(mech.name, links, pairs, loops, "0", planar, mech.description,
                                 f"model of {mech.name}")


def _closure_joints(mech: Mechanism, closure) -> tuple[int, int]:
    from ..model.closures import Gear

    frames = (closure.a, closure.b) if isinstance(closure, Gear) else tuple(closure.frames)
    joints = [mech.model.frames[mech.frame_id(f)].parentJoint for f in frames]
    return (joints[0], joints[1]) if len(joints) == 2 else (0, joints[0])


def _planar_chain(mech: Mechanism) -> bool:
    """A serial chain is planar when every revolute axis is along world z and every prismatic axis in the xy
    plane, at its neutral configuration."""
    import pinocchio as pin

    model, data = mech.model, mech.model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    for j in range(1, model.njoints):
        kind = mech.joint_kind(j)
        short = model.joints[j].shortname()
        if kind not in ("revolute", "prismatic"):
            return False
        axis = {"X": [1, 0, 0], "Y": [0, 1, 0], "Z": [0, 0, 1]}.get(short[-1]) if "Unaligned" not in short else \
            model.joints[j].extract().axis
        world = data.oMi[j].rotation @ np.asarray(axis, dtype=float)
        if kind == "revolute" and abs(abs(world[2]) - 1) > 1e-9:
            return False
        if kind == "prismatic" and abs(world[2]) > 1e-9:
            return False
    return True


def structure_file(name: str) -> Path | None:
    """A structural description file: ``name`` itself if it is a TOML file with [[pairs]], or one of the cases of
    [Egorov, chapter 3] shipped in ``robots/structures/`` by its stem (``ice_3_10a``)."""
    from ..io.data import data_dir
    from ..io.toml import read_toml

    path = Path(name)
    if path.suffix == ".toml" and path.is_file():
        return path if "pairs" in read_toml(path) else None
    shipped = data_dir("robots") / "structures" / f"{name}.toml"
    return shipped if shipped.is_file() else None


def shipped_structures() -> list[str]:
    """The structural cases of [Egorov, chapter 3] shipped in ``robots/structures/``."""
    from ..io.data import data_dir

    return sorted(p.stem for p in (data_dir("robots") / "structures").glob("*.toml"))
