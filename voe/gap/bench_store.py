"""An append-only store of a gap bench run's case results, so a run can stop and resume.

Why: an untouched bench run is hundreds of cases and hours of CPU on two cores (session 25's
machine: about 47 s a case with ``--jobs 2``). A run cut off by a shut-down machine used to be
lost whole, and restarting it was the only way to get its summary. Each finished case is
appended here as one JSON line and flushed, so a restart with the same arguments and the same
code runs only the cases that are missing, and the summary is printed from the stored results,
never by running the finder again (``bench/gap_bench.py --score-only``).

Format: the first line is a header (``{"voe_gap_bench": 1, "run": {...}, "code": sha256,
"versions": {...}}``); every further line is one case's result dict, in strict JSON (a missing
number such as the parameter error of an unnamed case is ``null``, read back as ``nan``;
``voe.io.jsonio``). A line cut off mid-write
(the machine stopped) is dropped when the file is opened again, and its case is run again. A header whose run arguments or code
hash differ from the current ones is refused with one line naming the file: results of
different code or a different plan must never be pooled into one summary.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from voe.errors import DataError
from voe.io import jsonio
from voe.io.atomic import atomic_write_text
from voe.io.provenance import package_versions

FORMAT = 1


def code_hash() -> str:
    """sha256 over the ``voe`` package's Python sources (relative names and contents, sorted):
    which code made the results, independent of ``__pycache__`` and of where it is installed."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for f in sorted(root.rglob("*.py")):
        h.update(f"{f.relative_to(root).as_posix()}\0".encode() + f.read_bytes() + b"\n")
    return h.hexdigest()


class BenchStore:
    """Case results of one bench run (or one shard of it) in a JSON-lines file.

    Args:
        path: the file; created with its header if absent (append mode).
        run: the run's arguments that fix its cases and their outcome (seed, counts, noise,
            episodes, duration, truths, clean kinds; not ``jobs``, which changes nothing).
        shard: ``(I, N)`` if this file holds part I of N of the run (``--shard``), else None.
        read_only: only read and score what is stored: the file must exist and is never
            rewritten, and it may have been made by other ``voe`` sources or another shard
            (``made_by`` says which code). Otherwise (append mode) a file made by other sources or
            for another shard is refused, so that results of different code are never pooled.
    """

    def __init__(self, path: str | Path, run: dict, shard: tuple[int, int] | None = None,
                 read_only: bool = False) -> None:
        self.path = Path(path)
        self.read_only = read_only
        self.run = json.loads(jsonio.dumps(run))
        self.shard = list(shard) if shard else None
        self.code = code_hash()
        self.made_by: str | None = None  # the sources sha256 the stored results were made by
        self.done: dict[int, dict] = {}
        if self.path.exists() and self.path.stat().st_size > 0:
            self._read()
        elif read_only:
            raise DataError(f"bench results {self.path}: no such file to score")
        else:
            self.made_by = self.code
            header = {"voe_gap_bench": FORMAT, "run": self.run, "shard": self.shard, "code": self.code,
                      "versions": package_versions()}
            atomic_write_text(self.path, jsonio.dumps(header) + "\n")

    def _read(self) -> None:
        lines = self.path.read_text().split("\n")
        try:
            header = json.loads(lines[0])
        except json.JSONDecodeError as exc:
            raise DataError(f"bench results {self.path}: first line is not a JSON header ({exc.msg})") from exc
        if not isinstance(header, dict) or header.get("voe_gap_bench") != FORMAT:
            raise DataError(f"bench results {self.path}: not a voe gap bench results file (format {FORMAT})")
        if header.get("run") != self.run:
            diff = sorted(k for k in set(self.run) | set(header.get("run", {}))
                          if self.run.get(k) != header.get("run", {}).get(k))
            raise DataError(f"bench results {self.path}: made with other run arguments ({', '.join(diff)}); "
                            "use another file")
        self.made_by = str(header.get("code"))
        if not self.read_only and header.get("code") != self.code:
            raise DataError(f"bench results {self.path}: made by other voe code (sources sha256 "
                            f"{self.made_by[:12]} against {self.code[:12]}); use another file")
        if not self.read_only and header.get("shard") != self.shard:
            raise DataError(f"bench results {self.path}: holds shard {header.get('shard')}, not {self.shard}; "
                            "use another file")
        for n, line in enumerate(lines[1:], start=2):
            if not line.strip():
                continue
            try:
                r = json.loads(line)
            except json.JSONDecodeError:
                if n == len(lines):  # the last line, with no newline: cut off mid-write
                    if not self.read_only:  # dropped, so the next case starts a line of its own
                        atomic_write_text(self.path, "\n".join(lines[:-1]) + "\n")
                    continue
                raise DataError(f"bench results {self.path}: line {n} is not JSON") from None
            self.done[int(r["seed"])] = _numbers(r)

    def add(self, result: dict) -> None:
        """Append one case's result and flush it to disk before the next case is reported."""
        if self.read_only:
            raise DataError(f"bench results {self.path}: opened read-only")
        line = jsonio.dumps(result)
        with open(self.path, "a") as fh:
            fh.write(line + "\n")
            fh.flush()
            os.fsync(fh.fileno())
        self.done[int(result["seed"])] = _numbers(json.loads(line))


NUMBERS = ("param_error", "before", "after")  # stored as null when missing, read back as nan


def _numbers(r: dict) -> dict:
    """A stored case with its float fields as floats again (``null`` written for ``nan``)."""
    return {**r, **{k: jsonio.nan_if_none(r[k]) for k in NUMBERS if k in r}}


def _same(a: dict, b: dict) -> bool:
    """Equal as stored (nan, which never equals itself, compares as the null it was written as)."""
    return jsonio.dumps(a, sort_keys=True) == jsonio.dumps(b, sort_keys=True)


def read_stores(paths: list[str | Path], run: dict) -> tuple[dict[int, dict], list[str]]:
    """The cases stored in ``paths`` (the shards of one run, or one whole run), merged, and the
    sources sha256 of each file. A case stored twice must be stored alike."""
    done: dict[int, dict] = {}
    codes = []
    for p in paths:
        st = BenchStore(p, run, read_only=True)
        codes.append(st.made_by or "")
        for seed, r in st.done.items():
            if seed in done and not _same(done[seed], r):
                raise DataError(f"bench results {p}: case {seed} differs from the same case in another file")
            done[seed] = r
    return done, codes
