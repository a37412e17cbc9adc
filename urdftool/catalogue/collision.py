"""The rule ``convert --collision`` reports: each collision mesh it replaced, with the volume error."""

from __future__ import annotations

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Severity


@register
class CollisionSimplified(Rule):
    """`convert --collision` replaced a collision mesh; the note gives the volume error.

    ## What it does
    For each collision mesh that `convert --collision hull|decompose|primitives`
    replaced, says what it became (its convex hull, N convex parts, a box,
    cylinder, sphere or capsule) and how far the new volume is from the
    mesh's (the union of the parts, for a decomposition). A capsule is
    written as a cylinder and two spheres where the target has no capsule
    (URDF, SDF 1.7); the note says so. Visual meshes are never changed.

    ## Why it matters
    A simplification trades accuracy for speed: a hull fills a bowl, a
    primitive rounds a corner. The volume error says how much shape was
    traded, so a large one can be reviewed before a simulation depends on it.

    ## Example
    ```
    link 'tray': collision mesh 'tray.obj' became 6 convex parts; volume error -1.1 %
    ```

    ## Fix
    Nothing when the error is acceptable. Otherwise use `decompose` with a
    lower `--collision-threshold` or a larger `--collision-max-parts`, or
    another mode.
    """

    code = "C006"
    name = "collision-simplified"
    family = Family.CONVERSION
    severity = Severity.INFO
