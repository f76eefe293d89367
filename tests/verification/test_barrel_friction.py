"""Coulomb friction between insert and barrel in the barrel compression (lab/barrel,
solvers/static_contact.solve_frictional_step) against two independent routes on a coarse bat:
with mu = 0 it is the frictionless contact solve (the condensed one of `compress_barrel`), and
with mu so large that every pair sticks it is, while every pair is pressed, a linear solve with
the stick springs as glue (the active-set solver with one more, two-sided, gap set). A finite
mu lies between the two.
The closed-form slider checks of the friction law itself are in
tests/unit/solvers/test_static_friction.py."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from batball.contact.shell_contact import PenaltyGaps
from batball.lab.barrel import (
    compress_barrel,
    compress_barrel_with_friction,
    insert_friction,
    run_barrel_compression,
    with_platen_friction,
)
from batball.models.barrel import (
    BarrelTestOptions,
    build_barrel_model,
    compression_supports,
    compute_prestress,
    platen_gaps,
)
from batball.solvers.static_contact import solve_static_contact
from batball.specs import load_bat_spec

IN = 0.0254
OPTIONS = BarrelTestOptions(preload_steps=2, final_steps=2)


@pytest.fixture(scope="module")
def coarse():  # noqa: ANN201
    model = build_barrel_model(load_bat_spec("default"), circumferential=8, axial_size=1.0 * IN)
    return model, compute_prestress(model)


def test_without_friction_it_is_the_frictionless_solve(coarse) -> None:  # noqa: ANN001
    model, prestress = coarse
    frictionless = compress_barrel(model, prestress, OPTIONS, 0.0, curve=True)
    with_zero = compress_barrel_with_friction(model, prestress, OPTIONS, 0.0, 0.0)
    np.testing.assert_allclose(with_zero.force, frictionless.force, rtol=1e-6)


def test_when_every_pair_sticks_it_is_the_glued_linear_solve(coarse) -> None:  # noqa: ANN001
    model, prestress = coarse
    stuck = compress_barrel_with_friction(model, prestress, OPTIONS, 0.0, 1e6)
    # the glue: the stick springs k_t (T u - xi) with xi the slips of the fit under the
    # compression's supports, as a two-sided gap set of the frictionless active-set solver
    friction = insert_friction(model, 1e6)
    fixed, springs = compression_supports(model, OPTIONS, 0.0)
    fit = dataclasses.replace(model.interference, bilateral=True)
    forces = []
    for k, travel in enumerate(OPTIONS.travels(curve=True)):
        top, bottom = platen_gaps(model, OPTIONS, 0.0, travel, prestress.u)
        held = bottom.initial <= bottom.initial.min() + 1e-12
        rest = dataclasses.replace(bottom, stiffness=np.where(held, 0, bottom.stiffness))
        holder = dataclasses.replace(bottom, stiffness=np.where(held, bottom.stiffness, 0),
                                     bilateral=True)  # fmt: skip
        sets = [fit, top, rest, holder, springs]
        if k == 0:
            start = platen_gaps(model, OPTIONS, 0.0, 0.0, prestress.u)
            at_rest = [fit, start[0], sets[2], sets[3], springs]
            u0 = solve_static_contact(model.stiffness, at_rest, fixed_dofs=fixed).u
            anchor = friction.slip(u0)
        glue = [PenaltyGaps(rows, -anchor[:, d], friction.stiffness, bilateral=True)
                for d, rows in enumerate(friction.slips)]  # fmt: skip
        solution = solve_static_contact(model.stiffness, [*sets, *glue], fixed_dofs=fixed)
        forces.append(-(solution.forces[1] * (top.matrix @ np.tile([0, 1, 0, 0, 0, 0],
                                                                    model.mesh.n_points))).sum())
    # exact while every fit pair is pressed (the first level); further on the squeeze pulls some
    # pairs apart, and a pair in tension has no friction where the glue still holds it
    assert stuck.force[0] == pytest.approx(forces[0], rel=1e-6)
    assert np.all(stuck.force[1:] < np.array(forces[1:]))


def test_friction_lies_between_sliding_and_sticking(coarse) -> None:  # noqa: ANN001
    model, prestress = coarse
    loads = [compress_barrel_with_friction(model, prestress, OPTIONS, 0.0, mu).force
             for mu in (0.0, 0.2, 1e6)]  # fmt: skip
    assert np.all(loads[0] < loads[1]) and np.all(loads[1] < loads[2])



@pytest.fixture(scope="module")
def finer():  # noqa: ANN201
    """32 around and 0.2-in rings: more than one node under each platen at 0.07 in."""
    model = build_barrel_model(load_bat_spec("default"), circumferential=32, axial_size=0.2 * IN)
    return model, compute_prestress(model)


def test_sticking_platens_are_the_glued_solve_with_the_platens_sliding_motion(finer) -> None:  # noqa: ANN001
    """Platen friction (lab/barrel.with_platen_friction) with every touching pair sticking, in
    one step of 0.07 in, equals the frictionless active-set solve with two-sided glue springs
    on the pairs that touch: k_t (s0 + T u - xi), s0 the platen's own tangential motion (it
    moves along the load, not along the tilted normals), xi the slips before the step. The
    force read includes the glue's share along the load in both."""
    model, prestress = finer
    protocol = BarrelTestOptions(preload_steps=1, final_steps=1, preload_travel=0.07 * IN,
                                 final_travel=0.001 * IN)  # fmt: skip
    stuck = compress_barrel_with_friction(model, prestress, protocol, 0.0, 0.0, platen_mu=1e6)
    fixed, springs = compression_supports(model, protocol, 0.0)
    friction = with_platen_friction(model, protocol, 0.0, insert_friction(model, 0.0), 1e6)
    fit = dataclasses.replace(model.interference, bilateral=True)

    def sets(travel: float) -> list[PenaltyGaps]:
        top, bottom = platen_gaps(model, protocol, 0.0, travel, prestress.u)
        held = bottom.initial <= bottom.initial.min() + 1e-12
        rest = dataclasses.replace(bottom, stiffness=np.where(held, 0, bottom.stiffness))
        holder = dataclasses.replace(bottom, stiffness=np.where(held, bottom.stiffness, 0),
                                     bilateral=True)  # fmt: skip
        return [fit, top, rest, holder, springs]

    anchor = friction.slip(solve_static_contact(model.stiffness, sets(0.0), fixed_dofs=fixed).u)
    travel = 0.07 * IN
    level = sets(travel)
    n_insert, n_top = model.insert_nodes.size, level[1].n_gaps
    translation = np.tile([0.0, 1.0, 0.0, 0.0, 0.0, 0.0], model.mesh.n_points)  # the load
    cosines = np.column_stack([rows @ translation for rows in friction.slips])
    moved = np.zeros_like(anchor)
    moved[n_insert:n_insert + n_top] = travel * cosines[n_insert:n_insert + n_top]

    def glued(touching: np.ndarray):  # noqa: ANN202
        glue = [PenaltyGaps(rows[touching], (moved - anchor)[touching, d],
                            friction.stiffness[touching], bilateral=True)
                for d, rows in enumerate(friction.slips)]  # fmt: skip
        return solve_static_contact(model.stiffness, [*level, *glue], fixed_dofs=fixed)

    def touching_of(solution) -> np.ndarray:  # noqa: ANN001
        pressed = np.zeros(friction.stiffness.size, bool)
        pressed[n_insert:] = np.concatenate([solution.forces[1],
                                             solution.forces[2] + solution.forces[3]]) > 0.0
        return pressed

    touching = touching_of(glued(np.zeros(friction.stiffness.size, bool)))
    solution = glued(touching)
    assert np.array_equal(touching_of(solution), touching)  # the glue kept the same contact
    top = np.zeros_like(touching)
    top[n_insert:n_insert + n_top] = True
    force = -(solution.forces[1] * (level[1].matrix @ translation)).sum() - sum(
        (solution.forces[5 + d] * cosines[touching, d])[top[touching]].sum() for d in range(2))
    assert touching[top].sum() >= 2 and touching[~top].sum() >= 2
    assert np.abs(moved[touching & top]).max() > 0.01 * travel  # a point off the apex slides
    assert stuck.force[0] == pytest.approx(force, rel=1e-6)


def test_the_bats_own_insert_friction_is_the_tests_default(coarse) -> None:  # noqa: ANN001
    """A bat file's ``[insert] friction`` is what the test runs with when no ``friction`` option
    is given: the same curve as that coefficient passed to the frictional solve (two routes to
    one computation; 1e-9 for round-off), and a given option overrides it."""
    model, prestress = coarse
    rubbing = dataclasses.replace(model.spec, insert=dataclasses.replace(model.spec.insert,
                                                                         friction=0.2))
    model_mu = dataclasses.replace(model, spec=rubbing)
    one = dataclasses.replace(OPTIONS, orientations_deg=(0.0,))
    by_bat = run_barrel_compression(model_mu, prestress, one).curves[0].force
    direct = compress_barrel_with_friction(model, prestress, one, 0.0, 0.2).force
    np.testing.assert_allclose(by_bat, direct, rtol=1e-9)
    assert one.for_bat(rubbing).insert_friction == 0.2
    assert dataclasses.replace(one, friction=0.0).for_bat(rubbing).insert_friction == 0.0
