"""The seed's three calibration routes and the batted-ball speed each predicts.

A *route* is a kind of ball data and the way a ball model is fitted to it:

* ``cor``: flat-wall COR and peak force (ASTM F1887 rig) -> ``run_calibration``;
* ``ccor``: CCOR, dynamic stiffness, peak force and contact time against the 2.63-in cylinder
  (the seed's Tables 5-8) -> ``run_calibration``;
* ``dma``: storage and loss moduli against frequency -> the closed-form Prony fit of
  :mod:`batball.calibrate.dma` (no impact run at all).

:func:`compare_routes` calibrates by every route given, runs the batted-ball-speed test with
each calibrated ball and tabulates the predictions. :func:`measure_synthetic` writes the data
of each route for a known "true" ball, so that what each route recovers can be checked against
the truth (docs/notes/calibration-routes.md).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from batball.calibrate.dma import DmaData, dma_ball, prony_moduli, write_dma_csv
from batball.calibrate.targets import Target, targets_toml
from batball.errors import SpecError
from batball.results.store import check_output_folder
from batball.specs import BallSpec, MaterialSpec
from batball.units import MPH, PSI

ROUTES = ("cor", "ccor", "dma")
#: The synthetic data set's speeds: flat wall at the ASTM F1887 60 mph and at 95 mph, the
#: cylinder at the seed's 95 and 110 mph; DMA at 21 frequencies, 10 Hz to 1 MHz (a master curve
#: of that span needs time-temperature superposition in a real lab).
SYNTHETIC_COR_MPH = (60.0, 95.0)
SYNTHETIC_CCOR_MPH = (95.0, 110.0)
SYNTHETIC_DMA_HZ = tuple(float(f) for f in np.logspace(1.0, 6.0, 21))
#: Times at which the routes' shear relaxation G(t) is compared (s): 0, 10, 100 us, 1 ms.
RELAXATION_TIMES = (0.0, 1e-5, 1e-4, 1e-3)
#: The DMA file of a foam truth: compression (tensile-type) moduli E', E''.
DMA_TENSILE = "dma-tensile.csv"


def shear_relaxation(material: MaterialSpec, times: Sequence[float]) -> np.ndarray:
    """G(t) [Pa] of a MAT_006 (G_inf + (G0 - G_inf) e^(-beta t), docs/physics.md section 1.1) or
    Prony material, the common measure the routes' different models are compared by."""
    from batball.materials.prony import relaxation_modulus

    t = np.asarray(times, dtype=np.float64)
    v = material.values
    if material.law == "mat006":
        return v["g_inf"] + (v["g0"] - v["g_inf"]) * np.exp(-v["beta"] * t)
    if material.law.startswith("prony"):
        return relaxation_modulus(v, t)
    raise SpecError("material.law", material.law, "mat006 or prony1-3 for a relaxation curve")


def exact_dma(truth: BallSpec, frequencies_hz: Sequence[float]) -> DmaData:
    """The exact shear storage and loss moduli of a Prony ball at ``frequencies_hz``."""
    v = truth.material.values
    if not truth.material.law.startswith("prony"):
        raise SpecError("truth.material.law", truth.material.law, "a prony1-3 ball")
    n = int(truth.material.law.removeprefix("prony"))
    moduli = np.array([v[f"g{i}"] for i in range(1, n + 1)])
    tau = np.array([1.0 / v[f"beta{i}"] for i in range(1, n + 1)])
    omega = 2.0 * math.pi * np.asarray(frequencies_hz, dtype=np.float64)
    storage, loss = prony_moduli(omega, v["g_inf"], moduli, tau)
    return DmaData(omega, storage, loss)


def _impact_targets(
    truth: BallSpec,
    test: str,
    speeds: Sequence[float],
    divisions: int,
    quantities: Sequence[tuple[str, str]],
) -> list[Target]:
    """Run ``test`` on ``truth`` at each speed [mph]; a target per (quantity name, measures
    key) and speed, holding the truth's measured value (SI)."""
    from batball.calibrate.evaluate import RunRequest, run_request

    targets = []
    for mph in speeds:
        outcome = run_request(RunRequest(truth, test, mph * MPH, divisions))
        if "measures" not in outcome:
            raise SpecError("truth", truth.name, f"a ball that rebounds ({outcome['error']})")
        for name, key in quantities:
            targets.append(Target(name, mph * MPH, float(outcome["measures"][key])))
    return targets


