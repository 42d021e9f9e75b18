"""Finding and loading mechanisms: robot files (DH arms) and mechanism files (closed-loop linkages) by name — in
``./robots``, the folders of ``MECHATRON_PATH``, then the shipped ``robots/`` — or by path, URDF files, and the arms
of the installed ``example-robot-data`` package (found on disk, never downloaded). :func:`load` and
:func:`available_robots` are ``mechatron.load`` and ``mechatron.available_robots``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from .errors import InputError
from .io.data import data_dir

if TYPE_CHECKING:  # pragma: no cover
    from .model.mechanism import Mechanism

# Imported where used, so that loading a robot file by name costs only what it needs: ``importlib.metadata`` (the
# example-robot-data lookup, done only for a name no robot or mechanism file has), the URDF reader, the robot-file
# reader and the mechanism-file reader (see benchmarks/startup.py).


@dataclass(frozen=True)
class ExampleRobot:
    """An arm of ``example-robot-data``: its URDF path in the package, the frame used as tool, joints to lock, and
    whether its link masses include the drives (mechatron's reading of the files: the masses of whole links, motors
    and gears inside; :attr:`~mechatron.model.Mechanism.link_masses_include_drives`)."""

    urdf: str
    tool: str | None = None
    locked: tuple[str, ...] = ()
    description: str = ""
    masses_include_drives: bool = True


EXAMPLE_ROBOTS: dict[str, ExampleRobot] = {
    "ur3": ExampleRobot("ur_description/urdf/ur3_robot.urdf", "tool0", description="Universal Robots UR3 (URDF)"),
    "ur5": ExampleRobot("ur_description/urdf/ur5_robot.urdf", "tool0", description="Universal Robots UR5 (URDF)"),
    "ur10": ExampleRobot("ur_description/urdf/ur10_robot.urdf", "tool0", description="Universal Robots UR10 (URDF)"),
    "panda": ExampleRobot("panda_description/urdf/panda.urdf", "panda_hand_tcp",
                          ("panda_finger_joint1", "panda_finger_joint2"),
                          "Franka Emika Panda, fingers locked (URDF)"),
    "z1": ExampleRobot("z1_description/urdf/z1.urdf", "gripperStator", ("jointGripper",),
                       "Unitree Z1 arm, gripper locked (URDF)"),
    "xarm7": ExampleRobot("xarm_description/urdf/xarm7.urdf", "link_eef", description="UFactory xArm 7 (URDF)"),
    "so101": ExampleRobot("so_arm_description/urdf/so101.urdf", "gripper_frame_link", ("gripper",),
                          "SO-101 arm, gripper locked (URDF)"),
    "double_pendulum": ExampleRobot("double_pendulum_description/urdf/double_pendulum.urdf",
                                    description="double pendulum (URDF)", masses_include_drives=False),
}


@lru_cache(maxsize=1)
def example_robot_data_dir() -> Path | None:
    """The ``robots`` folder of the installed ``example-robot-data`` package, or ``None``."""
    import importlib.metadata

    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        return None
    folder = Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))
    return folder if folder.is_dir() else None


def search_path() -> list[tuple[Path, str]]:
    """The folders searched for ``NAME.toml``, first found first: ``./robots`` of the working directory, then every
    folder of the ``MECHATRON_PATH`` environment variable (separated by ``os.pathsep``), then the shipped ones; each
    with a word saying where it is (``./robots``, ``MECHATRON_PATH``, ``shipped``). The shipped folder is listed once,
    as ``shipped``, even when it is also ``./robots`` (working in a source checkout) or in ``MECHATRON_PATH``."""
    shipped = data_dir("robots")
    folders = [(Path.cwd() / "robots", "./robots")]
    folders += [(Path(part).expanduser(), "MECHATRON_PATH")
                for part in os.environ.get("MECHATRON_PATH", "").split(os.pathsep) if part]
    return [(f, origin) for f, origin in folders if f.resolve() != shipped.resolve()] + [(shipped, "shipped")]


def robot_files() -> dict[str, tuple[Path, str]]:
    """Every robot and mechanism file found by name: name (file stem) → (path, where it was found); the first
    folder of :func:`search_path` that has a name wins."""
    out: dict[str, tuple[Path, str]] = {}
    for folder, origin in search_path():
        if folder.is_dir():
            for path in sorted(folder.glob("*.toml")):
                out.setdefault(path.stem, (path, origin))
    return out


def builtin_robot_files() -> dict[str, Path]:
    """Robot and mechanism files found by name (see :func:`robot_files`)."""
    return {name: path for name, (path, _) in robot_files().items()}


def installed_example_robots() -> dict[str, Path]:
    """The arms of :data:`EXAMPLE_ROBOTS` whose URDF is installed, by name."""
    folder = example_robot_data_dir()
    if folder is None:
        return {}
    return {name: folder / robot.urdf for name, robot in EXAMPLE_ROBOTS.items() if (folder / robot.urdf).is_file()}


#: Where a name comes from (:func:`robot_origins`), in the order :func:`load` looks.
ORIGINS = ("./robots", "MECHATRON_PATH", "shipped", "example-robot-data")


def robot_origins() -> dict[str, tuple[str, Path | None]]:
    """Every name :func:`load` accepts → (where it comes from, the file it loads): the files of
    :func:`search_path` (``./robots``, ``MECHATRON_PATH``, ``shipped``), then the arms of ``example-robot-data``
    that no file replaces. A name is listed once, with what :func:`load` uses."""
    out: dict[str, tuple[str, Path | None]] = {name: (origin, path) for name, (path, origin) in robot_files().items()}
    for name, path in installed_example_robots().items():
        out.setdefault(name, ("example-robot-data", path))
    return out


def available_robots() -> list[str]:
    """Names :func:`load` accepts: robot and mechanism files (./robots, MECHATRON_PATH, shipped) and the installed
    example-robot-data arms; each once (see :func:`robot_origins`)."""
    return list(robot_origins())


def load_file(path: str | Path) -> Mechanism:
    """A mechanism from a file, told apart by its content: a robot file (a DH table, ``[[links]]``), a mechanism
    file (a closed-loop linkage, ``[points]`` and ``[[bodies]]``) or a URDF (``.urdf``)."""
    from .io.toml import read_toml

    path = Path(path)
    if path.suffix.lower() == ".urdf":
        from .model.urdf import load_urdf

        return load_urdf(path)
    if path.suffix.lower() != ".toml":
        raise InputError("unknown kind of file: expected a robot or mechanism file (.toml) or a URDF (.urdf)",
                         file=path)
    data = read_toml(path)
    if "bodies" in data:  # every mechanism file has [[bodies]]: its reader is imported only for a file that may be one
        from .model.linkage_file import is_linkage_file, linkage_spec
        from .model.spatial import build_mechanism

        if is_linkage_file(data):
            return build_mechanism(linkage_spec(data, file=path, default_name=path.stem))
    links = data.get("links")
    structural = "pairs" in data or (isinstance(links, list) and bool(links)
                                     and all(isinstance(x, (str, int)) for x in links))
    if structural and "pairs" in data:
        raise InputError("a structural description (moving links, pairs and loops), not a mechanism: use "
                         "'mechatron structure' with it; see docs/structure_file.md", file=path)
    if structural:  # a list of names: neither a robot file's tables nor, without its pairs, a structural description
        raise InputError("a list of names, not a robot file's links (one [[links]] table per link with its joint and "
                         "DH parameters, docs/robot_file.md); a structural description lists its links so but needs "
                         "its [[pairs]] too (docs/structure_file.md)", file=path, field="links")
    if "links" in data:
        from .model.robotfile import read_robot_file

        return read_robot_file(path).mechanism()
    raise InputError("neither a robot file (a DH table: [[links]]) nor a mechanism file (a closed-loop linkage: "
                     "[points] and [[bodies]]); see docs/robot_file.md and docs/mechanism_file.md", file=path)


def load(name_or_path: str | Path, **parameters: float) -> Mechanism:
    """Load a mechanism by name or path, with some geometric parameters overridden.

    Args:
        name_or_path: A name from :func:`available_robots` (``NAME.toml`` in ``./robots``, a ``MECHATRON_PATH``
            folder or the shipped ``robots/`` — a DH arm such as ``puma560`` or a linkage such as ``front_shovel``
            — or an example-robot-data arm such as ``ur5``), or the path of a robot or mechanism file (``.toml``,
            told apart by content) or a URDF (``.urdf``).
        **parameters: New values (SI: metres, radians) of named geometric parameters, e.g. ``a2=0.5`` of a DH arm,
            a named length ``l1=0.12`` or a point's coordinate ``B_x=0.05`` of a linkage.

    Returns:
        The :class:`Mechanism`. Its ``model`` is the ``pinocchio.Model`` and ``data`` its ``Data``.

    Raises:
        InputError: for an unknown name, an unreadable or invalid file, or an unknown parameter.
    """
    text = str(name_or_path)
    path = Path(text)
    looks_like_path = isinstance(name_or_path, Path) or path.suffix.lower() in (".toml", ".urdf") or "/" in text
    if looks_like_path:
        mechanism = load_file(path)
    elif text in (builtin := builtin_robot_files()):
        mechanism = load_file(builtin[text])
    elif text in (examples := installed_example_robots()):  # looked up only for a name no file has
        from .model.urdf import load_urdf

        robot = EXAMPLE_ROBOTS[text]
        mechanism = load_urdf(examples[text], text, tool=robot.tool, locked_joints=robot.locked,
                              description=robot.description, link_masses_include_drives=robot.masses_include_drives)
    else:
        from .model.mechanism import unknown_name_error

        raise unknown_name_error("robot", text, available_robots())
    return mechanism.with_parameters(parameters) if parameters else mechanism
