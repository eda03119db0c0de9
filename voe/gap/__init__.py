"""The sim-to-real gap finder: locate where recordings leave the nominal simulation, name the
missing physics from a library of effects, fit it and verify on held-out episodes."""

from __future__ import annotations

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import Effect, EffectSum
from voe.gap.finder import GapConfig, GapFinder
from voe.gap.recordings import Episode, load_recordings
from voe.gap.run import diagnose
from voe.gap.scene import load_scene

__all__ = ["EFFECTS", "Effect", "EffectSum", "Episode", "GapConfig", "GapFinder", "diagnose", "load_recordings",
           "load_scene"]
