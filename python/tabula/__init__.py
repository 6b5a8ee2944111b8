"""tabula from Python: robots (FK, IK, Jacobians), stable poses, point-cloud files and
tabletop perception, PDDL planning, and the simulator's jobs — numpy arrays in and out.

Every function checks its arrays (shape, dtype converted to float64, finite values) and
raises ``ValueError`` with the same message the ``tabula`` command line gives; long work
runs with the GIL released.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional, Sequence, Tuple, Union

import numpy as np

from . import _tabula

__version__ = _tabula.__version__
__all__ = [
    "Robot",
    "Scene",
    "stable_poses",
    "read_pcd",
    "read_ply",
    "read_cloud",
    "perceive",
    "plan_pddl",
    "plan_motion",
]

PathLike = Union[str, Path]


def _array(a, name: str, shape: Tuple[Optional[int], ...], dtype=np.float64) -> np.ndarray:
    """``a`` as a C-contiguous array of ``dtype`` whose shape matches ``shape`` (None: any)."""
    try:
        arr = np.ascontiguousarray(a, dtype=dtype)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name} must be an array of numbers: {e}") from None
    if arr.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, arr.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise ValueError(f"{name} must have shape {want}, not {arr.shape}")
    return arr


def _vector(q, name: str) -> np.ndarray:
    """``q`` as a contiguous float64 vector (checked for finiteness natively)."""
    if type(q) is np.ndarray and q.dtype == np.float64 and q.ndim == 1 and q.flags.c_contiguous:
        return q
    return _array(q, name, (None,))


def _matrix(t, name: str = "T") -> np.ndarray:
    """``t`` as a contiguous float64 (4, 4) array (checked for finiteness natively)."""
    if type(t) is np.ndarray and t.dtype == np.float64 and t.shape == (4, 4) and t.flags.c_contiguous:
        return t
    return _array(t, name, (4, 4))


def _pose(t, name: str = "T") -> list:
    arr = _array(t, name, (4, 4))
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    return arr.tolist()


class Robot:
    """A robot: a built-in name (``"pr2"``, ``"wam"``, ``"golem3"``), a URDF or a xacro
    file (``$(find pkg)`` resolved through ``package_paths`` and ``ROS_PACKAGE_PATH``),
    with its SRDF (``srdf``, else the ``.srdf`` beside the file).

    Chains default to the description's first arm; ``base``/``tip`` pick any other."""

    def __init__(
        self,
        path_or_name: PathLike,
        srdf: Optional[PathLike] = None,
        xacro_args: Optional[dict] = None,
        package_paths: Optional[Sequence[PathLike]] = None,
    ):
        args = [(str(k), str(v)) for k, v in (xacro_args or {}).items()]
        paths = [str(p) for p in (package_paths or [])]
        self._robot = _tabula.Robot(
            str(path_or_name), None if srdf is None else str(srdf), args, paths
        )

    @property
    def name(self) -> str:
        """The robot's name as loaded."""
        return self._robot.name

    def arms(self) -> list:
        """``(name, base_link, tip_link)`` of every arm the description names."""
        return self._robot.arms()

    def joint_names(self, base: Optional[str] = None, tip: Optional[str] = None) -> list:
        """The chain's moving joints, in the order joint vectors list them."""
        return self._robot.joint_names(base, tip)

    def limits(self, base: Optional[str] = None, tip: Optional[str] = None) -> np.ndarray:
        """``(n, 2)`` lower and upper limits of the chain's joints (±inf if unlimited)."""
        return self._robot.limits(base, tip)

    def fk(self, q, base: Optional[str] = None, tip: Optional[str] = None) -> np.ndarray:
        """``base_from_tip`` at joint values ``q``: a (4, 4) homogeneous matrix."""
        return self._robot.fk(_vector(q, "q"), base, tip)

    def jacobian(self, q, base: Optional[str] = None, tip: Optional[str] = None) -> np.ndarray:
        """The geometric Jacobian at ``q``: (6, n), linear rows first, base frame."""
        return self._robot.jacobian(_vector(q, "q"), base, tip)

    def ik(
        self,
        T,
        base: Optional[str] = None,
        tip: Optional[str] = None,
        seed=None,
        position_only: bool = False,
    ) -> list:
        """Every joint solution found for ``base_from_tip = T`` (4, 4), nearest to
        ``seed`` (default: mid-range) first; an empty list when there is none."""
        seed = None if seed is None else _vector(seed, "seed")
        return self._robot.ik(_matrix(T), base, tip, seed, bool(position_only))

    def __repr__(self) -> str:
        return f"tabula.Robot({self.name!r}, arms={[a[0] for a in self.arms()]})"


