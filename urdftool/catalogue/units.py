"""Angles written in degrees where the format reads radians (N005), reported while a file is read.

The readers see each ``<origin rpy>`` and SDF ``<pose>`` as written, with the position of
the attribute or element; the model keeps only the resolved pose. So the check runs in the
readers (URDF ``<origin>`` and the SDF poses inside ``<gazebo>`` blocks; every ``<pose>`` of
an SDF document), with the one test below shared by both.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.source import Span

#: One turn (rad), plus the rounding of a written 2π (6.2832, 6.28319).
ONE_TURN = 2 * math.pi + 0.01
#: A degree value is written in whole or half degrees up to a full turn; beyond two turns
#: (4π rad) any value is read as degrees, since no generator writes a rotation that far.
DEGREE_STEP = 0.5
DEGREES_MAX = 360.0
TWO_TURNS = 4 * math.pi


def looks_like_degrees(value: float) -> bool:
    """An angle written as radians that only makes sense as degrees: beyond one turn (a rotation
    never needs more), at most 360, and in whole or half degrees or beyond two turns. Wrapped
    radians such as 6.597 (2π + π/10, a steering wheel's spoke in gazebo_models' Polaris)
    stay quiet."""
    size = abs(value)
    if size <= ONE_TURN or size > DEGREES_MAX:
        return False
    return size > TWO_TURNS or abs(value / DEGREE_STEP - round(value / DEGREE_STEP)) < 1e-9


def _text(value: float) -> str:
    return f"{value:.6g}"


@register
class AngleLooksLikeDegrees(Rule):
    """An `rpy` or `<pose>` angle is only plausible as degrees.

    ## What it does
    Reports a URDF `<origin rpy="…">` and an SDF `<pose>` (in an SDF file, and
    in the `<gazebo>` blocks of a URDF) whose roll, pitch or yaw lies beyond
    one turn (2π rad, with room for a rounded `6.2832`), at most 360, and is
    a whole or half number (`90`, `-45`, `22.5`) or beyond two turns. An SDF
    pose with `degrees="true"` or `rotation_format="quat_xyzw"` is read as
    such and not judged. Valid radians stay quiet: `3.14159`, `1.5708`,
    `-3.1416`, xacro's `${pi/2}`, small integers (`rpy="0 0 1"`), and radians
    just past a turn (`6.597`).

    ## Why it matters
    URDF and SDF read these angles in radians (urdfdom's `parseOrigin`; the
    SDFormat specification, unless `degrees="true"`). `rpy="0 0 90"` turns
    the frame by 90 rad, which is 116.6°: the joint, sensor, tool or visual
    points in a direction nobody chose, and nothing reports it. Users who
    write degrees ask for degree support (ros/urdfdom#124); sdformat added
    `degrees="true"` to poses for that reason (sdformat#589).

    ## Example
    ```xml
    <origin xyz="0 0 0.1" rpy="0 0 90"/>
    ```

    ## Fix
    Write radians (`rpy="0 0 1.5708"`, or `${radians(90)}` in xacro). In SDF
    1.9 and later, `<pose degrees="true">` reads the angles as degrees.
    Silence one element with `<!-- urdftool: ignore[angle-looks-like-degrees] -->`.
    """

    code = "N005"
    name = "angle-looks-like-degrees"
    family = Family.INTENT
    severity = Severity.WARNING
    since = "0.2.0"

    @classmethod
    def judge(
        cls, rpy: Sequence[float], span: Span | None, element: str, written: str, *, sdf: bool = False
    ) -> Diagnostic | None:
        """The finding on the angles *rpy* (rad as written) of *element*, or ``None`` when every
        angle is plausible as radians. *written* is the element as the user wrote it."""
        slips = [v for v in rpy if looks_like_degrees(v)]
        if not slips:
            return None
        meant = " ".join(_text(math.radians(v)) if looks_like_degrees(v) else _text(v) for v in rpy)
        readings = ", ".join(f"{_text(v)} → {math.radians(v):.4f} rad" for v in slips)
        worst = max(slips, key=abs)
        where = "rpy" if not sdf else "roll pitch yaw"
        fix = (f"write radians: roll pitch yaw {meant}, or <pose degrees=\"true\"> in SDF 1.9+" if sdf
               else f'write radians: rpy="{meant}" (xacro: ${{radians(…)}})')
        return cls.diagnostic(
            f"{written}: {where} angles look like degrees: {readings}",
            span,
            element=element,
            help=f"as radians {_text(worst)} turns the frame {fmt_turns(worst)}; {fix}",
            data={"rpy": list(rpy), "meant_rpy": [math.radians(v) if v in slips else v for v in rpy]},
        )


def fmt_turns(angle: float) -> str:
    """How far *angle* (rad) turns, in turns and the angle in (-180°, 180°] it lands at
    (90 rad: 14.3 turns, landing at 116.6°)."""
    landed = -((180.0 - math.degrees(angle)) % 360.0) + 180.0
    return f"{abs(angle) / (2 * math.pi):.1f} turns, landing at {landed:.1f}°"
