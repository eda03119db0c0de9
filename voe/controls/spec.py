"""What a control is, and how users declare their own in YAML.

A control declares, per concept, one of:

* ``pass``: it should learn the concept (verdict *learned*);
* ``fail``: it should not (verdict *not learned*: at chance or reversed);
* ``chance``: it must sit at chance (the 95% CI of its accuracy contains 0.5): neither learned
  nor reversed;
* ``not-learned``: it must not be judged *learned* (a physics-poor reference outside its
  declared knowledge: at chance, reversed or inconclusive are all fine);
* ``none``: no claim.

Concepts it does not mention default to ``default`` (``pass`` for counterfactual models, which
should keep every law they were not deprived of; lesions declare every concept explicitly).

User file (``--controls my_controls.yaml``)::

    controls:
      - name: my-sim-without-friction
        model: mypkg.sims:NoFriction          # or a registered model name
        args: {noise: 0.1}                     # optional, as --model-arg
        checkpoint: runs/ckpt                  # optional, relative to this file, inside its folder
        should_fail: [solidity]
        should_pass: [permanence, gravity]
        default: pass                          # for unlisted concepts (pass|fail|chance|not-learned|none)
        family: user                           # or knowledge-free / physics-poor: then it can
                                               # mark a probe confounded (voe.controls.confound)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from voe.errors import VoeError
from voe.io.paths import inside

EXPECTATIONS = ("pass", "fail", "chance", "not-learned", "none")
#: Families whose controls know nothing: off chance on a probe set means the probe gives its
#: answer away (``voe.controls.confound``).
KNOWLEDGE_FREE = ("knowledge-free", "random-net")
#: Families that know part of physics: learned beyond their declaration means the same.
PHYSICS_POOR = ("physics-poor",)


@dataclass(frozen=True)
class Control:
    """A model with declared expectations.

    Attributes:
        name: row label in the matrix.
        family: ``knowledge-free``, ``random-net``, ``physics-poor``, ``lesion``,
            ``counterfactual`` or ``user``.
        model: registered model name, ``module:attr``, or ``stat:NAME`` for a statistic of the
            probe set's stored bytes (``voe.controls.probe_runs``).
        args: model arguments.
        checkpoint: optional checkpoint path (or the name of a counterfactual training set the
            runner trains on, for ``counterfactual`` controls: ``train_on``).
        expect: concept name (or ``concept/visible``, ``concept/occluded``) -> expectation;
            concepts not listed get ``default``.
        default: expectation for unlisted concepts.
        why: one line on what the control knows and why it should pass/fail where it does.
        train_on: counterfactual world the control's model is trained on (counterfactual family).
        calibrate: fit the model's noise on the training world before scoring (``voe train``).
        invariant_to: the balance (``F`` frames, ``M`` per-step change, ``S`` per-frame states)
            on which the control ties by construction: its ``chance`` cells on sets that reach
            it could not have failed, and are reported apart.
    """

    name: str
    family: str
    model: str
    args: dict[str, Any] = field(default_factory=dict)
    checkpoint: str | None = None
    expect: dict[str, str] = field(default_factory=dict)
    default: str = "pass"
    why: str = ""
    train_on: str | None = None
    calibrate: bool = False
    invariant_to: str = ""

    def expectation(self, concept: str, condition: str | None = None) -> str:
        """Expectation for a concept (name or versioned id, ``Gravity-v1``), or for one of its
        conditions (``visible``/``occluded``), which is only checked where declared."""
        base = concept.split("-v")[0].lower()
        if condition is not None:
            return self.expect.get(f"{base}/{condition}", "none")
        return self.expect.get(base, self.default)


def _names(entry: dict[str, Any], key: str, path: Path) -> list[str]:
    val = entry.get(key, []) or []
    if not isinstance(val, list) or not all(isinstance(v, str) for v in val):
        raise VoeError(f"{path}: '{key}' of control '{entry.get('name')}' must be a list of concept names")
    return [v.lower() for v in val]


def load_user_controls(path: Path) -> list[Control]:
    """Read user controls from YAML (see the module docstring); one-line errors name the file."""
    from voe.concepts import CONCEPTS

    path = Path(path)
    if not path.exists():
        raise VoeError(f"controls file {path} does not exist")
    try:
        doc = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise VoeError(f"{path} is not valid YAML: {str(exc).splitlines()[0]}") from exc
    except (UnicodeDecodeError, OSError) as exc:
        raise VoeError(f"{path} cannot be read as UTF-8 YAML text: {exc}") from exc
    entries = (doc or {}).get("controls") if isinstance(doc, dict) else None
    if not isinstance(entries, list) or not entries:
        raise VoeError(f"{path}: expected a non-empty list under 'controls'")
    out = []
    for e in entries:
        if not isinstance(e, dict) or "name" not in e or "model" not in e:
            raise VoeError(f"{path}: every control needs 'name' and 'model' (got {e!r})")
        expect: dict[str, str] = {}
        for key, val in (("should_pass", "pass"), ("should_fail", "fail"), ("should_be_chance", "chance"),
                         ("should_not_learn", "not-learned")):
            for concept in _names(e, key, path):
                try:
                    CONCEPTS.resolve(concept)  # did-you-mean on typos
                except VoeError as exc:
                    raise type(exc)(f"{path}: control '{e['name']}': {exc}") from exc
                expect[concept] = val
        default = str(e.get("default", "none"))
        if default not in EXPECTATIONS:
            raise VoeError(f"{path}: default '{default}' of control '{e['name']}' is not one of {EXPECTATIONS}")
        family = str(e.get("family", "user"))
        if family not in ("user", *KNOWLEDGE_FREE, *PHYSICS_POOR):
            raise VoeError(f"{path}: family '{family}' of control '{e['name']}' is not one of "
                           f"{('user', *KNOWLEDGE_FREE, *PHYSICS_POOR)}")
        ckpt = e.get("checkpoint")
        if ckpt is not None:  # relative to the YAML file, and never outside its directory
            ckpt = str(inside(path.parent, ckpt, path))
        args = e.get("args") or {}
        if not isinstance(args, dict):
            raise VoeError(f"{path}: 'args' of control '{e['name']}' must be a mapping")
        out.append(Control(name=str(e["name"]), family=family, model=str(e["model"]),
                           args=dict(args), checkpoint=ckpt,
                           expect=expect, default=default, why=str(e.get("why", "declared by the user"))))
    return out