def stable_poses(vertices, faces) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """How a rigid mesh rests on a table: ``(transforms (k, 4, 4), probabilities (k,),
    margins (k,))``, most likely first. As trimesh's ``compute_stable_poses``, each
    transform rests the mesh on z = 0 on that face, its centre of mass over the origin;
    a margin is the distance (m) from the centre of mass's projection to the nearest
    edge of the contact polygon."""
    v = _array(vertices, "vertices", (None, 3))
    f = _array(faces, "faces", (None, 3), dtype=np.int64)
    return _tabula.stable_poses(v, f)


def read_cloud(path: PathLike) -> Tuple[np.ndarray, Optional[np.ndarray], np.ndarray]:
    """A PCD or PLY file (by its first bytes): ``(points, colors, viewpoint)``. Points are
    ``(h, w, 3)`` for an organized cloud, else ``(n, 3)``, NaN where there is no point;
    colours the same shape in uint8, or None; ``viewpoint`` the file's sensor pose (4, 4)."""
    points, colors, viewpoint = _tabula.read_cloud(str(path))
    return points, colors, np.asarray(viewpoint)


def read_pcd(path: PathLike) -> np.ndarray:
    """A PCD file's points: ``(h, w, 3)`` organized or ``(n, 3)``."""
    return read_cloud(path)[0]


def read_ply(path: PathLike) -> np.ndarray:
    """A PLY file's vertices: ``(h, w, 3)`` organized or ``(n, 3)``."""
    return read_cloud(path)[0]


def _params(params) -> Optional[Tuple[str, str]]:
    """``params`` for the native half: a dict (keys as in the module's TOML, nested
    tables as dicts) or the path of a TOML file; None keeps every default."""
    if params is None:
        return None
    if isinstance(params, dict):
        try:
            return ("json", json.dumps(params, allow_nan=False))
        except (TypeError, ValueError) as e:
            raise ValueError(f"params: {e}") from None
    if isinstance(params, (str, Path)):
        return ("file", str(params))
    raise ValueError(f"params must be a dict or a TOML file's path, not {type(params).__name__}")


def perceive(points, up=None, world_from_camera=None, params=None) -> dict:
    """One frame's perception: the table, the objects on it, every horizontal surface,
    the free space — ``tabula perceive --json``'s content — plus ``labels``, one per
    point (-1 none, 0 the table, k + 1 object k, -2 objects cut by the frame's edge),
    and ``segments``, one per point in PCL's convention as ``tabula perceive --labels``
    writes it (uint32: 0 not an object, k the object or cut object whose ``label`` is k).

    ``points``: ``(h, w, 3)`` (organized, the sensor's grid) or ``(n, 3)``, NaN for no
    point. The frame is set by ``world_from_camera`` (4, 4), else by ``up`` (the world's
    up in the cloud's frame), else found from the largest support. ``params``: the
    tabletop pipeline's parameters (``tabula perceive --print-params``'s keys) as a dict
    or a TOML file; left-out keys keep their defaults."""
    arr = np.ascontiguousarray(points, dtype=np.float64)
    if not (arr.ndim == 3 and arr.shape[2] == 3) and not (arr.ndim == 2 and arr.shape[1] == 3):
        raise ValueError(f"points must have shape (h, w, 3) or (n, 3), not {arr.shape}")
    pose = None if world_from_camera is None else _pose(world_from_camera, "world_from_camera")
    up = None if up is None else _vector(up, "up").tolist()
    if up is not None and len(up) != 3:
        raise ValueError("up must have 3 values")
    text, labels, segments = _tabula.perceive(arr, pose, up, _params(params))
    out = json.loads(text)
    out["labels"] = labels
    out["segments"] = segments
    return out


def plan_pddl(
    domain: str, problem: str, optimal: bool = True, timeout_s: Optional[float] = None
) -> Optional[list]:
    """A plan for a PDDL domain and problem (texts): the actions as ``"(name arg…)"``
    strings, a cheapest plan when ``optimal`` (A*), else any plan fast; ``None`` when
    no plan exists. ``TimeoutError`` past ``timeout_s``."""
    return _tabula.plan_pddl(domain, problem, bool(optimal), timeout_s)


