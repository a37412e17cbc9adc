"""The smoke simulation in PyBullet, from urdftool's own PyBullet URDF in a temporary folder.

PyBullet loads URDF from files only, so the export (and its converted meshes)
is written to a temporary directory that is removed afterwards. Set-up, as a
user gets it plus what "zero commands" needs:

* loaded with ``URDF_USE_INERTIA_FROM_FILE`` (the flag the export is meant
  for), ``useFixedBase`` for robots bolted to the world, onto a plane shape
  at z = 0 for mobile robots; self-collision stays off (PyBullet's default);
* PyBullet's default velocity motors (which hold every joint still) are
  switched off (force 0), each joint gets its ``<dynamics damping>`` as
  PyBullet joint damping, and the default linear/angular damping of links is
  0, so that, as in MuJoCo, joints are held by their own damping only;
* a mobile robot whose root link has no mass (``base_footprint``) is
  re-rooted at its heaviest fixed child, since PyBullet fixes massless bases;
* mimic joints are tied to what they follow by the gear constraints of
  :func:`~urdftool.backends.pybullet.couple_mimics` (PyBullet ignores ``<mimic>``).

Energy is computed from PyBullet's link states: ½ m v² + ½ ωᵀ I ω + m g z for
the base and every link, at each link's centre of mass.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from urdftool.backends.pybullet import captured_output, couple_mimics, import_pybullet
from urdftool.catalogue.conversion import EngineRejected
from urdftool.facts.simulation.record import EngineRun, Penetration, Recorder
from urdftool.facts.simulation.scene import (
    DROP_CLEARANCE,
    GRAVITY,
    PENETRATION_TOLERANCE,
    HoldController,
    Scene,
    SimOptions,
)
from urdftool.model import Joint
from urdftool.model.pose import quaternion_to_matrix

#: Joint speed clamp (rad/s or m/s), far above the instability bound (PyBullet's default is 100).
MAX_JOINT_VELOCITY = 1e4


def run_pybullet(scene: Scene, path: Path, options: SimOptions) -> EngineRun:
    """Simulate the PyBullet URDF *path* (urdftool's export of *scene*'s robot) for ``options.duration`` s."""
    run = EngineRun("pybullet")
    p = import_pybullet()
    with captured_output():
        client = p.connect(p.DIRECT)
    try:
        world = _World(p, client, scene)
        with captured_output():
            loaded = world.load(path, options)
        if loaded is not None:
            run.refused = [_rejected(scene, loaded)]
            return run
        run.penetrations = _penetrations(p, path, scene, options)
        run.self_collision = world.self_collision
        return world.simulate(options, run)
    finally:
        p.disconnect(physicsClientId=client)


def _penetrations(p: Any, path: Path, scene: Scene, options: SimOptions) -> list[Penetration]:
    """Overlapping links at the start pose, measured in a second client that loads the robot with
    self-collision on: PyBullet answers no query about two links of one body without it, and the
    simulation itself keeps PyBullet's default (self-collision off)."""
    with captured_output():
        client = p.connect(p.DIRECT)
    try:
        probe = _World(p, client, scene, self_collision=True)
        with captured_output():
            failed = probe.load(path, options)
        if failed is not None:
            return []
        probe.call("performCollisionDetection")
        return probe.penetrations()
    finally:
        p.disconnect(physicsClientId=client)


def _rejected(scene: Scene, message: str) -> Any:
    return EngineRejected.diagnostic(f"PyBullet refused the exported model: {message}", scene.robot.span,
                                     data={"engine": "pybullet"})


