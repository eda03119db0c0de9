"""Does the data depart from the nominal model more than its clean replicate does, overall?

Why: the verdict ``unexplained`` used to need only one located stretch above the clean
replicate's largest window z. On 40 clean bench cases (development seeds 50-89) that fired in
10; with this test in 2, both with timestamp jitter, which the null's noise model does not
reproduce. Window z-scores are dominated by a few chaotic windows (a ball striking a box
amplifies a millimetre of initial-state error into centimetres), and the largest of about 20
such values is itself a wild draw, so the data's largest window beats the replicate's about
half the time. Physics that is really missing (a gusting wind, a floor patch, a wrong law)
raises many windows, not one. So the departure is also tested as a whole: a one-sided Wilcoxon
signed-rank test on the paired log z-scores of the same windows in the data and in the clean
replicate (same start states, same noise model, so under the nominal model the pairs are
exchangeable and the test's level is honest without any tuning).

A test that only swaps pairs cannot give a p-value below 2^-k when k pairs depart, whatever
their size, and the signed-rank test dilutes k large departures among many unaffected windows.
Physics confined to a place (a floor patch the box slides over once, early in an episode) raises
one 1-s window per episode it touches: development case 3629067 had six windows at z 11-124
against a replicate whose largest was 3.4, and the signed-rank p was 0.033, so a 0.14 m error was
called consistent. So the departure is tested by two statistics, Bonferroni-combined: the
signed-rank test on the 1-s windows against the clean replicate (many windows raised a little),
and a paired randomisation test of how far data windows exceed clean replicates of the same
windows (a few raised far beyond what clean data shows; ``tail_p``), on the same 1-s windows
against ``REPLICATES`` window-local clean replicates (``local_replicates``).

Why window-local replicates (session 28): until then the tail test compared half-second windows
with four whole-episode replicates, the nominal motion from each episode's fitted initial state
with fresh noise. In the bench's arena that motion leaves the data's within a second or two, so
the replicates share one path and the data has another: a window where the data grazes a
collision its replicates miss stands out whatever the physics. With four replicates that rarely
reached the 1 % level; with more it did, so more replicates (the floor of k departing windows is
(R + 1)^-k, and eight floor patches of the development seeds stayed ``consistent`` although they
moved 3-5 selection windows by up to 17-156 mm) bought power only with false alarms: 20 replicates
on 1-s windows called 10 of 216 clean development cases ``unexplained``. A window-local replicate
starts at the data's own fitted state where the window's start fit begins, perturbed by a draw of
that fit's error, so each replicate has its own path near the data's, as the data's true start
differs from the fitted one; data and replicates then meet the same collisions, and the window
z-scores of a column are exchangeable up to the start fit's error. Development seeds 6685, 1078,
1967 and 2250 (the 48 out-of-library cases and 216 clean, located stage only,
``docs/bench-runs/dev-s28``): floor patches unexplained-able 16 -> 18 of 24, gusts 24 of 24,
clean 0 of 216 as before, and the tail p alone on clean cases no more often small than a uniform
p (6 below 0.05 of 216 with ten replicates).

Timing jitter (session 29): samples taken off their stamps are off by velocity times the time
error, which the replicates now reproduce when the recordings show it (``voe.gap.jitter``). Before,
14 of 40 clean jittered development cases were located with p < 0.01 (``unexplained``); now 0."""


from __future__ import annotations

import numpy as np
from scipy.stats import ttest_1samp, wilcoxon

from voe.gap.effects.base import Effect
from voe.gap.jitter import Jitter
from voe.gap.locate import window_z
from voe.gap.recordings import Episode
from voe.gap.shooting import ORDER, Shooter, Window
from voe.gap.synth import replicate_noise

ALPHA = 0.01  # one located case in a hundred clean ones may be called unexplained
N_PERM = 2000  # random exchanges of ``tail_p``: its smallest p-value is 1/2001
# window-local clean replicates ``tail_p`` compares each window with: k departing windows can reach
# p = 11^-k, so three suffice at ALPHA after the Bonferroni factor; on the development cases 20 found
# the same patches at twice the cost (5.1 against 9.1 cpu-s on bench/gap_speed.py's case, where the
# half-second part this replaced took 1.8)
REPLICATES = 10


