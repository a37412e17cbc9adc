"""MuJoCo behind a lazy import: compiling a model file, mapping its errors, computing quantities.

MuJoCo's compiler errors name the element (``Element name 'forearm', id 3,
line 12``); :func:`compile_model` turns them into :class:`EngineError` with the
element's name so callers can point at the link or joint it came from.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from urdftool.records import record

_ELEMENT = re.compile(r"Element name '([^']*)'")
_LINE = re.compile(r"line (\d+)")


@record(frozen=False)
class EngineError(Exception):
    """MuJoCo refused the model: its message, and the element name and line it gave, if any."""

    message: str
    element: str | None = None
    line: int | None = None

    def __str__(self) -> str:
        return self.message


def compile_model(path: str | Path) -> Any:
    """``mujoco.MjModel`` compiled from the MJCF or URDF file at *path*. Raises :class:`EngineError`."""
    import mujoco

    try:
        return mujoco.MjModel.from_xml_path(str(path))
    except Exception as exc:  # MuJoCo raises ValueError for every compile error
        text = str(exc).strip()
        element = _ELEMENT.search(text)
        line = _LINE.search(text)
        raise EngineError(" ".join(text.split()), element.group(1) if element else None,
                          int(line.group(1)) if line else None) from exc


def positions_and_mass_matrix(model: Any, qpos: np.ndarray) -> tuple[Any, np.ndarray]:
    """Run kinematics and the composite-rigid-body algorithm at *qpos*; return the data
    (``xpos``, ``xmat`` filled) and the dense joint-space mass matrix (nv × nv)."""
    import mujoco

    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    mujoco.mj_makeM(model, data)
    dense = np.zeros((model.nv, model.nv))
    sparse = data.M if hasattr(data, "M") else data.qM
    try:
        mujoco.mj_fullM(model, data, dense)  # MuJoCo >= 3.5 / 4
    except TypeError:
        mujoco.mj_fullM(model, dense, sparse)
    return data, dense


def total_mass(model: Any) -> float:
    import mujoco

    return float(mujoco.mj_getTotalmass(model))


def name_to_id(model: Any, kind: str, name: str) -> int:
    """Id of the named body or joint (``kind`` ``"body"`` | ``"joint"``), -1 when absent."""
    import mujoco

    obj = {"body": mujoco.mjtObj.mjOBJ_BODY, "joint": mujoco.mjtObj.mjOBJ_JOINT}[kind]
    return int(mujoco.mj_name2id(model, obj, name))
