"""Planted defects: one mutation per statically visible catalogue class that has a rule.

Each entry of :data:`MUTATIONS` maps a class id of ``docs/defects/catalogue.yaml`` to a
function ``(text) -> (mutated_text, planted_line) | None``. It plants the class into the
text of a real robot file and says on which line of the mutant the defect now sits; it
returns None when the class does not apply to that model (no element to mutate).

Every mutation must change what a consumer does with the file (its docstring says how);
a mutation that a consumer would not notice would measure nothing and is not written.
Mutations edit the text of a single line where they can, so that the line numbers of the
rest of the file are unchanged; removals go through lxml and the planted line is looked up
again in the re-parsed mutant.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable

from lxml import etree

Mutant = tuple[str, int]
Mutation = Callable[[str], Mutant | None]

_PARSER = etree.XMLParser(remove_comments=False, resolve_entities=False, huge_tree=True)


def _tree(text: str) -> etree._Element | None:
    try:
        return etree.fromstring(text.encode(), _PARSER)
    except (etree.XMLSyntaxError, ValueError):
        return None


def _moving_joints(root: etree._Element) -> list[etree._Element]:
    return [j for j in root.findall("joint") if j.get("type") in ("revolute", "prismatic", "continuous")]


def _line_sub(
    text: str, line: int, pattern: str, repl: str | Callable[[re.Match[str]], str]
) -> Mutant | None:
    """*text* with the first match of *pattern* on 1-based *line* replaced, or None."""
    lines = text.split("\n")
    new, n = re.subn(pattern, repl, lines[line - 1], count=1)
    if not n or new == lines[line - 1]:
        return None
    lines[line - 1] = new
    return "\n".join(lines), line


def _first(
    candidates: list[etree._Element], edit: Callable[[etree._Element], Mutant | None]
) -> Mutant | None:
    for element in candidates:
        result = edit(element)
        if result is not None:
            return result
    return None


def _removed(
    text: str, root: etree._Element, victims: list[etree._Element], anchor_xpath: str
) -> Mutant | None:
    """The document without *victims*; the planted line is where *anchor_xpath* sits in the mutant."""
    for victim in victims:
        parent = victim.getparent()
        if parent is None:
            return None
        parent.remove(victim)
    mutated = etree.tostring(root, encoding="unicode")
    again = _tree(mutated)
    if again is None:
        return None
    found = again.xpath(anchor_xpath)
    if not found:
        return None
    return mutated, int(found[0].sourceline)


def _set_attr(text: str, element: etree._Element, attr: str, value: Callable[[str], str]) -> Mutant | None:
    old = element.get(attr)
    if old is None:
        return None
    pattern = rf'(\b{attr}\s*=\s*)(["\']){re.escape(old)}\2'
    return _line_sub(
        text,
        int(element.sourceline),
        pattern,
        lambda m: f"{m.group(1)}{m.group(2)}{value(old)}{m.group(2)}",
    )


def _num(value: str) -> float | None:
    try:
        return float(value)
    except ValueError:
        return None


# --- inertial ---------------------------------------------------------------------------


def missing_inertial(text: str) -> Mutant | None:
    """Delete the <inertial> of the child link of the last moving joint.

    A link with no inertial is given no mass: Gazebo drops it with its joint, Drake and
    Pinocchio treat the joint as driving nothing, PyBullet invents a 1 kg body."""
    root = _tree(text)
    if root is None:
        return None
    for joint in reversed(_moving_joints(root)):
        child = joint.find("child")
        name = child.get("link") if child is not None else None
        link = root.find(f"link[@name='{name}']") if name else None
        if link is not None and link.find("inertial") is not None:
            return _removed(text, root, [link.find("inertial")], f"/robot/link[@name='{name}']")
    return None


def link_without_inertial_dropped(text: str) -> Mutant | None:
    """Delete the <inertial> of the first moving link below the root.

    urdf2sdf and gz-sim drop a link without inertial together with its parent joint, so
    the chain below it vanishes from the simulation."""
    root = _tree(text)
    if root is None:
        return None
    for joint in _moving_joints(root):
        child = joint.find("child")
        name = child.get("link") if child is not None else None
        link = root.find(f"link[@name='{name}']") if name else None
        if link is not None and link.find("inertial") is not None:
            return _removed(text, root, [link.find("inertial")], f"/robot/link[@name='{name}']")
    return None


def _inertias(root: etree._Element) -> list[etree._Element]:
    """Inertia elements of links that head a rigid body (the root, or the child of a moving
    joint): a welded link's own tensor is lumped into its body by every consumer, so a
    mistake there may change nothing anyone computes and would not count as a defect."""
    welded = {
        child.get("link")
        for joint in root.findall("joint")
        if joint.get("type") == "fixed" and (child := joint.find("child")) is not None
    }
    out = []
    for link in root.findall("link"):
        if link.get("name") in welded:
            continue
        inertia = link.find("inertial/inertia")
        mass = link.find("inertial/mass")
        if inertia is None or mass is None or (_num(mass.get("value", "")) or 0.0) <= 0:
            continue
        values = [_num(inertia.get(k, "")) for k in ("ixx", "iyy", "izz")]
        if all(v is not None and v > 0 for v in values) and link.find("collision") is not None:
            out.append(inertia)
    return out


def _scaled_inertia(text: str, factor: float) -> Mutant | None:
    root = _tree(text)
    if root is None:
        return None

    def edit(inertia: etree._Element) -> Mutant | None:
        line = int(inertia.sourceline)
        lines = text.split("\n")

        def scale(m: re.Match[str]) -> str:
            return f'{m.group(1)}"{float(m.group(3)) * factor:.6g}"'

        new = re.sub(r'(\bi(xx|yy|zz|xy|xz|yz)\s*=\s*)"([^"]+)"', scale, lines[line - 1])
        if new.count("=") < 3 or new == lines[line - 1] or len(re.findall(r"\bi(?:xx|yy|zz)\s*=", new)) < 3:
            return None
        lines[line - 1] = new
        return "\n".join(lines), line

    return _first(_inertias(root), edit)


def cad_export_inertia_wrong(text: str) -> Mutant | None:
    """Multiply one link's inertia tensor by 1e6, as a CAD exporter writing kg·mm² does.

    The body resists rotation a million times more than its shape says: joints barely move
    under their controllers and contacts behave as with a flywheel."""
    return _scaled_inertia(text, 1e6)


def inertia_implausible(text: str) -> Mutant | None:
    """Divide one link's inertia tensor by 1e4 (a copy-pasted tiny placeholder).

    A link far lighter in rotation than its geometry makes the mass matrix stiff: the
    simulation jitters or explodes at usual time steps."""
    return _scaled_inertia(text, 1e-4)


def inertia_physically_invalid(text: str) -> Mutant | None:
    """Negate izz of one link's inertia tensor (a sign lost in a hand edit or an exporter).

    The tensor is not positive definite, so no rigid body has it: Drake and MuJoCo refuse
    the model, Bullet and ODE integrate a body that gains energy."""
    root = _tree(text)
    if root is None:
        return None

    def edit(inertia: etree._Element) -> Mutant | None:
        return _set_attr(text, inertia, "izz", lambda v: f"{-float(v):.6g}")

    return _first(_inertias(root), edit)


def negative_or_zero_mass(text: str) -> Mutant | None:
    """Negate the mass of a moving link.

    A negative mass makes the equations of motion meaningless: loaders reject it or the body
    accelerates against the applied force."""
    root = _tree(text)
    if root is None:
        return None
    masses = [
        link.find("inertial/mass")
        for link in root.findall("link")
        if link.find("inertial/mass") is not None
    ]
    return _first(
        [m for m in masses if (_num(m.get("value", "")) or 0) > 0],
        lambda m: _set_attr(text, m, "value", lambda v: f"{-float(v):.6g}"),
    )


def extreme_mass_ratio(text: str) -> Mutant | None:
    """Multiply the mass and the inertia of the heaviest link by 1e4 (grams read as kilograms).

    Mass ratios of 1e5 and more make the solver of every simulator lose joint constraints:
    the light links drift or tear off."""
    root = _tree(text)
    if root is None:
        return None
    inertias = _inertias(root)
    if not inertias:
        return None
    links = sorted(
        (i.getparent().getparent() for i in inertias),
        key=lambda link: -(_num(link.find("inertial/mass").get("value", "")) or 0),
    )
    for link in links:
        mass = link.find("inertial/mass")
        result = _set_attr(text, mass, "value", lambda v: f"{float(v) * 1e4:.6g}")
        if result is not None:
            return result
    return None


def root_link_inertia_kdl(text: str) -> Mutant | None:
    """Give the root link an <inertial> when it has none (a mobile base's mass put on the root).

    KDL (robot_state_publisher, gazebo_ros, MoveIt's KDL solvers) ignores the inertia of the
    root link and warns: the mass the author wrote never reaches KDL's dynamics."""
    root = _tree(text)
    if root is None:
        return None
    children = {c.get("link") for c in root.iter("child")}
    roots = [link for link in root.findall("link") if link.get("name") not in children]
    if len(roots) != 1 or roots[0].find("inertial") is not None:
        return None
    link = roots[0]
    inertial = (
        '<inertial><mass value="2.0"/>'
        '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'
    )
    line = int(link.sourceline)
    lines = text.split("\n")
    if re.search(r"<link\b[^>]*/>", lines[line - 1]) and len(link) == 0:
        lines[line - 1] = re.sub(r"(<link\b[^>]*?)\s*/>", lambda m: f"{m.group(1)}>{inertial}</link>",
                                 lines[line - 1], count=1)
    elif re.search(r"<link\b[^>]*>\s*$", lines[line - 1]):
        lines[line - 1] += inertial
    else:
        return None
    return "\n".join(lines), line


# --- joints ------------------------------------------------------------------------------


def _limits(
    root: etree._Element, types: tuple[str, ...] = ("revolute", "prismatic")
) -> list[etree._Element]:
    return [
        j.find("limit")
        for j in root.findall("joint")
        if j.get("type") in types and j.find("limit") is not None
    ]


def zero_effort_limit(text: str) -> Mutant | None:
    """Set effort="0" on a revolute or prismatic joint.

    ros2_control and Gazebo clamp the command to the effort limit: the joint never moves."""
    root = _tree(text)
    if root is None:
        return None
    return _first(
        [lim for lim in _limits(root) if (_num(lim.get("effort", "")) or 0) > 0],
        lambda lim: _set_attr(text, lim, "effort", lambda _: "0"),
    )


def missing_joint_limit(text: str) -> Mutant | None:
    """Delete the <limit> of a revolute joint.

    The URDF parser rejects a revolute or prismatic joint without limits; where it is
    tolerated the range collapses to [0, 0] and the joint is locked."""
    root = _tree(text)
    if root is None:
        return None
    for joint in root.findall("joint"):
        if joint.get("type") in ("revolute", "prismatic") and joint.find("limit") is not None:
            return _removed(text, root, [joint.find("limit")], f"/robot/joint[@name='{joint.get('name')}']")
    return None


def limit_missing_effort_or_velocity(text: str) -> Mutant | None:
    """Remove the velocity attribute of a joint limit.

    urdfdom rejects the model ("velocity attribute missing"); others read it as 0 and the
    joint cannot move."""
    root = _tree(text)
    if root is None:
        return None

    def edit(lim: etree._Element) -> Mutant | None:
        return _line_sub(text, int(lim.sourceline), r'\s+velocity\s*=\s*"[^"]*"', "")

    return _first(_limits(root), edit)


def continuous_with_limits(text: str) -> Mutant | None:
    """Turn a limited revolute joint into a continuous one, keeping its lower/upper.

    Consumers disagree: urdfdom drops the range, Drake and some controllers enforce it, so
    the joint wraps in one tool and stops in another."""
    root = _tree(text)
    if root is None:
        return None

    def edit(joint: etree._Element) -> Mutant | None:
        lim = joint.find("limit")
        if lim is None or lim.get("lower") is None or lim.get("upper") is None:
            return None
        if (_num(lim.get("upper", "")) or 0) - (_num(lim.get("lower", "")) or 0) <= 0:
            return None
        return _set_attr(text, joint, "type", lambda _: "continuous")

    return _first([j for j in root.findall("joint") if j.get("type") == "revolute"], edit)


# --- structure ---------------------------------------------------------------------------


def unknown_link_reference(text: str) -> Mutant | None:
    """Misspell the child link of a joint.

    urdfdom refuses the model ("child link not found"); nothing loads."""
    root = _tree(text)
    if root is None:
        return None
    children = [j.find("child") for j in root.findall("joint") if j.find("child") is not None]
    return _first(children, lambda c: _set_attr(text, c, "link", lambda v: v + "_lnk"))


def multiple_roots(text: str) -> Mutant | None:
    """Add a link no joint connects to.

    urdfdom refuses a second root; Gazebo and MoveIt never load the model."""
    root = _tree(text)
    if root is None or root.find("link") is None:
        return None
    line = int(root.find("link").sourceline)
    lines = text.split("\n")
    lines[line - 1] = '<link name="planted_orphan"/>' + lines[line - 1]
    return "\n".join(lines), line


def duplicate_link_name(text: str) -> Mutant | None:
    """Declare a second, empty link with the name of an existing leaf link.

    urdfdom rejects duplicate link names; other readers keep one of the two silently."""
    root = _tree(text)
    if root is None:
        return None
    links = root.findall("link")
    if len(links) < 2:
        return None
    link = links[-1]
    line = int(link.sourceline)
    lines = text.split("\n")
    lines[line - 1] = f'<link name="{link.get("name")}"/>' + lines[line - 1]
    return "\n".join(lines), line


def closed_chain_in_urdf(text: str) -> Mutant | None:
    """Add a fixed joint to a link that already has a parent (a loop).

    URDF is a tree: urdfdom rejects a link with two parents, so the model does not load."""
    root = _tree(text)
    if root is None:
        return None
    joints = [
        j for j in root.findall("joint") if j.find("child") is not None and j.find("parent") is not None
    ]
    if len(joints) < 2:
        return None
    first, last = joints[0], joints[-1]
    parent = first.find("parent").get("link")
    child = last.find("child").get("link")
    if parent == child or last.find("parent").get("link") == parent:
        return None
    line = int(last.sourceline)
    lines = text.split("\n")
    lines[line - 1] = (
        f'<joint name="planted_loop" type="fixed"><parent link="{parent}"/>'
        f'<child link="{child}"/></joint>' + lines[line - 1]
    )
    return "\n".join(lines), line


def unknown_element(text: str) -> Mutant | None:
    """Misspell the <origin> of a visual as <orgin>.

    Parsers skip unknown elements: the visual sits at the link frame and the robot looks
    wrong in RViz and Gazebo without any message."""
    root = _tree(text)
    if root is None:
        return None
    origins = [o for o in root.iter("origin") if o.getparent().tag == "visual"]

    def edit(origin: etree._Element) -> Mutant | None:
        return _line_sub(text, int(origin.sourceline), r"<origin\b", "<orgin")

    return _first(origins, edit)


def missing_geometry_element(text: str) -> Mutant | None:
    """Delete the <geometry> of a collision.

    urdfdom refuses a collision without geometry; the model does not load."""
    root = _tree(text)
    if root is None:
        return None
    for collision in root.iter("collision"):
        geometry = collision.find("geometry")
        if geometry is not None:
            link = collision.getparent()
            return _removed(
                text, root, [geometry], f"/robot/link[@name='{link.get('name')}']/collision[not(geometry)]"
            )
    return None


def no_collision_geometry(text: str) -> Mutant | None:
    """Delete every <collision> of the model.

    Nothing collides: the robot falls through the floor in every simulator and MoveIt plans
    through obstacles."""
    root = _tree(text)
    if root is None:
        return None
    collisions = list(root.iter("collision"))
    if not collisions:
        return None
    return _removed(text, root, collisions, "/robot")


def xml_malformed(text: str) -> Mutant | None:
    """Write the name attribute of a joint twice.

    Every XML parser rejects the file: nothing loads."""
    root = _tree(text)
    if root is None:
        return None
    return _first(
        root.findall("joint"),
        lambda j: _line_sub(text, int(j.sourceline), r"(<joint\b)", r'\1 name="planted"'),
    )


# --- meshes ------------------------------------------------------------------------------


def _meshes(root: etree._Element) -> list[etree._Element]:
    return [m for m in root.iter("mesh") if m.get("filename")]


def mesh_uri_unresolvable(text: str) -> Mutant | None:
    """Misspell the package of a package:// mesh URI.

    Gazebo and RViz cannot find the package: the link is invisible or the spawn fails."""
    root = _tree(text)
    if root is None:
        return None

    def edit(mesh: etree._Element) -> Mutant | None:
        if not mesh.get("filename", "").startswith("package://"):
            return None
        return _line_sub(text, int(mesh.sourceline), r"package://([^/\"']+)/", r"package://\1_typo/")

    return _first(_meshes(root), edit)


def _rescaled(text: str, mesh: etree._Element, factor: float) -> Mutant | None:
    """*mesh*'s ``scale`` multiplied by *factor* (written when the mesh has none)."""
    scale = mesh.get("scale")
    if scale is None:
        written = " ".join([f"{factor:g}"] * 3)
        return _line_sub(text, int(mesh.sourceline), r"<mesh\b", f'<mesh scale="{written}"')
    values = [_num(v) for v in scale.split()]
    if len(values) != 3 or any(v is None for v in values):
        return None
    return _set_attr(text, mesh, "scale", lambda _: " ".join(f"{(v or 0) * factor:g}" for v in values))


def mesh_units_wrong(text: str) -> Mutant | None:
    """Multiply a mesh's scale by 1000 (millimetres read as metres, or the reverse fix doubled).

    The link's visual and collision are a thousand times too large: the robot collides with
    everything and explodes at the first step."""
    root = _tree(text)
    if root is None:
        return None

    def edit(mesh: etree._Element) -> Mutant | None:
        if mesh.getparent().getparent().tag != "collision":
            return None
        return _rescaled(text, mesh, 1000)

    return _first(_meshes(root), edit)


def mesh_format_not_accepted(text: str) -> Mutant | None:
    """Point a mesh at a .blend file instead of its exported .stl/.dae/.obj.

    No URDF consumer reads Blender files: the link has no visual or collision."""
    root = _tree(text)
    if root is None:
        return None

    def edit(mesh: etree._Element) -> Mutant | None:
        return _line_sub(text, int(mesh.sourceline), r"\.(stl|STL|dae|DAE|obj|OBJ)([\"'])", r".blend\2")

    return _first(_meshes(root), edit)


def revolute_limits_in_degrees(text: str) -> Mutant | None:
    """Write one revolute joint's limits in degrees as a datasheet gives them (90 for pi/2,
    rounded to 5 degrees).

    Every consumer reads radians: the joint may turn 14 full turns, straight through the
    robot's own body, and a position controller's goal of "90" winds it up forever."""
    root = _tree(text)
    if root is None:
        return None

    def edit(lim: etree._Element) -> Mutant | None:
        lower, upper = _num(lim.get("lower", "")), _num(lim.get("upper", ""))
        if lower is None or upper is None or not (0.5 < upper - lower <= 2 * math.pi):
            return None
        if max(abs(lower), abs(upper)) > math.pi + 1e-6:
            return None
        degrees = lambda v: f"{5 * round(math.degrees(float(v)) / 5):d}"  # noqa: E731
        first = _set_attr(text, lim, "lower", degrees)
        if first is None:
            return None
        second = _set_attr(first[0], lim, "upper", degrees)
        return second

    return _first(_limits(root, ("revolute",)), edit)


def transmission_hardware_interface(text: str) -> Mutant | None:
    """Move a ros_control transmission joint's <hardwareInterface> away (left only on the actuator).

    ros_control's transmission parser skips the joint ("No valid hardware interface element
    found in joint"): gazebo_ros_control never exports it and its controller waits forever."""
    root = _tree(text)
    if root is None or root.find("ros2_control") is not None:
        return None
    for transmission in root.findall("transmission"):
        kind = transmission.find("type")
        if kind is None or not (kind.text or "").strip().startswith("transmission_interface/"):
            continue
        for joint in transmission.findall("joint"):
            interfaces = joint.findall("hardwareInterface")
            name = joint.get("name")
            if interfaces and name and '"' not in name:
                return _removed(
                    text, root, interfaces, f'//transmission/joint[@name="{name}"]'
                )
    return None


def collision_visual_mismatch(text: str) -> Mutant | None:
    """Scale one collision mesh by 10 while its link's visual uses the same mesh unscaled
    (a CAD export in centimetres for the collision only).

    The robot looks right in RViz but collides with a body ten times its size: it hovers on
    its collision shapes, grippers cannot close on anything."""
    root = _tree(text)
    if root is None:
        return None

    def edit(mesh: etree._Element) -> Mutant | None:
        collision = mesh.getparent().getparent()
        link = collision.getparent()
        if collision.tag != "collision" or link is None or link.tag != "link":
            return None
        twins = [
            v for v in link.findall("visual/geometry/mesh")
            if v.get("filename") == mesh.get("filename") and v.get("scale") == mesh.get("scale")
        ]
        if not twins:
            return None
        return _rescaled(text, mesh, 10)

    return _first(_meshes(root), edit)


#: class id -> mutation; the classes with a rule and no mutation yet are listed in NOT_PLANTED
MUTATIONS: dict[str, Mutation] = {
    "link-without-inertial-dropped": link_without_inertial_dropped,
    "missing-inertial": missing_inertial,
    "root-link-inertia-kdl": root_link_inertia_kdl,
    "cad-export-inertia-wrong": cad_export_inertia_wrong,
    "inertia-implausible": inertia_implausible,
    "inertia-physically-invalid": inertia_physically_invalid,
    "negative-or-zero-mass": negative_or_zero_mass,
    "extreme-mass-ratio": extreme_mass_ratio,
    "zero-effort-limit": zero_effort_limit,
    "missing-joint-limit": missing_joint_limit,
    "limit-missing-effort-or-velocity": limit_missing_effort_or_velocity,
    "continuous-with-limits": continuous_with_limits,
    "unknown-link-reference": unknown_link_reference,
    "multiple-roots": multiple_roots,
    "duplicate-link-name": duplicate_link_name,
    "closed-chain-in-urdf": closed_chain_in_urdf,
    "unknown-element": unknown_element,
    "missing-geometry-element": missing_geometry_element,
    "no-collision-geometry": no_collision_geometry,
    "xml-malformed": xml_malformed,
    "mesh-uri-unresolvable": mesh_uri_unresolvable,
    "mesh-units-wrong": mesh_units_wrong,
    "revolute-limits-in-degrees": revolute_limits_in_degrees,
    "transmission-hardware-interface": transmission_hardware_interface,
    "collision-visual-mismatch": collision_visual_mismatch,
}

#: classes with a rule that the harness does not plant yet, and why
NOT_PLANTED: dict[str, str] = {
    "mesh-format-not-accepted": (
        "M004 reads the mesh file's header; planting needs a mesh file of a refused format, "
        "which a mutation of the robot's text cannot create (mesh_format_not_accepted is kept "
        "for when the harness writes meshes)"
    ),
    "fixed-joint-lumping-loses-frame": "needs a Gazebo plugin naming a joint; no URDF of the corpus has one",
    "drive-geometry-mismatch": (
        "needs a diff-drive plugin; only the xacro seeds have one (xacro planting not built yet)"
    ),
    "xacro-expansion-error": "xacro only; xacro planting not built yet",
    "macros-only-description": "xacro only; xacro planting not built yet",
    "overlapping-collision-geometry": "caught by the simulation rule R002; too slow for the harness",
    "initial-penetration": "caught by the simulation rule R002; too slow for the harness",
    "low-inertia-needs-armature": "caught by the dynamics rule D002; not planted yet",
    "plugin-frame-not-in-model": "needs a gazebo_ros plugin naming a frame; no URDF of the corpus has one",
    "base-footprint-not-on-ground": (
        "needs a base_footprint joint; N102 checks its horizontal offset and tilt, and the corpus "
        "has too few mobile bases with one (xacro planting would add the seeds')"
    ),
    "srdf-unknown-link": "the error is in the SRDF; SRDF planting not built yet",
    "srdf-groups-inconsistent": "the error is in the SRDF; SRDF planting not built yet",
    "controller-joint-not-in-urdf": (
        "the error is in the controllers YAML; YAML planting not built yet"
    ),
    "ros2-control-block-misconfigured": "needs a <ros2_control> block; no URDF of the corpus has one",
    "mimic-joint-sim-unsupported": "reported with check --target; the harness checks without a target",
    "frame-link-without-inertial": "reported with check --target; the harness checks without a target",
    "camera-optical-frame-missing": (
        "needs a Gazebo camera plugin stamping an optical frame; the corpus has none (racecar's "
        "stamps its body frame and is reported on the twin)"
    ),
    "mesh-filename-case": (
        "needs a mesh file on disk in the other case, which a mutation of the text cannot create"
    ),
}
