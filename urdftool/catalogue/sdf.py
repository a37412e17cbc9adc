"""SDF-only problems (S1xx): frames, includes and versions, reported while an SDF file is read."""

from __future__ import annotations

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Severity


class _Sdf(Rule):
    family = Family.SYNTAX


@register
class UnknownFrameReference(_Sdf):
    """A `relative_to`, `attached_to`, `expressed_in` or joint end names a frame that does not exist.

    ## What it does
    Checks every frame name an SDF model refers to: `<pose relative_to>`,
    `<frame attached_to>`, `<xyz expressed_in>`, and joint `<parent>`/`<child>`
    against the links, joints, frames and nested models in scope (plus
    `__model__` and `world`), with a did-you-mean suggestion.

    ## Why it matters
    libsdformat refuses the model ("relative_to name does not match a
    frame"), so Gazebo will not spawn it; older Gazebo versions ignored the
    name and placed the element somewhere else than the author meant.

    ## Example
    ```xml
    <link name="arm"><pose relative_to="shoulderr">0 0 0.3 0 0 0</pose></link>
    ```

    ## Fix
    Use the exact name of a link, joint, frame or nested model of the same model.
    """

    code = "S101"
    name = "unknown-frame-reference"
    severity = Severity.ERROR


@register
class FrameCycle(_Sdf):
    """Poses or frame attachments refer to each other in a cycle.

    ## What it does
    Follows each `relative_to` (and `attached_to`) from frame to frame and
    reports a chain that comes back to where it started, listing the frames
    on the cycle.

    ## Why it matters
    A pose defined through itself has no value: libsdformat refuses the
    model ("cycle detected in PoseRelativeTo graph"), and urdftool can only
    guess where the element is.

    ## Example
    ```xml
    <frame name="a"><pose relative_to="b"/></frame>
    <frame name="b"><pose relative_to="a"/></frame>
    ```

    ## Fix
    Express one of the poses relative to a link or to the model frame.
    """

    code = "S102"
    name = "frame-cycle"
    severity = Severity.ERROR


@register
class ModelIncludeNotFound(_Sdf):
    """An `<include>` names a model that cannot be found.

    ## What it does
    Resolves each `<include><uri>` (`model://NAME`, a path, or a file URI)
    through `--package NAME=DIR`, `--package-path`, `GZ_SIM_RESOURCE_PATH`,
    `IGN_GAZEBO_RESOURCE_PATH`, `GAZEBO_MODEL_PATH` and the folders around
    the file, and reports an include that leads to no model. `model://sun`
    and `model://ground_plane` are Gazebo's standard models and need no files.
    An `http(s)://` URI (a Gazebo Fuel model) is downloaded by Gazebo on first
    load: it gets an info saying the model is not checked, not an error.

    ## Why it matters
    Gazebo prints a warning and leaves the model out of the world, so a
    robot or an obstacle is silently missing from the simulation.

    ## Example
    ```xml
    <include><uri>model://my_robot</uri></include>
    ```

    ## Fix
    Add the model's parent folder with `--package-path` (or to
    `GZ_SIM_RESOURCE_PATH`), or correct the name.
    """

    code = "S103"
    name = "model-include-not-found"
    severity = Severity.ERROR


@register
class SdfVersion(_Sdf):
    """The `<sdf version>` is missing or outside the versions urdftool reads (1.4 to 1.11).

    ## What it does
    Reads the `version` attribute of `<sdf>`. A missing version is read with
    the newest rules (1.11); versions before 1.4 with 1.4's rules; versions
    after 1.11 with 1.11's.

    ## Why it matters
    Pose and axis defaults changed between versions (a joint axis is in the
    model frame in 1.4, in the joint frame from 1.5 on), so the same numbers
    mean a different robot under a different version.

    ## Example
    ```xml
    <sdf> <model name="cart"> … </model> </sdf>
    ```

    ## Fix
    ```xml
    <sdf version="1.7"> <model name="cart"> … </model> </sdf>
    ```
    """

    code = "S104"
    name = "sdf-version"
    severity = Severity.WARNING


@register
class SdfModelMissing(_Sdf):
    """An SDF file holds neither a model nor a world, or an included file holds no model.

    ## What it does
    Reports an `<sdf>` file with no `<model>`, `<world>`, `<light>` or
    `<actor>`, and an `<include>` whose file holds none of `<model>`,
    `<light>` and `<actor>`. A file that holds only a light or an actor is
    valid SDFormat (Gazebo's own `model://sun` is one) with nothing to check:
    an info. (A world with only lights and Gazebo's standard models is fine.)

    ## Why it matters
    There is nothing to check or convert; usually the wrong file was given
    (a `model.config`, a launch file) or the model is written elsewhere.
    libsdformat refuses such an include ("Failed to find top level <model> /
    <actor> / <light> for <include>").

    ## Example
    ```xml
    <sdf version="1.7"> <!-- the model moved to model_v2.sdf --> </sdf>
    ```

    ## Fix
    Point urdftool at the file that holds the `<model>`.
    """

    code = "S105"
    name = "sdf-model-missing"
    severity = Severity.ERROR


@register
class SdfNameCollision(_Sdf):
    """Two elements of one SDF scope share a name.

    ## What it does
    Checks the names of one scope: links, joints, `<frame>`s and nested
    models of a model share one namespace from SDFormat 1.7 on (they are all
    frames); models, frames and joints of a world likewise; visuals and
    collisions are unique within their link; worlds within the file. Before
    1.7 a link and a joint (or a world frame and a model) may share a name:
    that is a warning, as libsdformat gives.

    ## Why it matters
    libsdformat refuses the file ("Non-unique names", "already exists"), so
    Gazebo will not load it; a `relative_to` or `attached_to` naming the
    shared name could mean either element.

    ## Example
    ```xml
    <link name="tool"/>
    <joint name="tool" type="fixed"> … </joint>
    ```

    ## Fix
    Rename one of them, for example the joint to `tool_joint`.
    """

    code = "S106"
    name = "sdf-name-collision"
    severity = Severity.ERROR


@register
class SdfReservedName(_Sdf):
    """An SDF element is named `world` or `__…__`, names the spec reserves.

    ## What it does
    Reports links, joints, frames, models, visuals and collisions (SDFormat
    1.7 and later) named `world` or starting and ending with two
    underscores (`__model__`, `__root__`, ...).

    ## Why it matters
    These names are the spec's own frames: `world` is the world frame and
    `__model__` the model frame. libsdformat refuses the file ("is reserved").

    ## Example
    ```xml
    <link name="world"/>
    ```

    ## Fix
    Choose another name; to fix a link to the world, use a joint whose
    `<parent>` is `world`.
    """

    code = "S107"
    name = "sdf-reserved-name"
    severity = Severity.ERROR
