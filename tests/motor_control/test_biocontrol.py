"""Biocontrol time profiles of the movement manners (seed 000, 4.5)."""

from __future__ import annotations

import numpy as np
import pytest

from motor.trajectory.biocontrol import (
    END_SMOOTHING,
    MANNERS,
    Manner,
    integrate_manner,
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


#: Where the stop begins: the speed there is what the last tenth of the movement brings to rest.
STOPPING = 1.0 - END_SMOOTHING


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


def test_targetted_peaks_late_and_stops_sharply() -> None:
    assert peak("targetted") > 0.6
    targetted, lax = profile("targetted"), profile("lax")
    assert targetted.rate(STOPPING) > lax.rate(STOPPING), "targetted ends more suddenly than lax"


def test_lax_peaks_near_the_middle_with_a_sharper_start() -> None:
    assert peak("lax") == pytest.approx(0.5, abs=0.1)
    early = np.array([0.02])
    assert profile("lax").rate(early)[0] > profile("targetted").rate(early)[0]


def test_linear_is_near_constant_in_the_middle() -> None:
    middle = (U >= 0.1) & (U <= 0.9)
    speed = profile("linear").rate(U[middle])
    assert speed.min() / speed.max() > 0.97
    np.testing.assert_allclose(profile("linear").fraction(0.5), 0.5, atol=0.03)


def test_hard_contact_and_sudden_stop_end_more_suddenly_than_targetted() -> None:
    end = profile("targetted").rate(STOPPING)
    assert profile("hard_contact").rate(STOPPING) > end
    assert profile("sudden_stop").rate(STOPPING) > profile("hard_contact").rate(STOPPING)
    assert peak("hard_contact") > peak("targetted")


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
