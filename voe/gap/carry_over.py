"""The final model's test bars: does what the check and the drift test kept carry over to the test
episodes, which nothing before has seen?

Why a module of its own: these bars run last (``voe.gap.finder``, after ``voe.gap.drift``), read only
the test split, and drop the whole model when it fails (``drop_all``): ``worse_on_test`` asks that the
model neither leave the typical test window departing more than the nominal model does nor add to any
one test window an error that is itself a departure (``deepened``); ``short_on_test`` asks the second
look's model for a practical gain on the test episodes. The selection-window checks that decide which
effects stay are ``voe.gap.check``.
"""

from __future__ import annotations

import numpy as np

from voe.gap.check import Checked, heldout_pairs, verify_on_test
from voe.gap.departure import local_replicates
from voe.gap.fit import FitResult
from voe.gap.locate import window_z
from voe.gap.recordings import Episode
from voe.gap.shooting import Shooter, Window
from voe.gap.stages import GapConfig, Problem
from voe.gap.start_refit import refitted_z
from voe.gap.verify import EXPRESSED_Z, Verification


def worse_on_test(c: Checked, p: Problem, config: GapConfig, z_thr: float,
                  null_episodes: list[Episode] | None = None, seed: int = 0) -> Checked:
    """``c`` with nothing reported if its model leaves the typical test window departing (median
    window z above the located threshold ``z_thr``) and departing more than the nominal model
    leaves it (``Verification.median_z_before``), or, given the clean replicate's ``null_episodes``,
    adds to any one test window an error that is itself a departure (``deepened``); else ``c``. The
    last step, after the drift test (``voe.gap.finder``), on the final model's test figures, which
    nothing before has seen.

    Why: a missing library effect, fitted, takes the windows it acts in towards what clean data
    shows; on episodes it has not seen it can fall short (a second effect not found), but it
    does not make the typical window depart more. Physics outside the library, fitted by a
    library effect, moves error between windows, and where it is wrong it is wrong everywhere the
    effect acts. Development case 6685149 (a gust) named ``rolling_resistance`` 0.048 once the
    drift test had dropped ``quadratic_drag``: test windows z 10.1, 18.6, 62.8 -> 24.4, 3.5,
    48.0 against 5.0 (median 18.6 -> 24.4; test RMSE 88 -> 70 mm, carried by the worst window);
    on the selection windows it had cleared 3 of 11 departures (11 -> 8), so ``clears_none``
    passed it. Right names leave the median test window z at or below the threshold (session 23
    must-stay cases, docs/gap-findings.md), but not always: with two test windows the median is
    their mean, and a right model whose collision goes the other way in one of them is dropped
    (development case 4261054, a true ``constant_acceleration``: z 31.1, 67.4 -> 4.0, 142.9 against
    41.6; the truth itself gives 247.2 there, in its own replicates' upper mode; session 35, a known
    limitation, not changed).
    """
    v = c.verification
    if c.model is None:
        return c
    if v.median_z_after > max(v.median_z_before, z_thr):
        why = (f"on the test episodes the median window z rises from {v.median_z_before:.1f} to "
               f"{v.median_z_after:.1f}, above the located threshold z = {z_thr:.1f}: it does not carry over")
    else:
        deep = deepened(p, c.model, config, z_thr, null_episodes, v, seed) if null_episodes is not None else []
        if not deep:
            return c
        why = ("on the test episodes it adds an error that is itself a departure: " + ", ".join(
            f"a window from z {b:.1f} to {a:.1f} (a rise of {np.sqrt(a * a - b * b):.1f}; clean replicate {n:.1f}, "
            f"the model's own replicates {m:.1f})" for b, a, n, m in deep)
            + f", located threshold z = {z_thr:.1f}: it does not carry over")
    return drop_all(c, why)