def measure_synthetic(
    truth: BallSpec,
    out_dir: Path,
    *,
    divisions: int = 8,
    bbs_runs: Mapping[float, float] | None = None,
    bbs_mesh: str = "",
) -> dict[str, Path]:
    """Measure ``truth`` with the virtual tests and write each route's data into ``out_dir``:
    ``cor-targets.toml`` (flat-wall COR and peak force at 60 and 95 mph), ``ccor-targets.toml``
    (CCOR, DS, peak force, contact time at 95 and 110 mph), both on a ``divisions`` ball mesh,
    and the DMA at :data:`SYNTHETIC_DMA_HZ`, psi: for a Prony truth ``dma.csv``, its exact
    shear moduli; for a foam truth ``dma-tensile.csv``, the compression E', E'' of the virtual
    DMA (:mod:`batball.calibrate.foam_dma`; read with ``--dma-modulus tensile``). ``bbs_runs``
    (speed mph -> BBS mph, the truth's own, on the bat mesh ``bbs_mesh`` says) go into
    ``bbs.toml``. Returns the paths by name; each file is written atomically."""
    from batball.results.store import write_text_atomic

    out_dir.mkdir(parents=True, exist_ok=True)
    cor = _impact_targets(
        truth, "cor", SYNTHETIC_COR_MPH, divisions,
        [("cor", "restitution"), ("wall_peak_force", "peak_force")],
    )  # fmt: skip
    ccor = _impact_targets(
        truth, "ccor", SYNTHETIC_CCOR_MPH, divisions,
        [("ccor", "restitution"), ("dynamic_stiffness", "dynamic_stiffness"),
         ("peak_force", "peak_force"), ("contact_time", "contact_time")],
    )  # fmt: skip
    note = f"synthetic data of the true ball {truth.name}, {divisions}-division ball mesh"
    paths = {
        "cor": out_dir / "cor-targets.toml",
        "ccor": out_dir / "ccor-targets.toml",
        "dma": out_dir / ("dma.csv" if truth.material.law.startswith("prony") else DMA_TENSILE),
        "bbs": out_dir / "bbs.toml",
    }
    write_text_atomic(paths["cor"], targets_toml(cor, "flat-wall COR route: " + note))
    write_text_atomic(paths["ccor"], targets_toml(ccor, "CCOR route: " + note))
    if truth.material.law.startswith("prony"):
        write_dma_csv(paths["dma"], exact_dma(truth, SYNTHETIC_DMA_HZ), unit="psi")
    else:
        from batball.calibrate.foam_dma import measure_foam_dma

        write_dma_csv(paths["dma"], measure_foam_dma(truth.material, SYNTHETIC_DMA_HZ))
    bbs = [f"# the true ball's batted-ball speed, {note}; bat {bbs_mesh}", ""]
    for mph, value in sorted((bbs_runs or {}).items()):
        bbs += ["[[bbs]]", f'speed = "{mph:g} mph"', f'value = "{value:.6g} mph"', ""]
    write_text_atomic(paths["bbs"], "\n".join(bbs))
    return paths


def load_measured_bbs(path: Path) -> dict[float, float]:
    """``[[bbs]]`` tables (speed, value with units) -> {inbound speed mph: BBS mph}."""
    import tomllib

    from batball.units import parse_quantity

    if not path.is_file():
        raise SpecError("measured-bbs", str(path), "an existing TOML file of [[bbs]] tables")
    rows = tomllib.loads(path.read_text(encoding="utf-8")).get("bbs", [])
    out = {}
    for i, row in enumerate(rows):
        speed = parse_quantity(row.get("speed", ""), "velocity", field=f"bbs[{i}].speed")
        value = parse_quantity(row.get("value", ""), "velocity", field=f"bbs[{i}].value")
        out[round(speed / MPH, 3)] = value / MPH
    if not out:
        raise SpecError("measured-bbs", str(path), "at least one [[bbs]] table")
    return out


