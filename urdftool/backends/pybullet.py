"""PyBullet as a backend: load a URDF headless, hear what it says, read back what it built.

PyBullet reports problems with a file by printing them from C (``b3Warning``,
``b3Error`` and plain ``printf`` lines such as "joint unsupported") to the
process's standard output, where Python cannot catch them. :func:`captured_output`
therefore redirects file descriptor 1 itself into a temporary file for the
duration of a call, flushing C's buffers before it restores it. ``import
pybullet`` also prints a banner, so it is imported inside the capture too.

Frames: PyBullet places each body at its *inertial* frame (centre of mass,
principal axes). The URDF link frame is read from ``getLinkState``'s
``worldLinkFrame*`` fields for links, and computed for the base from its
inertial pose and ``getDynamicsInfo``'s local inertial frame.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import re
import sys
import tempfile
import threading
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import field
from types import ModuleType, TracebackType
from typing import Any, cast

from urdftool.model.pose import Matrix, Vec3, homogeneous, quaternion_to_matrix
from urdftool.records import record

#: PyBullet's joint type numbers, by name.
JOINT_TYPE_NAMES = {
    0: "revolute",
    1: "prismatic",
    2: "spherical",
    3: "planar",
    4: "fixed",
    5: "point2point",
    6: "gear",
}

_CAPTURE_LOCK = threading.RLock()
_MARKER = re.compile(r"b3(?:Warning|Error)\[[^\]]*\]:\s*")
#: Lines PyBullet prints with plain printf that announce a changed or ignored element.
_PLAIN_WARNING = re.compile(r"^\s*(warning|error)\b", re.IGNORECASE)


@contextlib.contextmanager
def captured_output() -> Iterator[list[str]]:
    """Capture everything written to file descriptors 1 and 2 (C and Python) into the yielded list.

    The list is filled when the block ends: one string, the whole output.
    """
    with _CAPTURE_LOCK:
        sys.stdout.flush()
        sys.stderr.flush()
        libc = ctypes.CDLL(None)
        holder: list[str] = []
        with tempfile.TemporaryFile() as sink:
            saved = [os.dup(1), os.dup(2)]
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            try:
                yield holder
            finally:
                sys.stdout.flush()
                sys.stderr.flush()
                libc.fflush(None)  # C's stdout is fully buffered when it is a file
                for fd, copy in zip((1, 2), saved, strict=True):
                    os.dup2(copy, fd)
                    os.close(copy)
                sink.seek(0)
                holder.append(sink.read().decode("utf-8", "replace"))


def engine_messages(output: str) -> list[str]:
    """The warnings and errors in PyBullet's printed output, one string each.

    A ``b3Warning[file,line]:`` marker is followed by its message on the next
    line (often without a newline before the next marker); other lines that
    start with "Warning" or "Error" are messages of their own. The build-time
    banner and informational lines are not messages.
    """
    messages: list[str] = []
    parts = _MARKER.split(output)
    plain = parts[0].splitlines()
    for part in parts[1:]:
        first, *rest = part.strip().splitlines() or [""]
        messages.append(first.strip())
        plain.extend(rest)
    messages.extend(line.strip() for line in plain if _PLAIN_WARNING.match(line))
    return [m for m in messages if m]


def import_pybullet() -> ModuleType:
    """``pybullet``, imported without letting its banner reach standard output."""
    if "pybullet" in sys.modules:
        return sys.modules["pybullet"]
    with captured_output():
        import pybullet
    return cast(ModuleType, pybullet)


@record
class EngineLink:
    """A link as PyBullet built it. ``index`` is -1 for the base.

    ``inertial_frame`` (4×4) is the centre of mass and principal axes in the
    URDF link frame; ``inertia_diagonal`` (kg·m²) the moments about those axes.
    """

    name: str
    index: int
    mass: float
    inertia_diagonal: Vec3
    inertial_frame: Matrix


@record
class EngineJoint:
    """A joint as PyBullet built it; ``axis`` is in the child link frame, as PyBullet stores it."""

    name: str
    index: int
    type: str
    child: str
    axis: Vec3
    lower: float
    upper: float
    effort: float
    velocity: float
    dof: int


def _frame(position: Any, orientation: Any) -> Matrix:
    x, y, z, w = (float(v) for v in orientation)
    px, py, pz = (float(v) for v in position)
    return homogeneous(quaternion_to_matrix((w, x, y, z)), (px, py, pz))


@record(frozen=False)
class PyBulletLoad:
    """A URDF loaded in a fresh headless PyBullet (``with PyBulletLoad(path) as loaded:``).

    ``messages`` are the engine's warnings and errors while loading; ``body``
    is ``None`` when it refused the file (``error`` says why).
    """

    path: str
    flags: int | None = None
    body: int | None = None
    error: str | None = None
    messages: list[str] = field(default_factory=list)
    _client: int = -1
    _p: Any = None
    _joints: list[EngineJoint] | None = None

    def __enter__(self) -> PyBulletLoad:
        p = import_pybullet()
        self._p = p
        flags = p.URDF_USE_INERTIA_FROM_FILE if self.flags is None else self.flags
        with captured_output() as output:
            self._client = p.connect(p.DIRECT)
            try:
                self.body = p.loadURDF(self.path, flags=flags, physicsClientId=self._client)
            except p.error as exc:
                self.error = str(exc)
        self.messages = engine_messages(output[0])
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        if self._client >= 0:
            self._p.disconnect(physicsClientId=self._client)
            self._client = -1

    def _call(self, name: str, *args: Any, **kwargs: Any) -> Any:
        return getattr(self._p, name)(*args, physicsClientId=self._client, **kwargs)

    def links(self) -> list[EngineLink]:
        """The base, then every link in PyBullet's order."""
        assert self.body is not None
        names = [(-1, self._call("getBodyInfo", self.body)[0].decode())]
        names += [(j.index, j.child) for j in self.joints()]
        out = []
        for index, name in names:
            info = self._call("getDynamicsInfo", self.body, index)
            out.append(
                EngineLink(
                    name,
                    index,
                    float(info[0]),
                    tuple(float(v) for v in info[2]),  # type: ignore[arg-type]
                    _frame(info[3], info[4]),
                )
            )
        return out

    def joints(self) -> list[EngineJoint]:
        """Every joint in PyBullet's order (joint *i* carries link *i*)."""
        assert self.body is not None
        if self._joints is not None:
            return self._joints
        out = []
        for index in range(self._call("getNumJoints", self.body)):
            info = self._call("getJointInfo", self.body, index)
            kind = JOINT_TYPE_NAMES.get(int(info[2]), str(info[2]))
            out.append(
                EngineJoint(
                    info[1].decode(),
                    index,
                    kind,
                    info[12].decode(),
                    tuple(float(v) for v in info[13]),  # type: ignore[arg-type]
                    float(info[8]),
                    float(info[9]),
                    float(info[10]),
                    float(info[11]),
                    _dof(self._p, int(info[2])),
                )
            )
        self._joints = out
        return out

    def link_frames(self, positions: Mapping[int, float]) -> dict[str, Matrix]:
        """World pose (4×4) of every URDF link frame with joint *index* at *positions* (rad or m).

        Joints not named sit at 0; the base stays where it was loaded.
        """
        assert self.body is not None
        for joint in self.joints():
            if joint.dof == 1:
                self._call(
                    "resetJointState",
                    self.body,
                    joint.index,
                    float(positions.get(joint.index, 0.0)),
                )
        position, orientation = self._call("getBasePositionAndOrientation", self.body)
        import numpy as np

        info = self._call("getDynamicsInfo", self.body, -1)
        base_name = self._call("getBodyInfo", self.body)[0].decode()
        frames = {
            base_name: _frame(position, orientation) @ np.linalg.inv(_frame(info[3], info[4]))
        }
        for joint in self.joints():
            state = self._call(
                "getLinkState", self.body, joint.index, computeForwardKinematics=True
            )
            frames[joint.child] = _frame(state[4], state[5])
        return frames


