"""Training worlds: ordinary-physics clips on the probes' stage, with counterfactual options."""

from voe.world.generate import COUNTERFACTUALS, generate_world

__all__ = ["COUNTERFACTUALS", "generate_world"]
