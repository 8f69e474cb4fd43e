"""Biocontrol time profiles of the movement manners (seed 000, 4.5)."""

from __future__ import annotations

import numpy as np
import pytest

from motor.trajectory.biocontrol import (
    JERK_PIECES,
    MANNERS,
    Manner,
    integrate_manner,
    jerk_bound,
    minimum_jerk,
    movement_duration,
    profile,
)

U = np.linspace(0.0, 1.0, 2001)


def peak(name: str) -> float:
    return float(U[np.argmax(profile(name).rate(U))])


@pytest.mark.parametrize("name", sorted(MANNERS))
def test_every_profile_is_monotone_from_zero_to_one(name: str) -> None:
    f = profile(name).fraction(U)
    assert f[0] == 0.0 and f[-1] == 1.0
    assert np.all(np.diff(f) >= 0.0)
    assert np.all(np.isfinite(profile(name).rate(U)))
    np.testing.assert_allclose(profile(name).fraction(np.array([-1.0, 2.0])), [0.0, 1.0])


@pytest.mark.parametrize("name", sorted(MANNERS))
def test_rate_is_the_derivative_of_the_fraction(name: str) -> None:
    p = profile(name)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (p.rate(U)[1:] + p.rate(U)[:-1]) * np.diff(U))])
    np.testing.assert_allclose(integral, p.fraction(U), atol=5e-3)


@pytest.mark.parametrize("name", sorted(MANNERS))
def test_every_profile_starts_and_stops_at_rest_with_zero_acceleration(name: str) -> None:
    p = profile(name)
    h = 1.0 / (p.rates.size - 1)
    assert p.rate(0.0) == pytest.approx(0.0, abs=1e-12) and p.rate(1.0) == pytest.approx(0.0, abs=1e-12)
    start_acceleration = (p.rate(h) - p.rate(0.0)) / h
    stop_acceleration = (p.rate(1.0) - p.rate(1.0 - h)) / h
    peak_acceleration = np.max(np.abs(np.diff(p.rates))) / h
    assert abs(start_acceleration) < 0.02 * peak_acceleration
    assert abs(stop_acceleration) < 0.02 * peak_acceleration


def accelerations(name: str) -> np.ndarray:
    return np.gradient(profile(name).rate(U), U)


def test_targetted_peaks_late_and_stops_sharply() -> None:
    assert peak("targetted") > 0.55
    a = accelerations("targetted")
    assert -a.min() > 1.2 * a.max(), "targetted stops more steeply than it starts"
    assert -a.min() > -accelerations("lax").min(), "targetted ends more suddenly than lax"


def test_lax_peaks_near_the_middle_and_gets_going_sooner() -> None:
    assert peak("lax") == pytest.approx(0.5, abs=0.1)
    assert profile("lax").fraction(0.5) > profile("targetted").fraction(0.5) + 0.1


def test_linear_is_near_constant_in_the_middle() -> None:
    middle = (U >= 0.25) & (U <= 0.75)
    speed = profile("linear").rate(U[middle])
    assert speed.min() / speed.max() > 0.8
    np.testing.assert_allclose(profile("linear").fraction(0.5), 0.5, atol=0.03)


@pytest.mark.parametrize("name", ["hard_contact", "sudden_stop"])
def test_abrupt_manners_peak_late_and_stop_steeply(name: str) -> None:
    assert peak(name) > 0.55
    a = accelerations(name)
    assert -a.min() > 1.05 * a.max()


@pytest.mark.parametrize("name", sorted(MANNERS))
def test_jerk_stays_within_the_bound(name: str) -> None:
    """The jerk is constant on each of JERK_PIECES pieces, bounded at the piece's middle."""
    p = profile(name)
    h = 1.0 / (p.fractions.size - 1)
    middles = (np.arange(JERK_PIECES) + 0.5) / JERK_PIECES
    inside = np.linspace(0.0, 1.0, p.fractions.size)[:-3] + 1.5 * h
    piece_of = np.minimum((inside * JERK_PIECES).astype(int), JERK_PIECES - 1)
    jerk = np.diff(p.fractions, 3) / h**3
    same_piece = piece_of == np.minimum(((inside + 1.5 * h) * JERK_PIECES).astype(int), JERK_PIECES - 1)
    same_piece &= piece_of == ((inside - 1.5 * h) * JERK_PIECES).astype(int)
    assert np.all(np.abs(jerk[same_piece]) <= 1.02 * jerk_bound(middles[piece_of[same_piece]]))


def sampled_jerk(fractions: np.ndarray, frames: int) -> float:
    """Peak third difference of a rest-to-rest profile sampled on ``frames`` intervals,
    with two still frames before and after (a start from rest counts its first jerk)."""
    u = np.linspace(0.0, 1.0, frames + 1)
    s = np.interp(u, np.linspace(0.0, 1.0, fractions.size), fractions)
    return float(np.abs(np.diff(np.concatenate([[0.0, 0.0], s, [1.0, 1.0]]), 3)).max())


@pytest.mark.parametrize("frames", [12, 18, 24, 31, 41, 60, 96])
@pytest.mark.parametrize("name", sorted(MANNERS))
def test_sampled_jerk_is_within_one_and_a_half_of_minimum_jerk(name: str, frames: int) -> None:
    """What a viewer's 60 fps sees of a 0.2–1.6 s movement: jerk ≤ 1.5 × minimum jerk's."""
    assert sampled_jerk(profile(name).fractions, frames) <= 1.5 * sampled_jerk(minimum_jerk().fractions, frames)


def test_profiles_are_cached() -> None:
    assert profile("lax") is profile("lax")


def test_minimum_jerk_is_symmetric() -> None:
    p = minimum_jerk()
    np.testing.assert_allclose(p.fraction(U) + p.fraction(1.0 - U)[...], 1.0, atol=1e-6)
    assert float(U[np.argmax(p.rate(U))]) == pytest.approx(0.5, abs=1e-3)


def test_durations_by_movement_kind_and_manner() -> None:
    straight, curved, circle = (movement_duration(kind) for kind in ("straight", "curved", "circle"))
    assert straight < curved < circle
    assert movement_duration("straight", "fast") < straight < movement_duration("straight", "slow")
    assert movement_duration("straight", "tense") > straight


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: profile("wobbly"), "unknown manner 'wobbly'"),
        (lambda: movement_duration("spiral"), "unknown movement kind 'spiral'"),
        (lambda: movement_duration("straight", "wobbly"), "unknown manner"),
        (lambda: Manner("bad", ratio=-1.0), "manner 'bad'"),
        (lambda: Manner("bad", duration_scale=0.0), "duration_scale"),
    ],
)
def test_bad_manners_are_named(call, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        call()


def test_a_custom_manner_integrates() -> None:
    underdamped = integrate_manner(Manner("custom", ratio=1.0, growth=0.0, sharpness=1.0, truncate=True))
    assert underdamped.fractions[-1] == 1.0 and np.all(np.diff(underdamped.fractions) >= 0)