#: Mimic joints as gear constraints that hold: error reduction 1 (PyBullet's default leaves the
#: position error uncorrected, so a five-follower gripper drifts by 0.4 rad), a force bound far
#: above any joint's, and more solver iterations (50 leave 0.02 rad on TIAGo Pro's gripper; 200
#: leave 0.001). See docs/pybullet.md.
MIMIC_ERP = 1.0
MIMIC_MAX_FORCE = 1e6
MIMIC_SOLVER_ITERATIONS = 200


def couple_mimics(
    p: Any, client: int, body: int, mimics: Iterable[tuple[str, str, float, float]]
) -> list[int]:
    """Tie each (follower, leader, multiplier, offset) joint pair of *body* with a gear constraint
    (follower = multiplier · leader + offset); the constraint ids. Pairs not in *body* are skipped.
    The client's solver iterations are raised to :data:`MIMIC_SOLVER_ITERATIONS` when lower."""
    index = {}
    for i in range(p.getNumJoints(body, physicsClientId=client)):
        index[p.getJointInfo(body, i, physicsClientId=client)[1].decode()] = i
    made = []
    for follower, leader, multiplier, offset in mimics:
        if follower not in index or leader not in index:
            continue
        constraint = p.createConstraint(
            body, index[follower], body, index[leader], jointType=p.JOINT_GEAR,
            jointAxis=[0, 0, 1], parentFramePosition=[0, 0, 0], childFramePosition=[0, 0, 0],
            physicsClientId=client,
        )
        p.changeConstraint(
            constraint, gearRatio=-multiplier, relativePositionTarget=offset, erp=MIMIC_ERP,
            maxForce=MIMIC_MAX_FORCE, physicsClientId=client,
        )
        made.append(constraint)
    if made:
        current = p.getPhysicsEngineParameters(physicsClientId=client).get("numSolverIterations", 0)
        if current < MIMIC_SOLVER_ITERATIONS:
            p.setPhysicsEngineParameter(
                numSolverIterations=MIMIC_SOLVER_ITERATIONS, physicsClientId=client
            )
    return made


def _dof(p: Any, joint_type: int) -> int:
    return {p.JOINT_REVOLUTE: 1, p.JOINT_PRISMATIC: 1, p.JOINT_SPHERICAL: 3, p.JOINT_PLANAR: 3}.get(
        joint_type, 0
    )