def short_on_test(c: Checked, p: Problem, config: GapConfig, z_thr: float) -> Checked:
    """``c`` with nothing reported if its model lowers the test-split RMSE by less than
    ``config.second_look_test_gain`` (5 %); else ``c``. Asked of the second look's answer only
    (``voe.gap.finder``), after ``worse_on_test``.

    Why: the second look cross-fits, so every non-test episode selects and a weakly felt truth
    passes the bootstrap; by the same token a clean case's noise gets two chances to be named.
    On development seed 6774 every right name a cross-fitted look gave where the three-way split
    had named nothing lowered the test RMSE by 16 % or more (6774016 ``friction`` 16.0 %, 024 and
    050 ``rolling_resistance`` 38.1 and 58.8 %, 055 ``friction`` 84.9 %, 080
    ``constant_acceleration`` 89.1 %), and the second look's two wrong names by 0.1 % (floor patch
    6774148, ``friction``) and 2.0 % (clean 6774226, ``rolling_resistance`` 0.0032: 2.32 -> 2.27
    mm); both now read ``consistent``, as they did before the second look existed.
    A name that does not predict unseen episodes better by a practical margin is not worth a
    claim, and the bar reads test figures the finder already has (docs/gap-findings.md,
    sessions 34 and 35). Not asked of the first look: its bootstrap on the selection windows is
    the stricter bar, and a right first-look name can lower the test RMSE little where one
    chaotic window dominates it (6774127 ``restitution``, 7.6 %; stopped seed 4261's three right
    first-look ``mass`` names, whose fits trade collisions, -14.3, 0.0 and -0.9 %).

    Not asked either when the model moves no test window's prediction by more than
    ``EXPRESSED_Z`` (3) noise sigmas (RMS over the window, ``Verification.moved``; the bench's
    measure of a window expressing a law, ``voe.gap.bench.expression``): two test episodes that do
    not express a law cannot say whether it is there, and the name stands on the second look's
    own bar (the cross-fitted selection windows, against that look's null). Why (session 65):
    on development seed 2276 the bar dropped three right singles and a floor patch's right
    ``friction_region`` this way (``friction`` 2276003 and 2276055, ``mass[box]`` 2276124: test
    gains -1.1, 0.5 and 2.3 %, no test window moved past 3 sigmas; the patch 2276138, 1.1 %), and
    3829011's ``rolling_resistance`` (1.7 %, none moved); three of seed 6219's four in session 46
    alike (the fourth, 6219050, moved a window and made it worse).
    The two wrong names the bar was built on (6774226, 6774148) no longer reach it on this
    code: the first look decides both (``consistent``; ``friction_region``, right for a patch).
    Of seed 2276's clean cases whose line drops a name, and seed 3829's, none had a second-look
    name the bar dropped (``docs/bench-runs/dev-s65/``). A name that does move a test window is
    judged as before: 3829037's ``rolling_resistance`` (two windows moved, the test RMSE 2.0 ->
    7.5 mm) and floor patch 2276142's ``friction_region`` (-42.9 %) stay dropped.

    Nor is the exemption given to a name that makes the test RMSE worse by more than the bar's own
    margin (``second_look_test_gain``): test episodes that cannot confirm a weak law can still
    refute it, many windows each a little worse. Why (session 66): the untouched run of seed 5905
    measured the exemption, and its one effect there was a false discovery: clean case 5905013's
    second look named ``constant_acceleration``, which moved no test window past 3 sigmas and made
    the test RMSE 35 % worse (1.38 -> 1.86 mm); before the exemption the bar dropped it. The right
    names the exemption kept on seeds 2276 and 3829 changed the test RMSE by -1.1 to +2.3 %.
    """
    v = c.verification
    if c.model is None or not np.isfinite(v.rmse_before) or v.rmse_before <= 0:
        return c
    gain = 1.0 - v.rmse_after / v.rmse_before
    if v.moved and max(v.moved) <= EXPRESSED_Z * float(np.median(p.sigma[:, :2])) \
            and gain > -config.second_look_test_gain:
        return c  # the test episodes do not express the name and do not refute it: they cannot judge it (see above)
    if gain >= config.second_look_test_gain:
        return c
    why = (f"the second look's name lowers the test RMSE by only {100 * gain:.1f} % ({v.rmse_before:.4g} -> "
           f"{v.rmse_after:.4g} m), below {100 * config.second_look_test_gain:g} %: not a practical gain on "
           "episodes it has not seen")
    return drop_all(c, why)


def drop_all(c: Checked, why: str) -> Checked:
    """``c`` with every effect dropped for ``why`` and the nominal model's test figures (the *before*
    figures of ``c``'s own, taken on the same test windows: ``Verification.nominal``)."""
    return Checked(None, (), np.zeros(0), np.zeros(0), c.dropped + tuple({"effect": k, "reason": why} for k in c.keys),
                   c.verification.nominal(), c.test_note, np.zeros(0))


