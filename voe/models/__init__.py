"""The model registry. Built-in registrations only; each model lives in its own module."""

from __future__ import annotations

from voe.registry import Registry

MODELS: Registry = Registry("model")

# references (no training; noise calibrated by maximum likelihood)
MODELS.register("framecopy-v1", "voe.models.framecopy:FrameCopy", observation="frames", learned=False)
MODELS.register("constvel-v1", "voe.models.constvel:ConstantVelocity", observation="states", learned=False)
MODELS.register("oracle-v1", "voe.models.oracle:PhysicsOracle", observation="states", learned=False)
# learned (torch)
MODELS.register("mlp-v1", "voe.models.mlp:FlatMLP", observation="states", learned=True)
MODELS.register("interaction-v1", "voe.models.interaction:InteractionNet", observation="states", learned=True)
MODELS.register("pixel-v1", "voe.models.pixel:PixelModel", observation="frames", learned=True)
