"""Gazebo and ROS extensions (G): plugins, transmissions and SDF-isms inside URDF."""

from __future__ import annotations