def deepened(p: Problem, model: FitResult, config: GapConfig, z_thr: float, null_episodes: list[Episode],
             ver: Verification | None = None, seed: int = 0) -> list[tuple[float, float, float, float]]:
    """(z without, z with ``model``, z of the clean replicate, median z of the model's own
    replicates) of each test window where ``model`` adds an error that is itself a departure: the
    rise of the window's squared z, as a z, ``sqrt(z_with^2 - z_without^2)``, above
    ``config.deepen_factor`` (2) times the largest of the located threshold ``z_thr``, the clean
    replicate's z there (the nominal model on nominal motion from the same recorded starts: how far
    noise alone, amplified by a chaotic collision, takes that window) and the median z of the
    model's own window-local replicates there (``config.deepen_replicates`` of them,
    ``voe.gap.departure.local_replicates`` with the model: how far noise takes the window if the
    model is right; drawn from ``seed``, and only for windows the first two bars do not excuse),
    in a window whose z the model also grows by ``config.deepen_growth`` (1.2) or more, and which
    still departs with each side's start velocity refitted (``start_noise``, ``config.deepen_refit``).

    Why: a missing library effect, fitted, can leave a test window as it was (a second effect not
    found, a collision whose outcome flips), but it does not add to a window an error that clean
    data would call a departure; physics outside the library fitted by a library effect moves
    error between windows, and on episodes it was not fitted on it puts error where there was
    none. If the model's change to a window's prediction were orthogonal to the window's residual,
    z_with^2 = z_without^2 + (its change in sigmas)^2: the rise is the model's own error there.
    Designed on development seed 1078 (the final model's test windows in all 150 non-clean
    cases, main 8419ffe; docs/gap-findings.md, session 24): gust 1078143 (named
    ``rolling_resistance_region``, ``quadratic_drag``) takes a window from z 6.0 to 15.8, a rise of
    14.5 against a threshold of 5.4 and a replicate z of 5.6; floor patch 4593142 (``mass[ball]``,
    development seed 4593) 38.2 -> 49.3, a rise of 31.1 against 11.4 and 2.4. Of the 122 right
    names, the largest rise was 0.58 of its bar (1078005 ``joint_friction``, 2.9 -> 4.1, rise 2.9
    against 5.0); 1078109 (``joint_friction``) takes a window from 20.0 to 21.4, a rise of 7.6
    against 16.7, which a bar on z itself (21.4 > 20.0 and the threshold) would have dropped.
    Not asked on the selection windows: there right names raise windows (1078034
    ``point_attractor`` 4.8 -> 150.9), since the selection windows chose the model among the
    candidates' fits, and a fit trades windows against each other.

    Why twice the bar: with a bar of 1 (session 24), the untouched seed 1967 lost two right names,
    1967005 ``joint_friction`` (a double pendulum's test window 6.0 -> 8.5, a rise of 5.9 against
    a replicate z of 5.7: 1.04 bars) and 1967085 ``mass[box]`` (beside a wrong
    ``constant_acceleration``, 1.4 bars), and saved one misname, gust 1967147 (named
    ``constant_acceleration``, 5.5 bars). The one replicate's z in a chaotic window is a
    noisy bar, and a right fit that mistimes one collision of a chaotic test episode rises a
    window by about it. The misnames on the development seeds rose 2.6 and 2.7 bars (1078143,
    4593142). Chosen on seeds 1078, 6685 and 1967 (docs/gap-findings.md, session 25). ``ver``: the model's test
    verification if at hand (its per-window z), so that the test windows are not simulated again.

    Why the model's own replicates (session 34): the clean replicate runs the nominal motion, which
    a right model changes. Development case 6774127 (a true ``restitution`` of 0.833, fitted 0.834)
    takes a test window from z 56.9 to 60.8, and the truth itself leaves it at 60.6: at the lower
    restitution the ball meets the box in a way that amplifies the start fit's millimetre into
    decimetres, a collision the nominal replicate (z 1.4) never meets. Its rise (21.4) passed twice
    the clean bar (14.0) and the right name was dropped (``unexplained``). Replicates of the model
    itself, window-local as the departure test's (each from the data's fitted start, perturbed by a
    draw of that fit's error), meet the same collision in half of ten draws: their median z there
    is 24.4, which excuses the rise. A library effect fitted to physics outside the library is not excused this
    way unless its own motion is chaotic in that window too. (Since session 61, restarts from the
    simulator's half-step start velocity, that case's replicates there have a median z of 7.7 and
    the growth bar below spares it; ``tests/gap/test_carry_over.py``.)

    Why the window's z must also grow by ``config.deepen_growth`` (1.2; session 42): the rise
    measures what the model adds as if its change were orthogonal to the residual, and in a window
    that already departs hugely without the model (a chaotic impact, z 50-70) a change of a few
    per cent in its z is a rise past any bar. Development cases 6219127 (a true ``restitution`` of
    0.736, fitted 0.734; median test window z 10.7 -> 2.8) and 8367093 (a true
    ``constant_acceleration``; median test window z 36.7 -> 2.6, test RMSE 73 -> 43 mm) were each
    dropped for one such window: 71.1 -> 74.5 (x1.05) and 53.0 -> 61.3 (x1.16; 53.0 -> 57.8, x1.09,
    in the second look). The right names the replicates spare grew theirs as little: 20.0 -> 21.4
    (1078109, x1.07), 56.9 -> 60.8 (6774127, x1.07). Every misname the rule has caught grew its
    window more: 38.2 -> 49.3 (floor patch 4593142, x1.29), 12.3 -> 30.0 (gust 1967147, x2.4),
    6.0 -> 15.8 (gust 1078143, x2.6), 4.9 -> 49.9 (floor patch 6219142, second look, x10): a wrong
    law puts error where there was little. 1.2 lies between (docs/gap-findings.md, session 42).
    """
    pairs = heldout_pairs(p, model, config)[0]
    if not pairs:
        return []
    ver = ver if ver is not None and ver.z_before else verify_on_test(p, model, config, z_thr)[0]  # the model's own
    zb, za = np.asarray(ver.z_before), np.asarray(ver.z_after)  # (W,) each
    null = Shooter(p.scene, null_episodes, p.substep, p.half)
    zn = window_z(null, [w for w, _ in pairs], p.sigma).max(axis=(1, 2))  # (W,) the data's windows on the replicate
    rise = np.sqrt(np.maximum(0.0, za ** 2 - zb ** 2))  # (W,)
    bar = config.deepen_factor * np.maximum(zn, z_thr)  # (W,)
    grown = za > config.deepen_growth * zb  # (W,) the window departs by a fifth more than it did, not a few per cent
    out = []
    rng = np.random.default_rng(seed)
    for i in np.flatnonzero((rise > bar) & grown):  # the model's own replicates, only where nothing else excuses it
        w, params = pairs[i]
        zm = float(np.median(local_replicates(p.shooter, [w], p.sigma, p.phi, rng, config.deepen_replicates,
                                              p.jitter, model.effect, params))) if config.deepen_replicates else 0.0
        if rise[i] > config.deepen_factor * max(zm, zn[i], z_thr) and not (
                config.deepen_refit and start_noise(p, w, model, params, config, z_thr)):
            out.append((float(zb[i]), float(za[i]), float(zn[i]), zm))
    return out


