"""Conversion (C): what an export cannot carry, reported per element.

These rules are raised by exporters (``urdftool convert``, ``urdftool.to_mjcf``),
not by ``check``: what is lost or changed depends on the target and its options.
Each finding points at the element of the source that was dropped or changed.
"""

from __future__ import annotations

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Severity


class _Conversion(Rule):
    family = Family.CONVERSION


@register
class ConversionDropped(_Conversion):
    """An element of the source has no equivalent in the target and was left out.

    ## What it does
    Reports, once per element, what an export leaves behind: Gazebo plugins
    and sensors, `<gazebo>` physics and material blocks, transmissions and
    `ros2_control` blocks that no actuator carries, link textures, SDF-only
    elements inside a URDF link, planes on moving links, and the rotational
    part of a cut revolute joint closing a loop. `data` names the element
    and the reason, so CI can diff the loss report between releases.

    ## Why it matters
    A converter that drops things silently produces a model that looks right
    and behaves differently: a robot whose wheel plugin vanished does not
    drive, a camera that vanished publishes nothing. Knowing exactly what was
    lost lets you re-create it in the target (MuJoCo sensors, actuators).

    ## Example
    ```xml
    <gazebo>
      <plugin name="diff_drive" filename="libgazebo_ros_diff_drive.so"/>
    </gazebo>
    ```
    exported to MJCF: MuJoCo has no Gazebo plugins.

    ## Fix
    Nothing to fix in the source when the loss is expected; add the MuJoCo
    equivalent (an `<actuator>`, a `<sensor>`) to the exported model or in a
    file that includes it. Use `--actuators auto` (or `position`, `velocity`, `motor`) to map
    transmissions to actuators.
    """

    code = "C001"
    name = "conversion-dropped"
    severity = Severity.WARNING


@register
class InertiaRepaired(_Conversion):
    """`--repair-inertia` changed a link's mass or inertia; the message gives before and after.

    ## What it does
    Reports every change that `--repair-inertia` makes, at the link's
    `<inertial>`: a tensor moved to the nearest physically valid one (principal
    moments raised to a floor and the triangle inequality restored, principal
    axes kept), a negative mass made positive, inertia without mass removed,
    and the minimum mass and inertia given to a moving link that carries none.
    `data` holds the values before and after.

    ## Why it matters
    A repair makes the model load and simulate, but it is not the robot's real
    mass distribution. Every change is reported so that it can be reviewed and
    fixed at the source instead of being forgotten.

    ## Example
    ```xml
    <inertial>
      <mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.3"/>
    </inertial>
    ```
    principal moments 0.1, 0.1, 0.3 break A + B >= C; the repair gives
    0.1333, 0.1333, 0.2667.

    ## Fix
    Write the real inertia in the source (CAD, or the formula for the link's
    shape) so that no repair is needed.
    """

    code = "C002"
    name = "inertia-repaired"
    severity = Severity.WARNING


@register
class InertiaNotExportable(_Conversion):
    """A link's mass or inertia is physically invalid, or too small for the target engine.

    ## What it does
    Refuses the export at the link's `<inertial>` (or the link, when it has
    none) when the tensor is not positive definite, breaks the triangle
    inequality A + B >= C of its principal moments, the mass is negative, a
    massless link has inertia, or a moving body (a link with its own joint,
    together with the links fixed to it) has less mass or inertia than the
    engine can integrate (MuJoCo: 1e-15 kg and kg·m² on every principal axis).
    The message names the numbers.

    ## Why it matters
    MuJoCo refuses such a model ("mass and inertia of moving bodies must be
    larger than mjMINVAL", "inertia must satisfy A + B >= C"); other converters
    quietly change the numbers, and the exported robot is then not the source
    robot. urdftool never changes them silently.

    ## Example
    ```xml
    <link name="camera_link">
      <inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
    </link>
    <joint name="pan" type="revolute"> <child link="camera_link"/> ... </joint>
    ```

    ## Fix
    Give the link its real mass and inertia (for a 0.1 kg box 5×5×5 cm:
    ixx = iyy = izz = 4.2e-5 kg·m²), or export with `--repair-inertia`, which
    applies a minimal documented repair and reports each change as
    `inertia-repaired`.
    """

    code = "C003"
    name = "inertia-not-exportable"
    severity = Severity.ERROR


