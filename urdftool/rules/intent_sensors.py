"""Sensor numbers (N006, N106): a camera's field of view in degrees, a lidar's limits out of order.

Gazebo sensors are SDF wherever they are written: under an SDF `<link>` (or `<joint>`), and
inside a URDF's `<gazebo reference="…">` blocks (Gazebo Classic and gz-sim read both alike).
Their angles are radians and their ranges metres (SDFormat `sensor.sdf`, `camera.sdf`,
`lidar.sdf`/`ray.sdf`); neither libsdformat nor gz-sensors nor Gazebo Classic checks them, so a
slip only shows as a wrong image or an empty scan.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from urdftool.catalogue.registry import register
from urdftool.catalogue.units import ONE_TURN
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import Robot
from urdftool.parse.locate import span_of
from urdftool.rules import gazebo_plugins as gz
from urdftool.rules.intent_common import IntentRule, written

#: A half turn (rad), plus the rounding of a written π (3.1416): what a pinhole camera cannot see.
HALF_TURN = math.pi + 0.01
#: Camera sensors whose lens may see more than a half turn (SDF `<lens>` or the wide-angle type).
WIDE_ANGLE_TYPES = frozenset({"wideanglecamera", "wide_angle_camera"})
#: Scan sensors whose rays turn through min_angle → max_angle one by one (Gazebo Classic's CPU
#: `ray`): with min > max they sweep backwards and publish a negative angle_increment, a
#: reversed scan rather than none; every other type (gpu_ray, gpu_lidar, lidar) renders a
#: field of view of max - min, which is then negative.
SWEEPING_TYPES = frozenset({"ray"})


def sensors(robot: Robot) -> Iterator[tuple[Any, str]]:
    """Every ``<sensor>`` element of the robot with the path of its owner: in the ``<gazebo>``
    blocks of a URDF, and under the links, joints and model of an SDF file."""
    seen: set[int] = set()
    for block in gz.gazebo_blocks(robot):
        owner = None  # written only for a block with a sensor: most blocks hold none
        for sensor in block.iter("sensor"):
            if owner is None:
                reference = block.get("reference")
                owner = f"gazebo[{reference}]" if reference else "gazebo"
            seen.add(id(sensor))
            yield sensor, owner
    holders: list[tuple[str, Any]] = [("link", link) for link in robot.links if link.extensions]
    holders += [("joint", joint) for joint in robot.joints if joint.extensions]
    holders.append(("model", robot))
    for kind, holder in holders:
        for extension in holder.extensions:
            element = extension.element
            if extension.tag != "sensor" or element is None or id(element) in seen:
                continue
            seen.add(id(element))
            # the owner's path is written only for a sensor: most links carry none
            yield element, (kind if holder is robot else f"{kind}[{holder.name}]")


def robot_sensors(ctx: CheckContext) -> list[tuple[Any, str]]:
    """:func:`sensors` of the robot under check, found once for both sensor rules (a search of
    every ``<gazebo>`` block: PR2's hold 860 elements)."""
    if "intent-sensors" not in ctx.cache:
        ctx.cache["intent-sensors"] = list(sensors(ctx.robot))
    found: list[tuple[Any, str]] = ctx.cache["intent-sensors"]
    return found


def _number(parent: Any, tag: str) -> tuple[float | None, Any]:
    """The finite number in *parent*'s child *tag* and that child (``None`` when absent, empty,
    an unexpanded substitution or not a number)."""
    child = parent.find(tag) if parent is not None else None
    if child is None:
        return None, None
    try:
        value = float((child.text or "").strip())
    except ValueError:
        return None, child
    return (value if math.isfinite(value) else None), child


def _where(sensor: Any, owner: str, *parts: str) -> str:
    name = sensor.get("name")
    return "/".join((owner, f"sensor[{name}]" if name else "sensor", *parts))


def _label(sensor: Any) -> str:
    return f"sensor '{sensor.get('name') or 'unnamed'}' ({sensor.get('type') or 'no type'})"


def _scans(sensor: Any) -> Iterator[tuple[str, Any]]:
    """The ``<ray>`` / ``<lidar>`` blocks of a sensor with their tag."""
    for tag in ("ray", "lidar"):
        for block in sensor.findall(tag):
            yield tag, block


@register
class SensorAngleLooksLikeDegrees(IntentRule):
    """A camera's field of view or a lidar's scan angle is only plausible as degrees.

    ## What it does
    Reads every Gazebo sensor (SDF `<sensor>` under a link or joint, and
    `<sensor>` in a URDF's `<gazebo>` blocks) and reports:

    - a camera's `<horizontal_fov>` beyond one turn (2π rad): an error, with
      the degree reading (`60 → 1.0472 rad`);
    - a camera's `<horizontal_fov>` between π and 2π (beyond a rounded
      `3.1416`) when the camera has no
      `<lens>` and is not a `wideanglecamera`: a warning, since only a
      fisheye or wide-angle lens sees a half turn or more;
    - a lidar's or ray sensor's `<min_angle>` or `<max_angle>` (horizontal or
      vertical) beyond one turn: an error, once per scan axis.

    Values written as xacro expressions are read after expansion
    (`${60.0/180.0*pi}` is 1.047).

    ## Why it matters
    SDFormat reads these angles in radians. A `horizontal_fov` of 60 is 60
    rad: a pinhole projection of more than a half turn has no meaning, so
    the camera renders garbage or nothing, and the intrinsics published with
    the images (CameraInfo) are wrong (compare gazebo-classic#3306,
    o3de-extras#558). A scan from -135 to 135 rad wraps the lidar around
    itself dozens of times.

    ## Example
    ```xml
    <camera><horizontal_fov>60</horizontal_fov></camera>
    ```

    ## Fix
    Write radians (`<horizontal_fov>1.0472</horizontal_fov>`, or
    `${radians(60)}` in xacro). A real fisheye wider than π needs a `<lens>`
    (gz-sim) or the `wideanglecamera` type (Gazebo Classic).
    """

    code = "N006"
    name = "sensor-angle-looks-like-degrees"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for sensor, owner in robot_sensors(ctx):
            for camera in sensor.findall("camera"):
                yield from self._camera(sensor, owner, camera)
            for tag, block in _scans(sensor):
                for axis in ("horizontal", "vertical"):
                    scan = block.find(f"scan/{axis}")
                    sides = [(side, *_number(scan, side)) for side in ("min_angle", "max_angle")]
                    slips = [(side, value, el) for side, value, el in sides
                             if value is not None and abs(value) > ONE_TURN]
                    if not slips:
                        continue
                    readings = ", ".join(f"{side} {written(value)}" for side, value, _ in slips)
                    meant = " ".join(f"<{side}>{_radians(value)}</{side}>" for side, value, _ in slips)
                    yield self.diagnostic(
                        f"{_label(sensor)}: {axis} {readings} rad {'lie' if len(slips) > 1 else 'lies'} "
                        "beyond a full turn"
                        + _as_degrees([value for _, value, _ in slips]),
                        span_of(slips[0][2]),
                        element=_where(sensor, owner, tag, "scan", axis),
                        help=f"write radians: {meant} (xacro: ${{radians(…)}})",
                        data={side: value for side, value, _ in slips},
                    )

    def _camera(self, sensor: Any, owner: str, camera: Any) -> Iterator[Diagnostic]:
        fov, element = _number(camera, "horizontal_fov")
        if fov is None or fov <= HALF_TURN:
            return
        where = _where(sensor, owner, "camera", "horizontal_fov")
        if fov > ONE_TURN:
            yield self.diagnostic(
                f"{_label(sensor)}: horizontal_fov {written(fov)} rad is beyond a full turn"
                + _as_degrees([fov]),
                span_of(element),
                element=where,
                help=f"write radians: <horizontal_fov>{_radians(fov)}</horizontal_fov> "
                "(xacro: ${radians(…)})",
                data={"value": fov, "meant": math.radians(fov)},
            )
            return
        wide = (sensor.get("type") or "") in WIDE_ANGLE_TYPES or camera.find("lens") is not None
        if wide:
            return
        yield self.diagnostic(
            f"{_label(sensor)}: horizontal_fov {written(fov)} rad ({math.degrees(fov):.0f}°) is a half turn "
            "or more, which only a fisheye lens sees; as degrees it would be "
            f"{written(fov)}° = {math.radians(fov):.4f} rad",
            span_of(element),
            element=where,
            help="a pinhole camera sees less than π rad; write radians, or give the camera a <lens> "
            "(gz-sim) or the wideanglecamera type (Gazebo Classic) for a real fisheye",
            data={"value": fov},
            severity=Severity.WARNING,
        )


def _as_degrees(values: list[float]) -> str:
    """``; it looks like degrees: 60° = 1.0472 rad`` (nothing for values no degree reaches)."""
    if any(abs(v) > 360.0 for v in values):
        return ""
    readings = ", ".join(f"{written(v)}° = {math.radians(v):.4f} rad" for v in values)
    return f"; {'they look' if len(values) > 1 else 'it looks'} like degrees: {readings}"


def _radians(value: float) -> str:
    return f"{math.radians(value):.4f}" if abs(value) <= 360.0 else "…"


@register
class SensorLimitsReversed(IntentRule):
    """A lidar's or camera's minimum is above its maximum, or a range starts below zero.

    ## What it does
    Reads every Gazebo sensor (SDF `<sensor>` under a link or joint, and
    `<sensor>` in a URDF's `<gazebo>` blocks) and reports:

    - a scan's `<min_angle>` above its `<max_angle>` (horizontal or vertical,
      in `<ray>` or `<lidar>`); an error, except on Gazebo Classic's CPU
      `ray` sensor, which sweeps the rays backwards and publishes a reversed
      scan with a negative `angle_increment` (a warning there). `min_angle`
      equal to `max_angle` is the single-ray idiom and stays quiet;
    - a range's `<min>` at or above its `<max>` (unless both are 0), or a
      negative `<min>`;
    - a camera's `<clip><near>` at or above its `<far>`.

    ## Why it matters
    Neither libsdformat nor the sensors check the order. A GPU lidar
    (`gpu_lidar`, `gpu_ray`) renders a field of view of `max_angle -
    min_angle`: negative, so the scan is empty or garbage (gz-rendering#384
    describes the min/max semantics). With `min` above `max` every return
    falls outside the range, so the scan is all `inf` and navigation and SLAM
    see no obstacle. A camera whose near plane is beyond its far plane draws
    nothing.

    ## Example
    ```xml
    <horizontal><samples>640</samples><min_angle>1.396263</min_angle><max_angle>-1.396263</max_angle></horizontal>
    <range><min>12</min><max>10.0</max></range>
    ```

    ## Fix
    Swap the two values (`min_angle` -1.396263, `max_angle` 1.396263; `min`
    0.08, `max` 12). To turn a scan round, turn the sensor's `<pose>`.
    """

    code = "N106"
    name = "sensor-limits-reversed"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for sensor, owner in robot_sensors(ctx):
            kind = sensor.get("type") or ""
            for tag, block in _scans(sensor):
                for axis in ("horizontal", "vertical"):
                    scan = block.find(f"scan/{axis}")
                    low, low_el = _number(scan, "min_angle")
                    high, _ = _number(scan, "max_angle")
                    if low is None or high is None or low <= high:
                        continue
                    sweeping = kind in SWEEPING_TYPES
                    effect = ("the rays sweep backwards: a reversed scan with a negative angle_increment"
                              if sweeping else "the lidar renders a negative field of view: an empty scan")
                    yield self.diagnostic(
                        f"{_label(sensor)}: {axis} min_angle {written(low)} is above max_angle "
                        f"{written(high)} rad; {effect}",
                        span_of(low_el),
                        element=_where(sensor, owner, tag, "scan", axis),
                        help=f"swap them: <min_angle>{written(high)}</min_angle> <max_angle>{written(low)}"
                        "</max_angle>; turn the sensor's <pose> to turn the scan round",
                        data={"min": low, "max": high, "axis": axis},
                        severity=Severity.WARNING if sweeping else None,
                    )
                yield from self._pair(sensor, owner, block.find("range"), (tag, "range"), ("min", "max"))
            for camera in sensor.findall("camera"):
                yield from self._pair(sensor, owner, camera.find("clip"), ("camera", "clip"), ("near", "far"))

    def _pair(self, sensor: Any, owner: str, parent: Any, path: tuple[str, str],
              names: tuple[str, str]) -> Iterator[Diagnostic]:
        """A ``min``/``max`` (or ``near``/``far``) pair in metres: in order and not negative."""
        low, low_el = _number(parent, names[0])
        high, _ = _number(parent, names[1])
        if low is None:
            return
        where = _where(sensor, owner, *path)
        if low < 0:
            yield self.diagnostic(
                f"{_label(sensor)}: {path[-1]} <{names[0]}> {written(low)} m is negative",
                span_of(low_el), element=where,
                help=f"a distance from the sensor is 0 or more: write <{names[0]}>{written(-low)}"
                f"</{names[0]}> or the sensor's real minimum",
                data={names[0]: low, names[1]: high},
            )
        elif high is not None and low >= high and not low == high == 0:
            yield self.diagnostic(
                f"{_label(sensor)}: {path[-1]} <{names[0]}> {written(low)} m is not below <{names[1]}> "
                f"{written(high)} m: "
                + ("the camera draws nothing" if names[0] == "near" else "no return can lie between them"),
                span_of(low_el), element=where,
                help=f"swap them, or write the sensor's real {names[0]} and {names[1]} (metres)",
                data={names[0]: low, names[1]: high},
            )
