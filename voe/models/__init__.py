"""The model registry. Built-in registrations only; each model lives in its own module."""

from __future__ import annotations

from voe.registry import Registry

MODELS: Registry = Registry("model")

# references (no training; noise calibrated by maximum likelihood)
MODELS.register("framecopy-v1", "voe.models.framecopy:FrameCopy", observation="frames", learned=False,
                summary="frame copy, calibrated pixel-flip probability (binarised pixels)")
MODELS.register("constvel-v1", "voe.models.constvel:ConstantVelocity", observation="states", learned=False,
                summary="constant velocity, calibrated Gaussian, presence and per-slot memory")
MODELS.register("oracle-v1", "voe.models.oracle:PhysicsOracle", observation="states", learned=False,
                summary="pymunk re-simulation from the observed state with calibrated noise (upper bound)")
# learned (torch)
MODELS.register("mlp-v2", "voe.models.mlp:FlatMLP", observation="states", learned=True,
                summary="flat Gaussian MLP over a window of k observed frames of all slots; no object "
                        "structure, no memory")
MODELS.register("interaction-v2", "voe.models.interaction:InteractionNet", observation="states", learned=True,
                summary="object-centric interaction network; rolls hidden objects forward on its own predictions "
                        "through a gated built-in Euler step")
MODELS.register("interaction-v3", "voe.models.interaction:InteractionNetV3", observation="states", learned=True,
                summary="object-centric interaction network; rolls hidden objects forward through a learned "
                        "linear integrator (nothing physical built in)")
MODELS.register("pixel-v1", "voe.models.pixel:PixelModel", observation="frames", learned=True,
                summary="conv predictor with ConvGRU memory, per-pixel Bernoulli")