class _World:
    """One PyBullet client holding the robot (and the ground for mobile robots)."""

    def __init__(self, p: Any, client: int, scene: Scene, self_collision: bool = False):
        self.p, self.client, self.scene = p, client, scene
        self.self_collision = self_collision
        self.body = -1
        self.joints: list[Joint] = []
        self.indices: list[int] = []
        self.links: list[int] = []

    def call(self, name: str, *args: Any, **kwargs: Any) -> Any:
        return getattr(self.p, name)(*args, physicsClientId=self.client, **kwargs)

    def load(self, path: Path, options: SimOptions) -> str | None:
        """Load the robot and set it up; the engine's message when it refuses."""
        p = self.p
        self.call("setGravity", 0.0, 0.0, -GRAVITY)
        if options.timestep:
            self.call("setTimeStep", options.timestep)
        if self.scene.floating:
            plane = self.call("createCollisionShape", p.GEOM_PLANE)
            self.call("createMultiBody", 0, plane)
        try:
            flags = p.URDF_USE_INERTIA_FROM_FILE | (p.URDF_USE_SELF_COLLISION if self.self_collision else 0)
            self.body = self.call("loadURDF", str(path), flags=flags, useFixedBase=not self.scene.floating)
        except p.error as exc:
            return str(exc)
        self._map_joints()
        self._zero_commands()
        mimics = [(j.name, j.mimic.joint, j.mimic.multiplier, j.mimic.offset)
                  for j in self.scene.robot.joints if j.mimic is not None and j.dof == 1]
        couple_mimics(p, self.client, self.body, mimics)
        return None

    def _map_joints(self) -> None:
        by_name = {}
        for index in range(self.call("getNumJoints", self.body)):
            info = self.call("getJointInfo", self.body, index)
            by_name[info[1].decode()] = (index, int(info[2]))
        one_dof = (self.p.JOINT_REVOLUTE, self.p.JOINT_PRISMATIC)
        for joint in self.scene.tree.joints_in_order:
            index, kind = by_name.get(joint.name, (-1, -1))
            if joint.dof == 1 and kind in one_dof:
                self.joints.append(joint)
                self.indices.append(index)
        self.links = [-1, *range(self.call("getNumJoints", self.body))]

    def _zero_commands(self) -> None:
        p = self.p
        self.call("setJointMotorControlArray", self.body, self.indices, p.VELOCITY_CONTROL,
                  forces=[0.0] * len(self.indices))
        for link in self.links:
            # PyBullet clamps joint speeds at 100 rad/s by default, which hides a blow-up.
            self.call("changeDynamics", self.body, link, linearDamping=0.0, angularDamping=0.0,
                      maxJointVelocity=MAX_JOINT_VELOCITY)
        for joint, index in zip(self.joints, self.indices, strict=True):
            damping = joint.dynamics.damping if joint.dynamics else 0.0
            self.call("changeDynamics", self.body, index, jointDamping=float(damping))
            self.call("resetJointState", self.body, index, self.scene.start.get(joint.name, 0.0))

    def simulate(self, options: SimOptions, run: EngineRun) -> EngineRun:
        if self.scene.floating:
            self._place_on_ground()
        timestep = float(self.call("getPhysicsEngineParameters")["fixedTimeStep"])
        steps = max(1, round(options.duration / timestep))
        recorder = Recorder(run, self.joints, steps, timestep)
        hold = self._hold() if options.hold else None
        energy = _Energy(self)
        started = time.perf_counter()
        for _ in range(steps):
            positions, velocities = self._joint_states()
            origin, linear = self._base()
            if not recorder.record(positions, velocities, origin, linear, energy.total()):
                break
            if hold is not None:
                self.call("setJointMotorControlArray", self.body, self.indices, self.p.TORQUE_CONTROL,
                          forces=list(hold.torques(positions, velocities)))
            self.call("stepSimulation")
        return recorder.finish(time.perf_counter() - started, self.scene.energy_scale)

    def _joint_states(self) -> tuple[Any, Any]:
        states = self.call("getJointStates", self.body, self.indices) if self.indices else []
        return np.array([s[0] for s in states]), np.array([s[1] for s in states])

    def _base(self) -> tuple[Any, Any]:
        """The root link frame's origin (m) and the base's linear velocity (m/s) in the world."""
        position, orientation = self.call("getBasePositionAndOrientation", self.body)
        info = self.call("getDynamicsInfo", self.body, -1)
        x, y, z, w = orientation
        rotation = quaternion_to_matrix((w, x, y, z))
        inertial = quaternion_to_matrix((info[4][3], info[4][0], info[4][1], info[4][2]))
        origin = np.asarray(position) - rotation @ inertial.T @ np.asarray(info[3])
        linear, _ = self.call("getBaseVelocity", self.body)
        return origin, np.asarray(linear)

    def _place_on_ground(self) -> None:
        lowest = min((self.call("getAABB", self.body, link)[0][2] for link in self.links
                      if self.call("getCollisionShapeData", self.body, link)), default=None)
        if lowest is None:
            return
        position, orientation = self.call("getBasePositionAndOrientation", self.body)
        lifted = (position[0], position[1], position[2] + DROP_CLEARANCE - lowest)
        self.call("resetBasePositionAndOrientation", self.body, lifted, orientation)

    def _link_name(self, link: int) -> str:
        if link < 0:
            return str(self.call("getBodyInfo", self.body)[0].decode())
        return str(self.call("getJointInfo", self.body, link)[12].decode())

    def penetrations(self) -> list[Penetration]:
        """Pairs of non-neighbouring links whose collision shapes overlap by more than the tolerance."""
        colliding = [link for link in self.links if self.call("getCollisionShapeData", self.body, link)]
        names = {link: self._link_name(link) for link in colliding}
        found = []
        for i, a in enumerate(colliding):
            for b in colliding[i + 1:]:
                if self.scene.touching(names[a], names[b]):
                    continue
                points = self.call("getClosestPoints", self.body, self.body, 0.0, a, b)
                depth = max((-pt[8] for pt in points), default=0.0)
                if depth > PENETRATION_TOLERANCE:
                    link_a, link_b = sorted((names[a], names[b]))
                    found.append(Penetration(link_a, link_b, float(depth)))
        return sorted(found, key=lambda p: (-p.depth, p.link_a, p.link_b))

    def _hold(self) -> HoldController:
        positions, _ = self._joint_states()
        return HoldController.at(positions, self._mass_diagonal(), self.joints)

    def _mass_diagonal(self) -> Any:
        """Diagonal of PyBullet's joint-space mass matrix at the recorded joints (base DOF first)."""
        movable = [i for i in self.links[1:]
                   if self.call("getJointInfo", self.body, i)[2] != self.p.JOINT_FIXED]
        positions = [self.call("getJointState", self.body, i)[0] for i in movable]
        matrix = np.asarray(self.call("calculateMassMatrix", self.body, positions))
        offset = matrix.shape[0] - len(movable)
        column = {index: offset + k for k, index in enumerate(movable)}
        return np.array([matrix[column[i], column[i]] for i in self.indices])


class _Energy:
    """Kinetic plus gravitational energy (J) of the whole multibody, from PyBullet's link states."""

    def __init__(self, world: _World):
        self.world = world
        infos = [world.call("getDynamicsInfo", world.body, link) for link in world.links]
        self.mass = np.array([info[0] for info in infos])
        self.inertia = np.array([info[2] for info in infos])

    def total(self) -> float:
        w = self.world
        position, orientation = w.call("getBasePositionAndOrientation", w.body)
        linear, angular = w.call("getBaseVelocity", w.body)
        frames = [(position, orientation, linear, angular)]
        if len(w.links) > 1:
            states = w.call("getLinkStates", w.body, w.links[1:], computeLinkVelocity=1)
            frames += [(s[0], s[1], s[6], s[7]) for s in states]
        energy = 0.0
        for (pos, quat, v, omega), m, diagonal in zip(frames, self.mass, self.inertia, strict=True):
            x, y, z, qw = quat
            rotation = quaternion_to_matrix((qw, x, y, z))
            local = rotation.T @ np.asarray(omega)
            energy += 0.5 * m * float(np.dot(v, v)) + 0.5 * float(local @ (diagonal * local))
            energy += m * GRAVITY * float(pos[2])
        return energy