def departure_p(z_data: np.ndarray, z_null: np.ndarray, local: np.ndarray | None = None) -> float:
    """One-sided p-value that the data's window z-scores (W,) exceed the clean replicate's (W,):
    the smaller of the signed-rank p (data against ``z_null``) and the tail p (``tail_p``: data
    against ``local``, the window-local replicates' z-scores (R, W) of the same windows; default
    ``z_null``), doubled.

    The signed-rank test needs ten pairs or more (with n pairs its smallest p-value is 2^-n);
    with fewer, a one-sided t-test on the log ratios (symmetric under the nominal model, so the
    test is at worst conservative for heavy tails). 1.0 with fewer than three pairs.
    """
    return min(1.0, 2.0 * min(_signed_rank_p(z_data, z_null), tail_p(z_data, z_null if local is None else local)))


def _signed_rank_p(z_data: np.ndarray, z_null: np.ndarray) -> float:
    d = np.log(np.maximum(z_data, 1e-6)) - np.log(np.maximum(z_null, 1e-6))  # (W,)
    d = np.nan_to_num(d, nan=0.0, posinf=1e6, neginf=-1e6)  # a diverged data window counts, hugely
    d = d[d != 0]
    if len(d) < 3:
        return 1.0
    if len(d) >= 10:
        return float(wilcoxon(d, alternative="greater").pvalue)
    if np.ptp(d) == 0:
        return 0.0 if d[0] > 0 else 1.0
    return float(ttest_1samp(d, 0.0, alternative="greater").pvalue)


def tail_p(z_data: np.ndarray, z_null: np.ndarray, n_perm: int = N_PERM, seed: int = 0) -> float:
    """One-sided randomisation p-value of T, the summed log excess of each window's data z (W,)
    over the largest of the same window's replicate z-scores (``z_null``: (W,) for one clean
    replicate, or (R, W) for R of them), ``sum_w max(0, log z_data[w] - log max_r z_null[r, w])``,
    under random exchanges within each window's column of data and replicate values (the nominal
    model makes each column exchangeable, whatever the window's chaos). 1.0 when T = 0 or with
    fewer than three windows.

    Why: it counts departures beyond what clean data shows, which the signed-rank test caps at
    their rank. Why several replicates: with one, a column can only be swapped or not, so k
    departing windows cannot give p below 2^-k (development case 1531065, a floor patch crossed
    in five episodes: five half-second windows at z 65-144 against a replicate whose largest was
    17, p = 0.037, and a 0.136 m error read as consistent). With R replicates the floor is
    (R + 1)^-k.

    Why each window against its own column, not against the largest replicate window anywhere
    (the count this test used until session 20): a chaotic window is chaotic in every replicate
    (they share the nominal motion; only the noise is redrawn), so one such window set the bar
    for all others. Development case 9028142 (a floor patch, test RMSE 40 mm against a clean
    median of 4): six 1-s windows at z 34-138 whose replicates were 2-4, but one window at z 62
    in all four replicates, so no data window counted, p = 1, and the case read ``consistent``.
    Column by column that window's data is one of five similar values and adds about nothing.
    The excess, not a count, so that a window far above its column weighs more than one just
    above it; the randomisation keeps the level exact whatever the statistic. On 113 clean
    bench cases (six development seeds, the largest-RMSE ones and every one ever called
    ``unexplained``) the departure test fired on 1 (3 with the count); on 48 out-of-library
    cases every one it found with the count it still finds, and 9028142/9028144 too.
    """
    zd = np.nan_to_num(np.asarray(z_data, dtype=float), nan=0.0, posinf=1e300)  # (W,) a diverged window counts
    zn = np.nan_to_num(np.atleast_2d(np.asarray(z_null, dtype=float)), nan=0.0, posinf=1e300)  # (R, W)
    if len(zd) < 3:
        return 1.0
    v = np.log(np.maximum(np.vstack([zd[None], zn]), 1e-6))  # (R + 1, W): each column exchangeable
    n_rows, w = v.shape
    order = np.sort(v, axis=0)
    top1, top2 = order[-1], order[-2]  # (W,) each column's largest and second largest

    def excess(chosen: np.ndarray) -> np.ndarray:  # (N, W) -> (N,) T with ``chosen`` playing the data
        rest = np.where(chosen >= top1[None], top2[None], top1[None])  # (N, W) the column's largest other
        return np.sum(np.maximum(0.0, chosen - rest), axis=1)

    t_obs = float(excess(v[:1])[0])
    if t_obs <= 0.0:
        return 1.0
    pick = np.random.default_rng(seed).integers(0, n_rows, size=(n_perm, w))  # (N, W) the row playing the data
    t = excess(v[pick, np.arange(w)[None]])  # (N,)
    return float((1 + np.sum(t >= t_obs * (1 - 1e-12))) / (n_perm + 1))


