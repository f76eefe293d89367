"""Keyword decks run as the lab tests they describe (``batball run``).

:mod:`batball.lsdyna` reads a deck into the same models the lab tests build; this module runs them
with the tests' own runners and measurements, and summarises them with the same keys as the tests'
``--json``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from batball.errors import SpecError
from batball.lab.barrel import run_barrel_compression
from batball.lab.bbs import BbsResult, measure_bbs, run_bbs_model
from batball.lab.bbs_run import summarise_bbs
from batball.lab.compression import power_law_reading, run_compression_model
from batball.lab.impact import run_impact_model
from batball.lab.modal import shell_modes
from batball.lsdyna.bat_barrel import check_supports, mesh_sizes, options_from_deck, spec_from_deck
from batball.lsdyna.bat_bbs import read_bbs_deck
from batball.lsdyna.bat_model import BatDeck
from batball.lsdyna.model import DeckModel
from batball.models.barrel import build_barrel_model, compute_prestress
from batball.models.bbs import BbsSetup
from batball.solvers.explicit import (
    BALANCE,
)
from batball.units import IN, LBF, MPH, OZ


def run_deck(
    deck: DeckModel, *, threshold: float = 0.01, progress: Callable[[float], None] | None = None
) -> dict[str, Any]:
    """Run a deck read by :func:`read_deck` as its test; the summary names its units."""
    if deck.test == "compression":
        return run_compression_deck(deck, progress=progress)
    run, _, m = run_impact_model(deck.model, deck.controls, threshold, progress=progress)
    kinetic0 = 0.5 * run.mass * deck.speed**2
    return {
        "test": deck.test,
        "title": deck.title,
        deck.test: m.restitution,
        "inbound_mph": m.inbound_speed / MPH,
        "rebound_mph": m.rebound_speed / MPH,
        "ds_lbf_per_in": m.dynamic_stiffness / (LBF / IN),
        "peak_force_lbf": m.peak_force / LBF,
        "contact_time_ms": m.contact_time * 1e3,
        "ball_mass_oz": run.mass / OZ,
        "n_cells": deck.model.mesh.n_cells,
        "n_steps": len(run.time),
        "energy_balance_error": float(np.abs(run.energies[:, BALANCE]).max() / kinetic0),
        "wall_seconds": run.wall_seconds,
    }


def run_compression_deck(
    deck: DeckModel, *, samples: int = 201, progress: Callable[[float], None] | None = None
) -> dict[str, Any]:
    """Run a compression deck and read it as :func:`batball.lab.compression.run_compression`."""
    run, grid, force, difference, _, ratio, error = run_compression_model(
        deck.model, deck.controls, deck.speed, deck.displacement, samples, progress=progress
    )
    return {
        "test": "compression",
        "title": deck.title,
        "compression_lbf": float(force[-1]) / LBF,
        "compression_fit_lbf": power_law_reading(grid, force, deck.displacement) / LBF,
        "displacement_in": deck.displacement / IN,
        "rate_in_per_min": deck.speed / IN * 60.0,
        "plate_force_difference_fraction": float(abs(difference[-1]) / max(force[-1], 1e-300)),
        "kinetic_to_internal_energy": ratio,
        "energy_balance_error": error,
        "n_cells": deck.model.mesh.n_cells,
        "n_steps": len(run.time),
        "wall_seconds": run.wall_seconds,
    }


def run_barrel_deck(bat: BatDeck) -> dict[str, Any]:
    """Run a barrel deck as ``batball barrel`` runs the spec (one orientation)."""
    spec = spec_from_deck(bat)
    options, orientation = options_from_deck(bat, spec)
    model = build_barrel_model(spec, **mesh_sizes(bat), penalty_factor=options.penalty_factor)
    check_supports(bat, model, options, orientation)
    result = run_barrel_compression(model, compute_prestress(model), options)
    return {
        "test": "barrel",
        "title": bat.title,
        "orientation_deg": orientation,
        "preload_lbf": float(result.preloads()[0]) / LBF,
        "final_load_lbf": float(result.final_loads()[0]) / LBF,
        "n_shells": bat.mesh.n_cells,
    }


def run_bbs_deck(bat: BatDeck, *, separation_time: float = BbsSetup.separation_time,
                 precision: str = BbsSetup.precision) -> dict[str, Any]:  # fmt: skip
    """Run a bbs deck as ``batball bbs`` runs its specs; the same summary keys (no run folder),
    with the deck's pivot."""
    start = time.perf_counter()
    read = read_bbs_deck(bat, separation_time=separation_time, precision=precision)
    run = run_bbs_model(read.model, read.setup)
    result = BbsResult(read.bat, read.ball, read.setup, read.model, run,
                       measure_bbs(read.model, run, read.setup))  # fmt: skip
    summary = summarise_bbs(result, time.perf_counter() - start)
    summary.update(title=bat.title, pivot_from_knob_in=read.setup.pivot_from_knob / IN,
                   pivot_band_nodes=int(read.model.coupled.bat.band.size),
                   pivot_offset_from_band_centre_in=read.band_offset / IN)  # fmt: skip
    return summary


def run_modal_deck(bat: BatDeck) -> dict[str, Any]:
    """Free-free modes of a modal deck, summarised as ``batball modal`` summarises them."""
    if bat.test != "modal":
        raise SpecError(
            "deck",
            bat.test,
            "a modal deck (barrel and bbs decks run through batball.lsdyna.bat_barrel and "
            "batball.lsdyna.bat_bbs, see docs/lsdyna.md)",
        )
    modes = shell_modes(bat.mesh, bat.section(), circumferential=bat.circumferential,
                        n_modes=bat.n_modes)  # fmt: skip
    bending, hoop = modes.first("bending"), modes.first("hoop")
    return {
        "test": "modal",
        "title": bat.title,
        "bending_hz": [float(modes.frequencies[i]) for i in bending],
        "hoop_hz": [float(modes.frequencies[i]) for i in hoop],
        "frequencies_hz": [float(f) for f in modes.frequencies],
        "labels": list(modes.labels),
        "n_shells": bat.mesh.n_cells,
    }
