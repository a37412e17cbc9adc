"""The smoke simulation in MuJoCo, from urdftool's own MJCF export, compiled in memory.

The MJCF comes from :func:`urdftool.export.mjcf.build` with absolute mesh paths
(converted meshes travel in the assets dict), a free base and the export's
ground plane for mobile robots, a fixed base and no ground otherwise. Loops
from SDF are the export's equality constraints. Energy is MuJoCo's own
(``mjENBL_ENERGY``: gravity potential plus kinetic energy). MuJoCo resets the
state when an acceleration is not finite (warning ``mjWARN_BADQACC``); that
counts as diverging.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from urdftool.backends.mujoco import positions_and_mass_matrix
from urdftool.catalogue.conversion import EngineRejected
from urdftool.diagnostics import Diagnostic
from urdftool.facts.simulation.record import EngineRun, Penetration, Recorder
from urdftool.facts.simulation.scene import (
    DROP_CLEARANCE,
    PENETRATION_TOLERANCE,
    HoldController,
    Scene,
    SimOptions,
)
from urdftool.model import Joint


def run_mujoco(scene: Scene, path: Path, options: SimOptions) -> EngineRun:
    """Simulate the MJCF file *path* (urdftool's export of *scene*'s robot) for ``options.duration`` s."""
    import mujoco

    run = EngineRun("mujoco")
    compiled = _compile(scene, path, run)
    if compiled is None:
        return run
    model = compiled
    if options.timestep:
        model.opt.timestep = options.timestep
    model.opt.enableflags |= int(mujoco.mjtEnableBit.mjENBL_ENERGY)
    data = mujoco.MjData(model)
    joints, qpos, dofs = _one_dof_joints(model, scene)
    for joint, address in zip(joints, qpos, strict=True):
        data.qpos[address] = scene.start.get(joint.name, 0.0)
    free = _free_joint(model) if scene.floating else None
    if free is not None:
        _place_on_ground(model, data, int(model.jnt_qposadr[free]))
    mujoco.mj_forward(model, data)
    run.penetrations = _penetrations(model, data, scene)
    steps = max(1, round(options.duration / model.opt.timestep))
    recorder = Recorder(run, joints, steps, float(model.opt.timestep))
    hold = _hold_gains(model, data, joints, dofs) if options.hold else None
    base = _root_body(model, scene)
    free_dof = int(model.jnt_dofadr[free]) if free is not None else None
    loops = LoopGap(model)
    started = time.perf_counter()
    for _ in range(steps):
        base_velocity = data.qvel[free_dof:free_dof + 3] if free_dof is not None else np.zeros(3)
        if not recorder.record(data.qpos[qpos], data.qvel[dofs], data.xpos[base], base_velocity,
                               float(data.energy[0] + data.energy[1])):
            break
        if hold is not None:
            data.qfrc_applied[dofs] = hold.torques(data.qpos[qpos], data.qvel[dofs])
        mujoco.mj_step(model, data)
        if _diverged(data):
            run.diverged_at = float(data.time)
            break
        loops.measure(data)
    finished = recorder.finish(time.perf_counter() - started, scene.energy_scale)
    finished.loop_gap = loops.largest
    return finished


class LoopGap:
    """The largest gap (m) of the loop closures over a run: the norm of the position rows of
    each connect or weld equality in MuJoCo's constraint residuals (``efc_pos``)."""

    def __init__(self, model: Any) -> None:
        import mujoco

        kinds = (int(mujoco.mjtEq.mjEQ_CONNECT), int(mujoco.mjtEq.mjEQ_WELD))
        self._closures = {i for i in range(model.neq) if int(model.eq_type[i]) in kinds}
        self._equality = int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)
        self.largest: float | None = 0.0 if self._closures else None

    def measure(self, data: Any) -> None:
        if self.largest is None:
            return
        rows = np.flatnonzero(data.efc_type[:data.nefc] == self._equality)
        ids = data.efc_id[rows]
        for eq in self._closures:
            position = data.efc_pos[rows[ids == eq][:3]]  # connect: 3 rows; weld: 3 of 6
            if position.size:
                self.largest = max(self.largest, float(np.linalg.norm(position)))


