"""Built-in gap effects, registered lazily by name (this file holds registrations only)."""

from __future__ import annotations

from voe.registry import Registry

EFFECTS: Registry = Registry("gap effect")

EFFECTS.register("linear_drag", "voe.gap.effects.linear_drag:LinearDrag")
EFFECTS.register("quadratic_drag", "voe.gap.effects.quadratic_drag:QuadraticDrag")
EFFECTS.register("rolling_resistance", "voe.gap.effects.rolling_resistance:RollingResistance")
EFFECTS.register("constant_acceleration", "voe.gap.effects.constant_acceleration:ConstantAcceleration")
EFFECTS.register("point_attractor", "voe.gap.effects.point_attractor:PointAttractor")
EFFECTS.register("restitution", "voe.gap.effects.restitution:Restitution")
EFFECTS.register("friction", "voe.gap.effects.friction:Friction")
EFFECTS.register("angular_damping", "voe.gap.effects.angular_damping:AngularDamping")
EFFECTS.register("spring_anchor", "voe.gap.effects.spring_anchor:SpringAnchor")
EFFECTS.register("mass", "voe.gap.effects.mass:Mass")
EFFECTS.register("joint_damping", "voe.gap.effects.joint:JointDamping")
EFFECTS.register("joint_friction", "voe.gap.effects.joint:JointFriction")
EFFECTS.register("friction_region", "voe.gap.effects.region:FrictionRegion")
EFFECTS.register("rolling_resistance_region", "voe.gap.effects.region:RollingResistanceRegion")
EFFECTS.register("restitution_region", "voe.gap.effects.restitution_region:RestitutionRegion")
EFFECTS.register("none", "voe.gap.effects.none:NoEffect")

__all__ = ["EFFECTS"]
