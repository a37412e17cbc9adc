"""ros2_control (G): findings the controllers YAML reader reports."""

from __future__ import annotations

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Severity


@register
class ControllersYamlInvalid(Rule):
    """The controllers YAML does not parse, or is not a ROS 2 parameter file.

    ## What it does
    Reports the line and column where PyYAML's safe loader gives up on the
    controllers file (`check --controllers FILE`, or the file a Gazebo
    ros2_control plugin's `<parameters>` names), or a file whose top level is
    not a mapping of node names to `ros__parameters`.

    ## Why it matters
    The controller manager cannot read its parameters: no controller is
    configured, and the launch fails with a parser error far from the file.

    ## Example
    ```yaml
    controller_manager:
      ros__parameters:
        arm_controller:
          type: joint_trajectory_controller/JointTrajectoryController
         joints: [a]        # indentation breaks the mapping
    ```

    ## Fix
    Correct the YAML at the reported line.
    """

    family = Family.GAZEBO
    code = "G200"
    name = "controllers-yaml-invalid"
    severity = Severity.ERROR
