"""The ``home`` keyframe of a robot with closed loops, solved so that every loop is closed.

A keyframe built joint by joint (the source's or the SRDF's values, zero
elsewhere) leaves a closed chain open wherever the values do not fit together:
Cassie's Achilles rods start 103 mm from their heel springs. MuJoCo would snap
the loops shut on the first steps, throwing the robot. Instead the exporter
compiles the model in memory and projects the keyframe onto the loop
constraints (:func:`close_loops`): damped Gauss–Newton steps on the residuals of
the ``<equality>`` rows MuJoCo computes (``efc_pos``, ``efc_J`` after
``mj_forward``), ``dq = −W Jᵀ (J W Jᵀ + λI)⁻¹ r`` integrated with
``mj_integratePos``. The weights ``W`` keep what the source states: the free
base does not move (weight 0), joints whose home value the source gives move
reluctantly (:data:`STATED_WEIGHT`), the others (a ball joint of a rod, a spring
the state leaves out) take up the closure (weight 1). A free robot on a floor
is then lifted again so that its lowest collision geom is
:data:`~urdftool.export.placement.CLEARANCE` above it.
"""

from __future__ import annotations

import copy as copy_module
from collections.abc import Collection
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree

from urdftool.export.numbers import vec
from urdftool.export.placement import CLEARANCE
from urdftool.records import record
from urdftool.safe_files import read_regular

#: Weight of a joint whose home value the source states (others: 1, the free base: 0).
STATED_WEIGHT = 1e-3
#: Projection steps at most, and the residual (m, rad) at which they stop.
MAX_STEPS = 100
TOLERANCE = 1e-10
#: Damping of the least-squares step (keeps it finite when the loops cannot all close).
DAMPING = 1e-12
_FLOOR = "floor"


@record
class LoopSolve:
    """The home keyframe's largest loop residual (m or rad) before and after the projection."""

    before: float
    after: float
    steps: int


def compile_in_memory(root: etree._Element, out_dir: Path | None, files: dict[str, bytes]) -> Any:
    """*root* compiled by MuJoCo with its meshes read from *files* or disk; ``None`` when MuJoCo is
    missing or cannot compile it (the verifier reports why)."""
    try:
        import mujoco
    except ImportError:
        return None
    copy = copy_module.deepcopy(root)  # not a text round trip: lxml caps parsed depth at 256
    assets: dict[str, bytes] = {}
    for i, mesh in enumerate(copy.iter("mesh")):
        file = mesh.get("file")
        if not file:
            continue
        data = files.get(file)
        if data is None:
            path = Path(file) if Path(file).is_absolute() or out_dir is None else out_dir / file
            try:
                data = read_regular(path, "mesh")
            except OSError:
                return None
        key = f"m{i}{Path(file).suffix.lower()}"
        assets[key] = data
        mesh.set("file", key)
    try:
        return mujoco.MjModel.from_xml_string(etree.tostring(copy, encoding="unicode"), assets)
    except Exception:  # MuJoCo raises ValueError for any compile error
        return None


def _residual(model: Any, data: Any) -> tuple[np.ndarray, np.ndarray]:
    import mujoco

    mujoco.mj_forward(model, data)
    rows = np.flatnonzero(data.efc_type[:data.nefc] == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
    jac = np.asarray(data.efc_J[:data.nefc * model.nv]).reshape(data.nefc, model.nv)
    return np.asarray(data.efc_pos[rows]), jac[rows]


def _weights(model: Any, stated: Collection[str]) -> np.ndarray:
    import mujoco

    weights = np.ones(model.nv)
    for j in range(model.njnt):
        adr = int(model.jnt_dofadr[j])
        kind = int(model.jnt_type[j])
        if kind == mujoco.mjtJoint.mjJNT_FREE:
            weights[adr:adr + 6] = 0.0
        elif model.joint(j).name in stated:
            width = 3 if kind == mujoco.mjtJoint.mjJNT_BALL else 1
            weights[adr:adr + width] = STATED_WEIGHT
    return weights


def close_loops(root: etree._Element, out_dir: Path | None, files: dict[str, bytes],
                stated: Collection[str]) -> LoopSolve | None:
    """Project the ``home`` keyframe of *root* onto its loop constraints (in place); *stated*: the
    joints whose home value the source gives. ``None`` when there is nothing to solve."""
    key = root.find("keyframe/key[@name='home']")
    equality = root.find("equality")
    if key is None or equality is None or not any(e.tag in ("connect", "weld") for e in equality):
        return None
    try:
        import mujoco
    except ImportError:
        return None
    model = compile_in_memory(root, out_dir, files)
    if model is None:
        return None
    model.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    weights = _weights(model, stated)
    residual, jac = _residual(model, data)
    before = float(np.max(np.abs(residual), initial=0.0))
    steps = 0
    while steps < MAX_STEPS and residual.size and np.max(np.abs(residual)) > TOLERANCE:
        weighted = jac * weights
        system = weighted @ jac.T + DAMPING * np.eye(len(residual))
        if not (np.isfinite(system).all() and np.isfinite(residual).all()):
            break  # a loop of links far beyond any real size (1e16 m): the keyframe stays as read
        try:
            step = -weighted.T @ np.linalg.solve(system, residual)
        except np.linalg.LinAlgError:  # rounding at such sizes leaves the system singular
            break
        mujoco.mj_integratePos(model, data.qpos, step, 1.0)
        residual, jac = _residual(model, data)
        steps += 1
    lifted = _lift(model, data)
    key.set("qpos", vec(data.qpos.tolist()))
    if key.get("ctrl") is not None:  # position servos follow their solved joints
        ctrl = [float(data.qpos[model.jnt_qposadr[model.actuator_trnid[i, 0]]])
                if model.actuator_biastype[i] == mujoco.mjtBias.mjBIAS_AFFINE
                and model.actuator_gainprm[i, 0] == -model.actuator_biasprm[i, 1] else 0.0
                for i in range(model.nu)]
        key.set("ctrl", vec(ctrl))
    after = float(np.max(np.abs(residual), initial=0.0))
    placed = f"; root then at z = {lifted:.6g} m, 1 mm above the floor" if lifted is not None else ""
    solved = "solved" if after <= TOLERANCE else "not solved (the projection stopped short)"
    key.addprevious(etree.Comment(f" home {solved} for the loop closures: largest residual {before:.3g} "
                                  f"before, {after:.3g} after {steps} projection steps{placed} "))
    return LoopSolve(before, after, steps)


def _lift(model: Any, data: Any) -> float | None:
    """Raise a free root so its lowest colliding geom is :data:`CLEARANCE` above the floor; the
    root's new height, ``None`` without a floor or a free root."""
    import mujoco

    floor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, _FLOOR)
    if floor < 0 or model.njnt == 0 or model.jnt_type[0] != mujoco.mjtJoint.mjJNT_FREE:
        return None
    mujoco.mj_forward(model, data)
    gaps = [mujoco.mj_geomDistance(model, data, floor, g, 10.0, None) for g in range(model.ngeom)
            if g != floor and (model.geom_contype[g] or model.geom_conaffinity[g])]
    height = int(model.jnt_qposadr[0]) + 2
    if gaps:
        data.qpos[height] += CLEARANCE - min(gaps)
    return float(data.qpos[height])
