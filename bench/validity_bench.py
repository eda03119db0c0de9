"""Validity bench: the specificity matrix and the quality-target lines, on a dev or an eval seed.

Designs and declarations are chosen on the development seed (``--split dev``, seed 0); the
figures quoted in the README are measured once, afterwards, on the untouched evaluation seed
(``--split eval``, seed 8305, drawn with ``secrets`` by the lead in session 12 before any run on
it). Earlier evaluation seeds have since been looked at and are development seeds now: 2026
(``--split dev2``), 8111 (``--split dev3``, session 6's), 4077 (``--split dev4``, session 7's),
5309 (``--split dev5``, session 8's), 4418 (``--split dev6``, session 9's) and 5768
(``--split dev7``, session 10's), 5590 (``--split dev8``, session 11's). One run: core probes, an ordinary training world (the trained
object-centric model) and a small calibration world (oracles, constant velocity), every control
family but the counterfactual worlds, the blind-harness cheats (batch position, identifiers) and
the report's confounded verdicts for the trained model. The reference measured in the same run
is the *untrained* object-centric model (zero output layers: a constant, which ties every set).

    nice python bench/validity_bench.py --split dev [--per-concept 20] [--work /tmp/vb] [--jobs 2]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import pandas as pd

SPLITS = {"dev": 0, "dev2": 2026, "dev3": 8111, "dev4": 4077, "dev5": 5309, "dev6": 4418, "dev7": 5768, "dev8": 5590, "eval": 8305}
KNOWLEDGE_FREE = ("knowledge-free", "random-net")
LAWFUL = ("gravity", "solidity", "collision", "energy")


def prepare(work: Path, seed: int, per_concept: int, world_n: int, steps: int | None, jobs: int,
            hidden_p: float = 0.0) -> dict[str, Path]:
    """Probes, worlds and a trained object-centric model (each made once under ``work``)."""
    from voe.concepts.generate import generate_probe_set, resolve_concepts
    from voe.models.train import TrainConfig, train
    from voe.sim.scene import SimConfig
    from voe.world.generate import generate_world

    p = {"probes": work / "probes", "world": work / "world", "calib": work / "calib",
         "ckpt": work / "ckpt-interaction"}
    if not (p["probes"] / "manifest.json").exists():
        generate_probe_set(p["probes"], resolve_concepts("core"), per_concept, seed, SimConfig(size=64), jobs, True)
    for key, n, s in (("world", world_n, seed), ("calib", 200, seed + 1)):
        if not (p[key] / "manifest.json").exists():
            generate_world(p[key], n, s, SimConfig(size=64), "none", jobs, True,
                           hidden_p=hidden_p if key == "world" else 0.0)
    if not p["ckpt"].exists():
        train("interaction", p["world"], p["ckpt"], TrainConfig(steps=steps, minutes=30.0, seed=seed, threads=1))
    return p


def score_models(p: dict[str, Path], work: Path) -> dict[str, Path]:
    """Runs of the trained and untrained object-centric model and of the two harness cheats."""
    from voe.models.loading import load_model
    from voe.scoring.score import score_probe_set
    from voe.testing import IdReaderModel, PositionModel

    models = {"interaction": load_model("interaction", None, p["ckpt"]),
              "interaction-untrained": load_model("interaction", {"seed": 1}),
              "id-reader": IdReaderModel(), "position": PositionModel()}
    runs = {}
    for label, model in models.items():
        runs[label] = work / "runs" / label
        if not (runs[label] / "run.json").exists():
            model.name = label
            score_probe_set(model, p["probes"], runs[label], batch_size=32, overwrite=True)
    return runs


def cheats_rejected(p: dict[str, Path]) -> dict[str, str]:
    """What ``check_model`` says about each cheat (the first line of its refusal, or 'accepted')."""
    from voe.errors import ModelContractError
    from voe.io.probeset import load_probe_set
    from voe.models.check import check_model
    from voe.testing import IdReaderModel, PositionModel

    ps = load_probe_set(p["probes"])
    ids = list(ps.index.groupby("set_id")["clip_id"].first()[:8])  # clips of different sets
    out = {}
    for model in (IdReaderModel(), PositionModel()):
        try:
            check_model(model, ps.batch(ids))
            out[model.name] = "accepted"
        except ModelContractError as exc:
            out[model.name] = "rejected: " + str(exc).splitlines()[0]
    return out


def cells_table(matrix: pd.DataFrame) -> str:
    """Control x concept (verdict-carrying sets): accuracy, declaration and agreement."""
    m = matrix[matrix["condition"] == "all"].copy()
    mark = {True: "", False: "!", None: ""}
    short = {"pass": "P", "fail": "F", "chance": "C", "not-learned": "N", "none": "-"}
    m["cell"] = [f"{a:.2f} {short[e]}{mark.get(ok, '')}{'' if cf is not False else '*'}"
                 for a, e, ok, cf in zip(m["accuracy"], m["expected"], m["as_declared"], m["could_fail"], strict=True)]
    t = m.pivot(index="control", columns="concept", values="cell")
    t.columns = [c.split("-v")[0][:8] for c in t.columns]
    return t.to_string()


def family_line(kf: pd.DataFrame) -> str:
    """Random networks as a family per architecture and concept: draws above and below 0.5.

    Why: one draw is one random function, and its 10-20 sets replicate that function's bias, not
    independent chances. A draw with a memory carries it with a random sign (docs/models-findings.md);
    the verdict rule still treats any off-chance draw as a confound, the conservative reading,
    and this line shows whether the architecture's draws *as a family* lean one way (two-sided
    sign test over draws; ties at 0.5 dropped), which no choice of draw can hide.
    """
    from scipy.stats import binomtest

    rn = kf[(kf["family"] == "random-net") & (kf["condition"] == "all")].copy()
    if rn.empty:
        return "random-network families: none scored"
    rn["arch"] = rn["control"].str.replace(r"-s\d+$", "", regex=True)
    rn["stat"] = rn["halves"].where(rn["verdict_stat"] == "halves", rn["accuracy"]).astype(float)
    families = rn.groupby(["arch", "concept"], sort=True)
    lean = []
    for (arch, concept), g in families:
        up, down = int((g["stat"] > 0.5).sum()), int((g["stat"] < 0.5).sum())
        p = binomtest(up, up + down).pvalue if up + down else 1.0
        if p < 0.05:
            lean.append(f"{arch} x {concept} {up} above / {down} below (p {p:.3f})")
    return (f"random-network families (draws above / below 0.5 on the verdict statistic, per architecture "
            f"and concept, {families.ngroups} families): leaning one way at p < 0.05: " + ("; ".join(lean) or "none"))


def summary_lines(matrix: pd.DataFrame, summary: pd.DataFrame, balance: pd.DataFrame, cheats: dict,
                  stat_sets: dict[str, pd.DataFrame]) -> list[str]:
    """The quality target, one line each, computed from the matrix and the report's summary."""
    from voe.scoring.verdict import LEARNED

    verdict_cells = matrix[(matrix["condition"] == "all") | matrix["carries_verdict"].astype(bool)]
    kf = verdict_cells[verdict_cells["family"].isin(KNOWLEDGE_FREE)]
    kf_ok = kf[(kf["ci_low"] <= 0.5) & (kf["ci_high"] >= 0.5) & (kf["verdict"] != LEARNED)]
    lines = [f"knowledge-free: {len(kf_ok)} of {len(kf)} verdict cells (concepts and verdict conditions) "
             f"have a CI containing 0.5 and are not learned; off: "
             + (", ".join(f"{r.control} x {r.concept} ({r.condition}) {r.accuracy:.2f}"
                          for r in kf.drop(kf_ok.index).itertuples()) or "none")]
    from voe.controls.confound import off_chance

    off = kf[off_chance(kf) | kf["verdict"].eq(LEARNED)]
    lines.append(f"knowledge-free on the statistic that carries each verdict (the halves on cells of spliced "
                 f"quadruplets, the sum elsewhere): {len(kf) - len(off)} of {len(kf)} at chance and not learned; off: "
                 + (", ".join(f"{r.control} x {r.concept} ({r.condition}) "
                              + (f"halves {r.halves:.2f}" if r.verdict_stat == "halves" else f"{r.accuracy:.2f}")
                              for r in off.itertuples()) or "none"))
    lines.append(family_line(kf))
    fm = balance[balance["F"] & balance["M"]]
    for name in ("motion-energy", "density", "stress-frame", "stress-step"):
        on = stat_sets[name].merge(fm[["concept", "set_id"]], on=["concept", "set_id"])
        lines.append(f"exact ties on F+M-balanced sets: {name} {int((on['accuracy'] == 0.5).sum())} of {len(on)}")
    pp = matrix[(matrix["family"] == "physics-poor") & (matrix["condition"] == "all")]
    over = pp[pp["verdict"].eq(LEARNED) & ~pp["expected"].isin(("pass", "none"))]
    lines.append("physics-poor learned outside declared knowledge: "
                 + (", ".join(f"{r.control} x {r.concept} {r.accuracy:.2f}" for r in over.itertuples()) or "none"))
    fc = verdict_cells[(verdict_cells["control"] == "framecopy") & verdict_cells["verdict"].eq(LEARNED)]
    lines.append(f"framecopy learned on verdict cells: {', '.join(f'{r.concept} ({r.condition})' for r in fc.itertuples()) or 'none'}")
    for ref in ("constvel", "smoothness"):
        got = pp[(pp["control"] == ref) & pp["verdict"].eq(LEARNED)
                 & pp["concept"].str.split("-v").str[0].str.lower().isin(LAWFUL)]
        lines.append(f"{ref} learned among gravity/solidity/collision/energy: "
                     + (", ".join(got["concept"]) or "none"))
    intact = matrix[(matrix["control"] == "oracle-intact") & (matrix["condition"] == "all")]
    lines.append(f"intact oracle learned on {int(intact['verdict'].eq(LEARNED).sum())} of {len(intact)} concepts")
    les = matrix[(matrix["family"] == "lesion") & (matrix["control"] != "oracle-intact")
                 & matrix["as_declared"].notna() & matrix["could_fail"].astype(bool)]
    bad = les[~les["as_declared"].astype(bool)]
    lines.append(f"lesions as declared on cells that could fail: {int(les['as_declared'].astype(bool).sum())} of "
                 f"{len(les)}; not: " + (", ".join(f"{r.control} x {r.concept} ({r.condition}) expected "
                                                    f"{r.expected} got {r.accuracy:.2f} {r.verdict}"
                                                    for r in bad.itertuples()) or "none"))
    for name, what in cheats.items():
        s = summary[summary["model"] == name]
        lines.append(f"{name}: accuracy {', '.join(f'{a:.2f}' for a in s['accuracy'])} "
                     f"(raw verdicts: {', '.join(sorted(set(s['raw_verdict'])))}); check_model {what}")
    for model in ("interaction", "interaction-untrained"):
        s = summary[summary["model"] == model]
        learned = s[s["verdict"] == LEARNED]["concept"].tolist()
        lines.append(f"{model}: learned on {len(learned)} of {len(s)} ({', '.join(learned) or '-'}); "
                     + "; ".join(f"{r.concept} {r.accuracy:.2f} {r.verdict}"
                                 + (f" (raw {r.raw_verdict}; {r.confounded_by})" if r.confounded_by else "")
                                 for r in s.itertuples() if r.verdict != LEARNED))
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--split", choices=sorted(SPLITS), default="dev")
    ap.add_argument("--per-concept", type=int, default=20)
    ap.add_argument("--world-n", type=int, default=2000)
    ap.add_argument("--steps", type=int, default=None,
                    help="training steps of the object-centric model (default: its preset)")
    ap.add_argument("--hidden-events", type=float, default=0.0,
                    help="share of training scenes with their main event behind a screen (voe.world.hidden); "
                         "default 0: the ordinary world")
    ap.add_argument("--work", type=Path, default=None)
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    from voe.controls.builtin import FAMILIES
    from voe.controls.probe_runs import as_run, set_balance, statistic
    from voe.controls.suite import validate_suite
    from voe.io.probeset import load_probe_set
    from voe.report.build import build_report
    from voe.scoring.table import set_table

    seed = SPLITS[a.split]
    work = a.work or Path(f"voe-work/validity-bench-{a.split}")
    t0 = time.monotonic()
    p = prepare(work, seed, a.per_concept, a.world_n, a.steps, a.jobs, a.hidden_events)
    runs = score_models(p, work)
    t1 = time.monotonic()
    fams = tuple(f for f in FAMILIES if f != "counterfactual")
    matrix = validate_suite(work / "validity", work / "controls", probes=p["probes"], world=p["calib"],
                            families=fams, seed=seed, say=lambda _: None, jobs=a.jobs)
    t2 = time.monotonic()
    summary = build_report(list(runs.values()), work / "report", overwrite=True, validity=work / "validity")
    ps = load_probe_set(p["probes"])
    stat_sets = {name: set_table(as_run(ps, statistic(ps, f"stat:{name}").traces, name, name))
                 for name in ("motion-energy", "density", "stress-frame", "stress-step")}
    print(f"split {a.split} (seed {seed}), {a.per_concept} sets per concept, probes {p['probes']}")
    from voe.models.checkpoint import read_checkpoint

    ck = read_checkpoint(p["ckpt"])
    print(f"trained {ck['model']}: {ck['steps']} of {ck.get('steps_budget', '?')} steps in {ck['seconds']:.0f} s"
          f"{' (stopped by the time cap)' if ck.get('time_capped') else ''}, validation NLL {ck['val_nll']:.2f}")
    print("cells: accuracy, declaration (P pass, F fail, C chance, N not learned, - none), "
          "! not as declared, * could not fail")
    print(cells_table(matrix))
    for line in summary_lines(matrix, summary, set_balance(ps), cheats_rejected(p), stat_sets):
        print(line)
    print(f"time: data+training+scoring {t1 - t0:.0f} s, controls {t2 - t1:.0f} s, report {time.monotonic() - t2:.0f} s")


if __name__ == "__main__":
    main()
