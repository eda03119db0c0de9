"""One-line descriptions of what each concept tests, for readers who never ran voe.

Why not import ``voe.concepts``: reports never import the simulator. The text comes from the
``**Concept.**`` paragraph of ``probes/<name>/README.md`` when the source tree has one, otherwise
from the short mapping below.
"""

from __future__ import annotations

import re
from pathlib import Path

PROBES_DIR = Path(__file__).resolve().parents[2] / "probes"

DESCRIPTIONS: dict[str, str] = {
    "permanence": "Objects keep existing when out of sight: nothing vanishes behind a screen or "
                  "appears from nowhere.",
    "continuity": "Objects move along connected paths: an object cannot get from one screen to "
                  "another without crossing the gap between them.",
    "unchangeableness": "Objects keep their shape and size: what comes out from behind a screen is "
                        "what went in.",
    "solidity": "Solid objects cannot pass through each other or through walls and floors.",
    "inertia": "Objects keep their velocity unless something acts on them: no spontaneous change "
               "of speed or direction.",
    "gravity": "Unsupported objects fall, with a constant downward acceleration.",
    "collision": "Colliding objects exchange momentum: a moving object sets a hit object in motion "
                 "in the plausible direction and amount.",
    "energy": "Objects do not gain energy from nowhere: a bouncing ball never bounces higher than "
              "it fell.",
}


def concept_name(concept_id: str) -> str:
    """``Permanence-v1`` -> ``permanence``."""
    return concept_id.split("-v")[0].lower()


def describe(concept_id: str, probes_dir: Path = PROBES_DIR) -> str:
    """What ``concept_id`` tests, in one or two sentences (empty string if unknown)."""
    name = concept_name(concept_id)
    readme = probes_dir / name / "README.md"
    if readme.exists():
        m = re.search(r"\*\*Concept\.\*\*\s*(.+?)(?:\n\s*\n|$)", readme.read_text(), flags=re.S)
        if m:
            return " ".join(m.group(1).split())
    return DESCRIPTIONS.get(name, "")
