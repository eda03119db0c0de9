"""Validity controls: models whose knowledge is known in advance, and the specificity matrix.

A control is a model plus what it *should* do on each concept (pass, fail, or sit at chance).
Running every control over a probe set and comparing outcomes with declarations shows whether
each probe measures the concept it names (``voe validate-suite``).
"""

from voe.controls.spec import EXPECTATIONS, Control, load_user_controls

__all__ = ["EXPECTATIONS", "Control", "load_user_controls"]
