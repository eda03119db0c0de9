"""One small exception hierarchy for everything voe reports to a user.

Why: the CLI turns any ``VoeError`` into a one-line message and an exit code, so every layer
raises one of these instead of printing. Exit code 1 is a user error (bad input, unknown name),
exit code 2 is a broken contract (a model that returns the wrong shape).
"""

from __future__ import annotations


class VoeError(Exception):
    """Base class. ``exit_code`` is what the CLI exits with.

    The message is always one line: a wrapped library message (pyarrow's spans several) has its
    line breaks folded, so the CLI never prints more than ``voe: error: ...``.
    """

    exit_code = 1

    def __str__(self) -> str:
        return " ".join(super().__str__().split())


class UnknownNameError(VoeError, KeyError):
    """A registry lookup failed; the message carries did-you-mean suggestions."""

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return " ".join(str(self.args[0]).split()) if self.args else ""


class ProbeSetError(VoeError):
    """A probe set (or training set) on disk is missing, malformed or inconsistent."""


class ModelContractError(VoeError):
    """A model broke the ``frame_nll`` protocol (shape, NaN, determinism...)."""

    exit_code = 2


class CheckpointError(VoeError):
    """A checkpoint is missing, corrupt or belongs to another architecture or feature layout."""


class RunError(VoeError):
    """A scoring run on disk is missing, malformed, empty or incompatible with another run."""


class DataError(VoeError):
    """Recordings or scene files for the gap finder are malformed."""


class ConceptError(VoeError):
    """A concept failed to build a valid matched set (a generator bug, not user input)."""

    exit_code = 2