def start_noise(p: Problem, w: Window, model: FitResult, params: np.ndarray, config: GapConfig, z_thr: float) -> bool:
    """Whether the model's departure in test window ``w`` goes once each side's start velocity is
    refitted under it (``voe.gap.start_refit``): the model's refitted z at or below the located
    threshold, or grown by less than ``config.deepen_growth`` over the nominal model's refitted z.

    Why (session 63): a start velocity read off noisy poses is about two sigmas off now and then, and
    a collision in the window amplifies it until the true physics itself departs. Restarted from the
    noise-free start, the truth follows. ``deepened`` dropped three right names for such windows on the
    development seeds, and the test-split guards asked of the truth itself dropped it in five of 720
    cycle cases. With each start refitted, the fits' windows fell from z 48.1, 25.5 and 48.5 to 0.6 in
    all three: 3829008 (``point_attractor``; the nominal model's window, refitted, 26.1), 1829053
    (``angular_damping``; 3.7) and 3511035 (``quadratic_drag``; 7.3). The misnames the rule was built
    for stay: gust 1078143's ``rolling_resistance`` goes from 15.2 to 9.9, refitted, against the
    nominal's 5.3 and a threshold of 5.4, and floor patch 6219142's ``friction_region`` from 37.0 to
    34.0 against 6.5 and 11.4 (docs/gap-findings.md, session 63; ``docs/bench-runs/dev-s63/tails_*.txt``).
    Only a window that the other bars would drop is refitted: two refits of at most about 130 rollouts each.
    """
    za = refitted_z(p.shooter, w, model.effect, params, p.sigma)
    return za <= max(z_thr, config.deepen_growth * refitted_z(p.shooter, w, None, None, p.sigma))