@dataclass(frozen=True)
class RouteData:
    """The data of one route: impact ``targets`` (cor, ccor), or ``dma`` with the bulk modulus
    [Pa] it needs (None: the base ball's), or an already ``calibrated`` ball (reused as is)."""

    route: str
    targets: tuple[Target, ...] = ()
    dma: DmaData | None = None
    bulk_modulus: float | None = None
    calibrated: BallSpec | None = None
    source: str = ""


@dataclass(frozen=True)
class RouteOptions:
    """How the routes are run: the impact routes' ``model`` and optimiser budget, the DMA
    route's Prony terms, the study folder, the pool size."""

    model: str = "mat006"
    prony_terms: int = 3
    global_points: int = 8
    max_evaluations: int = 15
    divisions: int = 8
    study_dir: Path = Path("runs")
    workers: int | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Every value checked before a route runs."""
        from batball.materials.prony import MAX_PRONY_TERMS

        if self.model not in ("mat006", "prony1", "prony2", "prony3"):
            raise SpecError("model", self.model, "mat006, prony1, prony2 or prony3")
        if not 1 <= self.prony_terms <= MAX_PRONY_TERMS:
            raise SpecError("prony-terms", self.prony_terms, f"an integer 1..{MAX_PRONY_TERMS}")
        if self.global_points < 0:
            raise SpecError("global-points", self.global_points, "an integer >= 0 (0 skips it)")
        if self.max_evaluations < 1:
            raise SpecError("max-evaluations", self.max_evaluations, "an integer >= 1")
        if not 2 <= self.divisions <= 40:
            raise SpecError("divisions", self.divisions, "an integer 2..40 (12 = seed mesh)")
        if self.workers is not None and self.workers < 0:
            raise SpecError("workers", self.workers, "0 (this process) or a positive pool size")
        check_output_folder("runs-dir", self.study_dir)


def _impact_start(base: BallSpec, model: str) -> BallSpec:
    """The starting ball of an impact route: ``base`` in ``model`` (a MAT_006 base converts to
    Prony by :func:`~batball.materials.prony.prony_from_mat006`; a Prony base to MAT_006 with
    G0 = G(0), the same G_inf and the modulus-weighted mean beta)."""
    from batball.materials.prony import prony_from_mat006

    law, v = base.material.law, base.material.values
    if law == model:
        return base
    if law == "mat006" and model.startswith("prony"):
        values = prony_from_mat006(v, n_terms=int(model.removeprefix("prony")))
    elif law.startswith("prony") and model == "mat006":
        n = int(law.removeprefix("prony"))
        g = np.array([v[f"g{i}"] for i in range(1, n + 1)])
        beta = np.array([v[f"beta{i}"] for i in range(1, n + 1)])
        values = {
            "bulk_modulus": v["bulk_modulus"],
            "g0": v["g_inf"] + g.sum(),
            "g_inf": v["g_inf"],
            "beta": float((g * beta).sum() / g.sum()),
        }
    else:
        raise SpecError("model", model, f"mat006 or prony1-3 from a {law} ball")
    return dataclasses.replace(base, material=MaterialSpec(law=model, values=values))


def calibrate_route(
    base: BallSpec, data: RouteData, options: RouteOptions
) -> tuple[BallSpec, dict[str, Any]]:
    """The ball calibrated by one route and a JSON-able account of the fit."""
    from batball.calibrate.command import run_calibration
    from batball.calibrate.optimise import OptimiserOptions

    if data.calibrated is not None:
        return data.calibrated, {"reused": data.source}
    if data.route == "dma":
        assert data.dma is not None
        ball, fit = dma_ball(
            base,
            data.dma,
            n_terms=options.prony_terms,
            bulk_modulus=data.bulk_modulus,
            name=f"{base.name}-dma",
        )
        return ball, {"rms_relative_residual": fit.rms_relative, "rows": int(data.dma.omega.size)}
    start = _impact_start(base, options.model)
    start = dataclasses.replace(start, name=f"{base.name}-{data.route}")
    optimiser = OptimiserOptions(
        global_points=options.global_points,
        coarse_divisions=options.divisions,
        coarse_evaluations=options.max_evaluations,
        fine_divisions=None,
    )
    study = options.study_dir / f"routes-{base.name}-{data.route}-{options.model}.db"
    ball, summary = run_calibration(
        start, optimiser, study=study, targets=data.targets, workers=options.workers
    )
    return ball, {
        "targets": summary["targets"],
        "runs_computed": summary["runs_computed"],
        "study": summary["study"],
    }


def _material_report(material: MaterialSpec) -> dict[str, Any]:
    """A material's parameters (display units) and its G(t) at :data:`RELAXATION_TIMES`, psi."""
    from batball.units import to_unit

    law = material.material_law
    units = {p.name: p.display_unit for p in law.parameters}
    return {
        "law": material.law,
        "parameters": {
            k: f"{to_unit(v, units[k]):.5g} {units[k]}" for k, v in material.values.items()
        },
        "relaxation_psi": {
            f"{t * 1e6:g} us": float(g) / PSI
            for t, g in zip(
                RELAXATION_TIMES, shear_relaxation(material, RELAXATION_TIMES), strict=True
            )
        },
    }