def _target(value, name: str):
    """A start or goal for the native half: a named state (str), a (4, 4) pose or joint
    values (a vector)."""
    if value is None or isinstance(value, str):
        return value
    arr = np.asarray(value, dtype=np.float64) if not isinstance(value, np.ndarray) else value
    if arr.ndim == 2:
        return _pose(arr, name)
    vec = _vector(arr, name)
    if not np.all(np.isfinite(vec)):
        raise ValueError(f"{name} must be finite")
    return vec.tolist()


def plan_motion(
    robot,
    scene: Optional[PathLike] = None,
    start=None,
    goal=None,
    group: Optional[str] = None,
    request: Optional[PathLike] = None,
    params=None,
    timeout: Optional[float] = None,
    seed: Optional[int] = None,
) -> dict:
    """A collision-free motion for ``robot``'s planning ``group`` in ``scene`` —
    ``tabula motion plan --json``'s content.

    ``robot``: a :class:`Robot`, a URDF/xacro file or a built-in name (with a tabula
    scene: which of its robots, None for its first). ``scene``: a tabula scene (``.toml``)
    or a MoveIt planning scene (``.yaml``), None for the robot alone. ``start``: joint
    values of the group, a named state, or None (the scene's state, or the request's).
    ``goal``: joint values, a (4, 4) pose of the group's tip in the world, or a named
    state; or instead ``request``, a MoveIt motion plan request (``.yaml``). ``params``:
    ``MoveGroupParams`` as a dict or TOML file (default: 1 mm padding, every edge
    certified). ``timeout`` (s): the planning limit (default: the request's, else 1 s).

    The answer: ``solved``; when True ``group``, ``joint_names``, ``path`` (waypoints),
    ``points`` (``time``, ``positions``, ``velocities``), ``planning_us``,
    ``path_length``, ``duration``, ``notes``; when False ``reason`` (``unreachable``,
    ``goal_in_collision``, ``goal_invalid``, ``start_invalid``, ``no_path``, …) and
    ``message``. A wrong query (file, group, joint count) raises ``ValueError``."""
    if isinstance(robot, Robot):
        robot = robot._robot
    elif robot is not None:
        robot = str(robot)
    if seed is not None and (not isinstance(seed, int) or seed < 0):
        raise ValueError(f"seed must be a non-negative integer, not {seed!r}")
    text = _tabula.plan_motion(
        robot,
        None if scene is None else str(scene),
        _target(start, "start"),
        _target(goal, "goal"),
        group,
        None if request is None else str(request),
        _params(params),
        None if timeout is None else float(timeout),
        seed,
    )
    return json.loads(text)


class Scene:
    """A scene file in tabula's simulator. Jobs are judged by its physics and answer
    with the command line's ``--json`` content; each changes the scene as it would the
    world (the next starts where the last left it)."""

    def __init__(self, path: PathLike):
        self._scene = _tabula.Scene(str(path))

    def settle(self) -> dict:
        """Steps the physics until everything rests: ``{steps, simulated_seconds,
        all_asleep}``."""
        return json.loads(self._scene.settle())

    def cameras(self) -> list:
        """The scene's camera names."""
        return self._scene.cameras()

    def capture(self, camera: Optional[str] = None, seed: int = 1) -> Tuple[np.ndarray, np.ndarray]:
        """A depth frame: ``(points (h, w, 3) in the camera's optical frame, NaN where
        nothing was hit, world_from_camera (4, 4))``."""
        points, pose = self._scene.capture(camera, int(seed))
        return points, np.asarray(pose)

    def to_toml(self) -> str:
        """The world now, as a scene file."""
        return self._scene.to_toml()

    def clear(self, seed: int = 1, max_actions: Optional[int] = None) -> dict:
        """Clears the table into the bin by grasps and pushes (seed 002)."""
        return json.loads(self._scene.clear(int(seed), max_actions))

    def place(self, arm: Optional[str] = None, seed: int = 1) -> dict:
        """Places the held object stably on a free spot of a surface it finds (seed 000)."""
        return json.loads(self._scene.place(arm, int(seed)))

    def pick_place(self, pick, place, arm: Optional[str] = None, seed: int = 1) -> dict:
        """Picks the object near ``pick`` and puts it at ``place`` (world, m)."""
        p = _vector(pick, "pick").tolist()
        q = _vector(place, "place").tolist()
        if len(p) != 3 or len(q) != 3:
            raise ValueError("pick and place are (x, y, z) points")
        return json.loads(self._scene.pick_place(p, q, arm, int(seed)))

    def tidy(self, source: str = "table", seed: int = 1) -> dict:
        """Moves every object off ``source`` onto other surfaces the robot finds."""
        return json.loads(self._scene.tidy(source, int(seed)))
