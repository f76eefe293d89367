"""The stored interference fit (lab/fit_store.py, LS-DYNA's drdisp): a run that restores the
fit must be the run that relaxed it, a different bat model must not reuse it, and a damaged
store is relaxed again rather than trusted."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from batball.lab.bbs import run_bbs
from batball.lab.fit_store import FIT_FILE, capture_fit, restore_fit
from batball.models.bbs import BbsSetup, build_bbs_model
from batball.specs import load_ball_spec, load_bat_spec

IN = 0.0254
# coarse ball and bat: the store's plumbing, not the seed's numbers
SETUP = BbsSetup(ball_divisions=4, circumferential=8, axial_size=1.0 * IN)


def fit_folders(root: Path) -> list[Path]:
    return sorted(root.glob("fit-*"))


@pytest.fixture(scope="module")
def bat_and_ball():
    return load_bat_spec("default"), load_ball_spec("type2")


def test_a_restored_fit_reproduces_the_relaxed_run(tmp_path: Path, bat_and_ball) -> None:
    bat, ball = bat_and_ball
    fresh = run_bbs(bat, ball, SETUP, store=tmp_path)
    assert not fresh.run.prestress_reused
    assert len(fit_folders(tmp_path)) == 1
    again = run_bbs(bat, ball, SETUP, store=tmp_path)
    assert again.run.prestress_reused
    # the same state, so the same run to round-off (the only difference is where the state
    # came from): every history column, the fit's pressure and its settling measure
    np.testing.assert_allclose(again.run.history, fresh.run.history, rtol=1e-12, atol=1e-12)
    assert again.run.interference_pressure == pytest.approx(fresh.run.interference_pressure,
                                                           rel=1e-12)  # fmt: skip
    assert again.run.prestress_kinetic_ratio == fresh.run.prestress_kinetic_ratio
    # without reuse the fit is relaxed again
    assert not run_bbs(bat, ball, SETUP, store=tmp_path, reuse=False).run.prestress_reused


def test_another_bat_model_relaxes_its_own_fit(tmp_path: Path, bat_and_ball) -> None:
    bat, ball = bat_and_ball
    run_bbs(bat, ball, SETUP, store=tmp_path)
    # the ball's speed does not touch the bat: same fit
    assert run_bbs(bat, ball, replace(SETUP, speed=40.0), store=tmp_path).run.prestress_reused
    # no mass scaling: lighter shells relax along another path, a new fit
    other = replace(SETUP, mass_scaling=None)
    assert build_bbs_model(bat, ball, other).coupled.bat.mass.sum() \
        < build_bbs_model(bat, ball, SETUP).coupled.bat.mass.sum()
    assert not run_bbs(bat, ball, other, store=tmp_path).run.prestress_reused
    assert len(fit_folders(tmp_path)) == 2


def test_a_damaged_store_is_relaxed_again(tmp_path: Path, bat_and_ball) -> None:
    bat, ball = bat_and_ball
    fresh = run_bbs(bat, ball, SETUP, store=tmp_path)
    (folder,) = fit_folders(tmp_path)
    data = (folder / FIT_FILE).read_bytes()
    (folder / FIT_FILE).write_bytes(data[: len(data) // 2])  # an interrupted copy
    again = run_bbs(bat, ball, SETUP, store=tmp_path)
    assert not again.run.prestress_reused
    assert again.run.interference_pressure == pytest.approx(fresh.run.interference_pressure,
                                                           rel=1e-12)  # fmt: skip


def test_restore_refuses_arrays_of_another_shape() -> None:
    from batball.contact.segments import SegmentContact
    from batball.elements.shell_bt import ShellForceState

    state = ShellForceState(np.array([0, 2]), np.zeros((1, 8)), 1)
    pair = SegmentContact("p", np.arange(3), np.zeros(3), np.ones(3), np.array([[0, 1, 2, 3]]),
                          np.zeros(1), two_sided=False, depth=0.0, margin=0.0)  # fmt: skip
    points = np.zeros((4, 3))
    stored = capture_fit(points + 1.0, state, [pair])
    assert restore_fit(stored, points, state, [pair])
    assert points[0, 0] == 1.0
    stored["points"] = np.zeros((5, 3))
    points[:] = 7.0
    assert not restore_fit(stored, points, state, [pair])
    assert np.all(points == 7.0)  # nothing changed
