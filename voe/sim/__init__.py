"""Simulation layer: scene specs, deterministic pymunk stepping, observation and rendering.

This is the only package that imports pymunk.
"""

from voe.sim.scene import (
    FEATURE_NAMES,
    Body,
    Occluder,
    Scene,
    Segment,
    SimConfig,
)

__all__ = ["FEATURE_NAMES", "Body", "Occluder", "Scene", "Segment", "SimConfig"]