def compare_routes(
    base: BallSpec,
    routes: Sequence[RouteData],
    options: RouteOptions,
    *,
    bat: Any,
    bbs_setup: Any,
    speeds_mph: Sequence[float],
    measured: Mapping[float, float],
    runs_dir: Path,
    truth: BallSpec | None = None,
) -> dict[str, Any]:
    """Calibrate by each route, run the BBS test of each calibrated ball at each speed (and the
    ``truth``'s, if given), and tabulate: the JSON-able comparison
    (docs/notes/calibration-routes.md). ``measured``: {speed mph: measured BBS mph} (may lack
    speeds)."""
    from batball.lab.bbs_run import run_bbs_test

    def bbs_of(ball: BallSpec) -> dict[str, float]:
        out = {}
        for mph in speeds_mph:
            setup = dataclasses.replace(bbs_setup, speed=mph * MPH)
            summary, _ = run_bbs_test(bat, ball, setup, runs_dir=runs_dir)
            out[f"{mph:g}"] = float(summary["bbs_mph"])
        return out

    report: dict[str, Any] = {
        "ball": base.name,
        "model": options.model,
        "divisions": options.divisions,
        "routes": [],
    }
    if truth is not None:
        report["truth"] = {
            "ball": truth.name,
            **_material_report(truth.material),
            "bbs_mph": bbs_of(truth),
        }
    for data in routes:
        ball, fit = calibrate_route(base, data, options)
        predicted = bbs_of(ball)
        errors = {s: predicted[s] - measured[float(s)] for s in predicted if float(s) in measured}
        report["routes"].append(
            {
                "route": data.route,
                "source": data.source,
                "fit": fit,
                **_material_report(ball.material),
                "bbs_mph": predicted,
                "bbs_error_mph": errors,
            }
        )
    report["measured_bbs_mph"] = {f"{k:g}": v for k, v in measured.items()}
    ranked = [
        (float(np.mean(np.abs(list(r["bbs_error_mph"].values())))), r["route"])
        for r in report["routes"]
        if r["bbs_error_mph"]
    ]
    report["best_route"] = min(ranked)[1] if ranked else None
    return report


__all__ = [
    "DMA_TENSILE",
    "RELAXATION_TIMES",
    "ROUTES",
    "SYNTHETIC_CCOR_MPH",
    "SYNTHETIC_COR_MPH",
    "SYNTHETIC_DMA_HZ",
    "RouteData",
    "RouteOptions",
    "calibrate_route",
    "compare_routes",
    "exact_dma",
    "load_measured_bbs",
    "measure_synthetic",
    "shear_relaxation",
]
