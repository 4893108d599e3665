"""h of a system with impacts is conserved between them; what an impact does to it is decided
at the coefficient of restitution given (Newton's law: the rebound speed is e times the
approach speed, so the kinetic energy of the approach keeps the fraction e^2)."""

from __future__ import annotations

import lagrangian as lg


def test_a_bouncing_ball_keeps_h_between_impacts_and_loses_energy_at_each_when_e_lt_1() -> None:
    report = lg.analyze(lg.examples.bouncing_ball())
    assert report.energy is not None and report.energy.conserved
    assert "between impacts and transitions only" in report.energy.reason
    assert "an impact on 'floor' (constraints[0]) (e = 0.8) loses energy" in report.energy.reason


def test_an_elastic_ball_keeps_h_through_its_impacts_too() -> None:
    report = lg.analyze(lg.examples.bouncing_ball(), parameters={"e": 1})
    assert report.energy is not None
    assert "an impact on 'floor' (constraints[0]) (e = 1) keeps it too" in report.energy.reason


def test_a_system_without_impacts_has_no_such_note() -> None:
    report = lg.analyze(lg.examples.simple_pendulum())
    assert report.energy is not None and "between impacts" not in report.energy.reason


def test_the_text_writes_a_unilateral_constraint_as_its_inequality() -> None:
    from lagrangian.render.analysis_text import analysis_text

    text = analysis_text(lg.analyze(lg.examples.bouncing_ball()))
    assert "\n  y >= 0: unilateral: the inequality" in text
    assert "y = 0:" not in text  # not an equation, nor its kind said twice


def test_impacts_of_one_coefficient_are_said_once_for_all_their_constraints() -> None:
    # the default gas: 4 disks, 16 walls and 6 pairs, all elastic
    report = lg.analyze(lg.examples.hard_disk_gas())
    assert report.energy is not None
    assert (
        report.energy.reason.count("impacts on") == 1 and "an impact on" not in report.energy.reason
    )
    assert "impacts on the 22 constraints 'left1' (constraints[0]), " in report.energy.reason
    assert "and 16 more (e = 1) keep it too" in report.energy.reason
