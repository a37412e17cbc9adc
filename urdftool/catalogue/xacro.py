"""xacro (X): expansion failures and the packages it needs."""

from __future__ import annotations

from typing import TYPE_CHECKING

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Severity

if TYPE_CHECKING:
    from urdftool.model import Robot


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
    reads that file and reports where it found it. An include written for the
    installed package is not reported: in ROS 2 `$(find pkg)` is `share/pkg`,
    and the package's `CMakeLists.txt` rule
    `install(DIRECTORY description/ros2_control DESTINATION share/${PROJECT_NAME})`
    puts the file at `$(find pkg)/ros2_control/…`.

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


@register
class MacrosOnly(_Xacro):
    """The xacro file is a macro library: it defines macros and builds no robot.

    ## What it does
    Recognises a xacro file whose expansion has no links and no joints, that
    writes no `<link>` or `<joint>` outside its macro bodies, and that defines
    (itself or through its includes) at least one `<xacro:macro>`. It is
    reported once, as information, instead of `robot-name-missing` and
    `empty-robot`, which would be false alarms for such a file.

    ## Why it matters
    Sensor and inertia macro files (a Kinect, a laser scanner, `common.xacro`)
    are meant to be included by a robot, not loaded on their own. Checking
    them alone says nothing about a robot; the macros are checked where a
    robot calls them.

    ## Example
    ```xml
    <robot xmlns:xacro="http://ros.org/wiki/xacro">
      <xacro:macro name="sick_lms100" params="name parent *origin">
        <link name="${name}_link"/> ...
      </xacro:macro>
    </robot>
    ```

    ## Fix
    Nothing to fix. Check the robot that includes the library; `urdftool check`
    on a folder does so and skips libraries that another file includes.
    """

    code = "X005"
    name = "macros-only"
    severity = Severity.INFO


def is_macro_library(robot: Robot) -> bool:
    """True when *robot* was read from a xacro macro library (see :class:`MacrosOnly`)."""
    return any(d.code == MacrosOnly.code for d in robot.diagnostics)


@register
class XacroInUrdf(_Xacro):
    """A `.urdf` file uses xacro; urdftool expands it with xacro.

    ## What it does
    Reports a file named `.urdf` that contains live xacro elements
    (`<xacro:arg>`, `<xacro:property>`, `<xacro:include>`, macro calls), at the
    first of them, and reads the file through xacro, as ROS launch files that
    run `xacro` on it do. Commented-out xacro and a merely declared
    `xmlns:xacro` do not count, nor does a file whose name says it is xacro
    (`robot.xacro.urdf`, as gz_ros2_control's demos name theirs). Such a file
    is read through xacro, without a finding, also when it uses xacro only
    through substitutions in attributes or text (`$(find pkg)` in a plugin's
    `<parameters>`), so that the file those name is checked.

    ## Why it matters
    URDF loaders that read the file directly (urdfdom's `check_urdf`,
    PyBullet, MuJoCo, Pinocchio) see `${…}` and `$(…)` as literal text: link
    names, numbers and mesh paths are garbage, and the robot differs from the
    one ROS publishes.

    ## Example
    ```xml
    <!-- turtlebot3_burger.urdf -->
    <robot name="turtlebot3_burger" xmlns:xacro="http://ros.org/wiki/xacro">
      <xacro:arg name="namespace" default=""/>
      <link name="$(arg namespace)base_link"/>
    ```

    ## Fix
    Rename the file to `.urdf.xacro`, or ship the expanded URDF
    (`xacro robot.urdf.xacro > robot.urdf`) under the `.urdf` name.
    """

    code = "X006"
    name = "xacro-in-urdf"
    severity = Severity.WARNING


@register
class MisspeltXacroArgument(_Xacro):
    """A xacro argument was given that no file uses, and one of a close name is.

    ## What it does
    Compares each argument given (`-a NAME:=VALUE`, `xacro-args` in the
    settings, `xacro_args=` in the API) with the arguments the files read
    declare (`<xacro:arg name=…>`) or use (`$(arg NAME)`). An argument none
    of them knows, with a close name among them, is reported at the
    declaration of the close one. Arguments with no close name are left
    alone: one setting given to many files is not a typo.

    ## Why it matters
    xacro ignores an argument no file uses, so the one meant keeps its
    default and the robot silently differs from the one asked for: with
    `-a gazbo:=true`, franka_description builds the Panda without a single
    `<inertial>`.

    ## Example
    ```xml
    <!-- urdftool check panda.urdf.xacro -a gazbo:=true -->
    <xacro:arg name="gazebo" default="false"/>
    ```

    ## Fix
    Spell the argument as the file declares it (`-a gazebo:=true`).
    """

    code = "X007"
    name = "misspelt-xacro-argument"
    severity = Severity.WARNING
    since = "0.2.0"


#: Reader warnings that mean the robot built is not the one asked for (an argument xacro ignored)
#: or not the one ROS's xacro builds (an include read from where it was found, not where it is
#: written). Commands that print no findings of their own, `convert` and `info`, print these on
#: stderr: exporting is where a typo costs most.
CHANGES_THE_ROBOT = frozenset({IncludeNotAtPath.code, MisspeltXacroArgument.code})