def _compile(scene: Scene, path: Path, run: EngineRun) -> Any:
    """The compiled model, or ``None`` with ``run.refused`` saying why."""
    import mujoco

    try:
        return mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        run.refused = [_rejected(scene, "MuJoCo", str(exc))]
        return None


def _rejected(scene: Scene, engine: str, message: str) -> Diagnostic:
    return EngineRejected.diagnostic(
        f"{engine} refused the exported model: {' '.join(message.split())}", scene.robot.span,
        data={"engine": engine.lower()})


def _one_dof_joints(model: Any, scene: Scene) -> tuple[list[Joint], list[int], list[int]]:
    """The robot's one-DOF joints MuJoCo has (by name), with their qpos and dof addresses."""
    import mujoco

    joints, qpos, dofs = [], [], []
    for joint in scene.tree.joints_in_order:
        if joint.dof != 1:
            continue
        jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint.name)
        if jid >= 0:
            joints.append(joint)
            qpos.append(int(model.jnt_qposadr[jid]))
            dofs.append(int(model.jnt_dofadr[jid]))
    return joints, qpos, dofs


def _free_joint(model: Any) -> int | None:
    import mujoco

    for jid in range(model.njnt):
        if model.jnt_type[jid] == mujoco.mjtJoint.mjJNT_FREE:
            return jid
    return None


def _root_body(model: Any, scene: Scene) -> int:
    import mujoco

    bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, scene.tree.root or "")
    return max(int(bid), 0)


def _collision_geoms(model: Any) -> list[int]:
    """Geoms of the robot that collide (not the ground, which belongs to the world body)."""
    return [g for g in range(model.ngeom)
            if model.geom_bodyid[g] != 0 and (model.geom_contype[g] or model.geom_conaffinity[g])]


def _lowest_point(model: Any, data: Any) -> float | None:
    """Lowest z (m) of the robot's collision geometry (bounding boxes) at the current pose."""
    lowest = None
    for g in _collision_geoms(model):
        center, half = model.geom_aabb[g][:3], model.geom_aabb[g][3:]
        rotation = data.geom_xmat[g].reshape(3, 3)
        z = float(data.geom_xpos[g][2] + rotation[2] @ center - np.abs(rotation[2]) @ half)
        lowest = z if lowest is None else min(lowest, z)
    return lowest


def _place_on_ground(model: Any, data: Any, free_qpos: int) -> None:
    """Lift or lower the free base so the lowest collision point is just above z = 0."""
    import mujoco

    mujoco.mj_kinematics(model, data)
    lowest = _lowest_point(model, data)
    if lowest is not None:
        data.qpos[free_qpos + 2] += DROP_CLEARANCE - lowest


def _penetrations(model: Any, data: Any, scene: Scene) -> list[Penetration]:
    """Robot links overlapping at the start (MuJoCo's contacts), neighbours left out."""
    import mujoco

    found: dict[frozenset[str], float] = {}
    for contact in data.contact[:data.ncon]:
        if contact.dist >= -PENETRATION_TOLERANCE:
            continue
        bodies = [int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2])]
        if 0 in bodies:
            continue  # the ground
        a, b = (mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, i) for i in bodies)
        if scene.touching(a, b):
            continue
        key = frozenset((a, b))
        found[key] = max(found.get(key, 0.0), -float(contact.dist))
    penetrations = []
    for pair, depth in found.items():
        link_a, link_b = sorted(pair)
        penetrations.append(Penetration(link_a, link_b, depth))
    return sorted(penetrations, key=lambda p: (-p.depth, p.link_a, p.link_b))


def _hold_gains(model: Any, data: Any, joints: list[Joint], dofs: list[int]) -> HoldController:
    _, mass = positions_and_mass_matrix(model, data.qpos.copy())
    return HoldController.at([data.qpos[model.jnt_qposadr[_jid(model, j)]] for j in joints],
                           np.diag(mass)[dofs], joints)


def _jid(model: Any, joint: Joint) -> int:
    import mujoco

    return int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint.name))


def _diverged(data: Any) -> bool:
    import mujoco

    warnings = data.warning
    return any(warnings[int(w)].number > 0 for w in (mujoco.mjtWarning.mjWARN_BADQACC,
                                                     mujoco.mjtWarning.mjWARN_BADQPOS,
                                                     mujoco.mjtWarning.mjWARN_BADQVEL))
