"""xacro (X): expansion failures and the packages it needs."""

from __future__ import annotations

from urdftool.diagnostics import Severity
from urdftool.rules.registry import Family, Rule, register


class _Xacro(Rule):
    family = Family.XACRO


@register
class XacroError(_Xacro):
    """xacro could not expand the file.

    ## What it does
    Reports a failed xacro expansion (an undefined property or macro, a wrong
    macro parameter, a Python error inside `${…}`, a missing include) at the
    innermost file being expanded and, where the offending name can be found
    there, its line.

    ## Why it matters
    Nothing downstream (robot_state_publisher, Gazebo, MoveIt) gets a robot;
    in ROS the failure surfaces at launch time with a bare traceback.

    ## Example
    ```xml
    <xacro:property name="wheel_radius" value="0.1"/>
    <cylinder radius="${wheel_raduis}" length="0.05"/>
    ```

    ## Fix
    Correct the name; pass missing arguments with `-a NAME:=VALUE`.
    """

    code = "X001"
    name = "xacro-error"
    severity = Severity.ERROR


@register
class PackageMissing(_Xacro):
    """`$(find PKG)` names a package urdftool cannot find.

    ## What it does
    Reports `$(find PKG)` substitutions whose package is not found by the
    resolver (`--package`, `--package-path`, `ROS_PACKAGE_PATH`,
    `AMENT_PREFIX_PATH`, the input file's ancestor folders), listing where it
    looked.

    ## Why it matters
    Without the package the file cannot be expanded at all.

    ## Example
    ```xml
    <xacro:include filename="$(find my_robot_description)/urdf/wheel.xacro"/>
    ```

    ## Fix
    Run with `--package my_robot_description=path/to/it` or
    `--package-path path/to/workspace/src`, or add a `package.xml` naming the
    package to its folder.
    """

    code = "X002"
    name = "package-not-found"
    severity = Severity.ERROR


@register
class IncludeNotAtPath(_Xacro):
    """An included file is not where the include says, but exists elsewhere in its package.

    ## What it does
    When `<xacro:include filename="$(find pkg)/x.xacro">` points at a missing
    file and exactly one file of that name exists inside the package, urdftool
    reads that file and reports where it found it.

    ## Why it matters
    ROS's xacro fails on such an include. It usually means the file was moved
    within the package (into `urdf/`, say) and the includer not updated.

    ## Example
    ```xml
    <xacro:include filename="$(find uos_common_urdf)/common.xacro"/>
    <!-- the file is at uos_common_urdf/urdf/common.xacro -->
    ```

    ## Fix
    Write the path where the file is:
    `$(find uos_common_urdf)/urdf/common.xacro`.
    """

    code = "X003"
    name = "include-not-at-path"
    severity = Severity.WARNING


@register
class XacroWarning(_Xacro):
    """xacro printed a warning while expanding the file.

    ## What it does
    Passes on xacro's own warnings (unknown attributes on xacro tags,
    redefined symbols, deprecated syntax) as findings instead of text on
    standard error.

    ## Why it matters
    They often point at a typo that changed the expansion, and in CI nobody
    reads standard error.

    ## Example
    ```xml
    <xacro:property name="pi" value="3.14"/>  <!-- redefines xacro's pi -->
    ```

    ## Fix
    Follow the warning's text.
    """

    code = "X004"
    name = "xacro-warning"
    severity = Severity.WARNING
