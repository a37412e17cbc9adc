"""The parts of a URDF ``<joint>`` after its ends and axis: type, limit, dynamics, mimic,
safety controller and calibration, read as urdfdom reads them (the first of a repeated element
wins) with every problem located. A mixin of :class:`~urdftool.parse.urdf.UrdfReader`, which
supplies the value reader, the span lookup, the attribute check and the report."""

from __future__ import annotations

from collections.abc import Callable

from lxml import etree

from urdftool.catalogue.suggest import did_you_mean
from urdftool.catalogue.syntax import UnknownJointType
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import Calibration, Dynamics, JointType, Limit, Mimic, SafetyController
from urdftool.parse.urdf_schema import SPHERICAL_NAMES, URDF_TYPES
from urdftool.parse.values import ValueReader
from urdftool.source import Span

#: URDF's joint types by name (a dict lookup: calling the enum costs a Python call of its metaclass)
_JOINT_TYPES = {name: JointType(name) for name in URDF_TYPES}


class JointParts:
    """Reads the optional parts of a joint; the reader supplies what these methods use."""

    values: ValueReader
    span: Callable[[etree._Element], Span | None]

    def _report(self, diagnostic: Diagnostic) -> None:
        raise NotImplementedError

    def _check_attributes(self, element: etree._Element, tag: str, where: str) -> None:
        raise NotImplementedError

    def _joint_type(self, element: etree._Element, where: str) -> JointType:
        raw = self.values.text(element, "type", where, required=True)
        if raw is None:
            return JointType.FIXED
        if raw in URDF_TYPES:
            return _JOINT_TYPES[raw]
        if raw in SPHERICAL_NAMES:
            self._report(
                UnknownJointType.diagnostic(
                    f"{where}: type \"{raw}\" is not a URDF joint type (a PyBullet extension, read "
                    "here as a ball joint; urdfdom, ROS and MuJoCo's importer reject it)",
                    self.values.attr_span(element, "type"),
                    element=where,
                    help="use SDF's ball joint, or three revolute joints",
                    data={"type": raw},
                    # A known extension that PyBullet honours: worth a warning, not an error.
                    severity=Severity.WARNING,
                )
            )
            return JointType.SPHERICAL
        self._report(
            UnknownJointType.diagnostic(
                f"{where}: unknown joint type \"{raw}\"" + did_you_mean(raw, URDF_TYPES)
                + " (read as fixed)",
                self.values.attr_span(element, "type"),
                element=where,
                data={"type": raw},
            )
        )
        return JointType.FIXED

    def _single(self, groups: dict[str, list[etree._Element]], tag: str, where: str) -> etree._Element | None:
        items = groups.get(tag)
        if not items:
            return None
        self._check_attributes(items[0], tag, f"{where}/{tag}")
        return items[0]

    def _limit(self, groups: dict[str, list[etree._Element]], where: str) -> Limit | None:
        el = self._single(groups, "limit", where)
        if el is None:
            return None
        here = f"{where}/limit"
        n = self.values.number
        span = self.span(el)
        lower = self.values.attr_span(el, "lower", span) if el.get("lower") is not None else None
        upper = self.values.attr_span(el, "upper", span) if el.get("upper") is not None else None
        return Limit(n(el, "lower", here), n(el, "upper", here), n(el, "effort", here),
                     n(el, "velocity", here), span, lower, upper)

    def _dynamics(self, groups: dict[str, list[etree._Element]], where: str) -> Dynamics | None:
        el = self._single(groups, "dynamics", where)
        if el is None:
            return None
        here = f"{where}/dynamics"
        damping = self.values.number(el, "damping", here)
        friction = self.values.number(el, "friction", here)
        return Dynamics(damping or 0.0, friction or 0.0, self.span(el))

    def _mimic(self, groups: dict[str, list[etree._Element]], where: str) -> Mimic | None:
        el = self._single(groups, "mimic", where)
        if el is None:
            return None
        here = f"{where}/mimic"
        target = self.values.text(el, "joint", here, required=True)
        if not target:
            return None
        multiplier = self.values.number(el, "multiplier", here)
        offset = self.values.number(el, "offset", here)
        return Mimic(target, 1.0 if multiplier is None else multiplier, offset or 0.0, self.span(el))

    def _safety(self, groups: dict[str, list[etree._Element]], where: str) -> SafetyController | None:
        el = self._single(groups, "safety_controller", where)
        if el is None:
            return None
        here = f"{where}/safety_controller"
        n = self.values.number
        k_velocity = n(el, "k_velocity", here, required=True)
        return SafetyController(
            k_velocity or 0.0,
            n(el, "k_position", here) or 0.0,
            n(el, "soft_lower_limit", here) or 0.0,
            n(el, "soft_upper_limit", here) or 0.0,
            self.span(el),
        )

    def _calibration(self, groups: dict[str, list[etree._Element]], where: str) -> Calibration | None:
        el = self._single(groups, "calibration", where)
        if el is None:
            return None
        here = f"{where}/calibration"
        return Calibration(self.values.number(el, "rising", here), self.values.number(el, "falling", here),
                           self.span(el))