def local_replicates(shooter: Shooter, windows: list[Window], sigma: np.ndarray, phi: np.ndarray,
                     rng: np.random.Generator, n: int = REPLICATES, jitter: Jitter | None = None,
                     effect: Effect | None = None, params: np.ndarray | None = None) -> np.ndarray:
    """(n, W) largest window z of ``n`` window-local clean replicates of the data's ``windows``;
    with ``effect`` and ``params``, replicates of that model instead of the nominal one (its motion,
    and its own window z on them: ``voe.gap.carry_over.deepened``).

    Each window is cut out together with the samples its centred start fit reaches back to (from
    ``lo``), so its z is computed as the location's is. A replicate of it starts at ``lo`` from the
    data's fitted state there (one-sided fit), perturbed by a draw of that fit's own error (the fit
    repeated on the nominal motion plus fresh noise), runs the nominal model to the window's end,
    and gets fresh noise of the data's noise model (``sigma`` (B, 3), AR(1) ``phi`` (B, 3), timing
    ``jitter``: ``voe.gap.synth.replicate_noise``); its z
    is the data's statistic, the residual of shooting from the centred start fit at the window's
    start. Why the perturbation: replicates sharing one start all meet (or all miss) a grazing
    collision the data's true path misses (or meets); each with its own draw, the data's path is one
    more draw of the same kind (see the module docstring). Two rollouts per window and replicate.
    """
    n_fit = max(2 * shooter.half + 1, ORDER + 3)  # samples of the start fit (``local_state``)
    seg, wins = [], []
    for i, w in enumerate(windows):
        ep = shooter.episodes[w.ep]
        lo = max(0, min(w.k0 - n_fit // 2, len(ep.t) - n_fit, w.k0))  # where local_state's fit at k0 starts
        seg.append(Episode(ep.id, ep.t[lo:w.k1 + 1].copy(), ep.pose[lo:w.k1 + 1]))
        wins.append(Window(i, w.k0 - lo, w.k1 - lo))
    whole = [Window(i, 0, len(e.t) - 1) for i, e in enumerate(seg)]
    base = Shooter(shooter.scene, seg, shooter.substep, shooter.half).simulate_many(whole, effect, params)  # (n_i, B, 3)
    out = []
    for _ in range(n):
        drawn = Shooter(shooter.scene, [Episode(e.id, e.t, m + replicate_noise(m, e.t, sigma, phi, jitter, rng))
                                        for e, m in zip(seg, base, strict=True)], shooter.substep, shooter.half)
        path = drawn.simulate_many(whole, effect, params)  # from the refitted, so perturbed, start
        eps = [Episode(e.id, e.t, m + replicate_noise(m, e.t, sigma, phi, jitter, rng))
               for e, m in zip(seg, path, strict=True)]
        rep = Shooter(shooter.scene, eps, shooter.substep, shooter.half)
        res = rep.residuals(wins, effect, params) if effect is not None else None
        out.append(window_z(rep, wins, sigma, res).max(axis=(1, 2)))
    return np.array(out).reshape(n, len(windows))