@register
class MeshNotExportable(_Conversion):
    """A mesh was left out of the export: its file was not found or cannot be read.

    ## What it does
    Reports, at the `<mesh>` element, a visual or collision mesh whose file
    did not resolve, does not exist, or that neither the target engine nor
    trimesh can read. The export carries on without that geom (the link keeps
    its body, mass and inertia), so the rest of the robot can still be used
    and verified.

    ## Why it matters
    The engine would refuse to load a model that names a missing file. Left
    out, a visual mesh only changes what you see, but a collision mesh changes
    what the robot touches: the warning says which one it was.

    ## Example
    ```xml
    <mesh filename="package://arm/meshes/forearm.stl"/>
    ```
    where `arm` has no `meshes/forearm.stl`.

    ## Fix
    Make the path resolve (`--package NAME=DIR`, `--package-path DIR`), or
    convert the file to STL or OBJ.
    """

    code = "C004"
    name = "mesh-not-exportable"
    severity = Severity.WARNING


@register
class EngineRejected(_Conversion):
    """The target engine refused the exported file; the message is the engine's, mapped to the source.

    ## What it does
    Reports an error from the engine that loads the export (MuJoCo's compiler
    for MJCF) during `--verify`, located at the link, joint or mesh of the
    source that the failing element came from, and reports each quantity that
    differs between the engine and the source model beyond its tolerance.

    ## Why it matters
    An export that does not load, or that loads as a different robot, is worse
    than no export. This is either a defect of the source the other rules did
    not catch or a bug in urdftool's exporter.

    ## Example
    A mesh whose triangles are all coplanar used for collision: MuJoCo cannot
    build its convex hull.

    ## Fix
    Fix the element named in the message; if the source is valid, report the
    file to the urdftool maintainers.
    """

    code = "C005"
    name = "engine-rejected"
    severity = Severity.ERROR


@register
class SdfDefaultInertia(_Conversion):
    """An SDF link without `<inertial>` was exported with SDFormat's default, 1 kg and unit inertia.

    ## What it does
    Reports, once per link, each link of an SDF model that declares no
    `<inertial>` and moves (it is not welded to the world) when it is
    exported to a format without that default (MJCF, PyBullet's URDF, URDF):
    the export writes 1 kg and 1 kg·m² about each axis of the link frame at the
    link origin. `data` names the link and the mass written. A link welded to
    the world (a static model's links, or links fixed to `world`) gets nothing:
    its mass acts on nothing a simulation measures.

    ## Why it matters
    SDFormat's `<inertial>` defaults are `<mass>` 1 and `<ixx>`, `<iyy>`,
    `<izz>` 1 (the specification's `inertial.sdf`), and libsdformat, gz-sim and
    Gazebo classic use them for a link that has none, so the SDF robot weighs
    that in its own simulator. MJCF (`inertiafromgeom="false"`) and URDF read
    0 kg instead, so an export that left the link empty would simulate a
    different robot. The export keeps the SDF robot's mass; this note says
    that the mass is SDFormat's, not the author's (`missing-inertial` says it
    on `check`). It is not a repair: `--repair-inertia` is not needed and does
    not change it.

    ## Example
    ```xml
    <link name="lidar">
      <visual name="v"><geometry><sphere><radius>0.04</radius></sphere></geometry></visual>
    </link>
    ```
    on a revolute joint, exported to MJCF: the body gets `mass="1"` and
    `diaginertia="1 1 1"`.

    ## Fix
    Write the link's real `<inertial>` in the SDF file.
    """

    code = "C007"
    name = "sdf-default-inertia"
    severity = Severity.INFO
