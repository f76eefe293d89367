"""Seeded measurement noise on a synthetic route data set.

The synthetic data of :func:`batball.calibrate.routes.measure_synthetic` are exact: the truth's
own virtual-test results and its exact DMA moduli. A lab's are not. :func:`write_noisy_data`
reads an exact data folder and writes a copy whose targets and DMA moduli carry Gaussian noise
of stated standard deviations (:class:`NoiseLevels`), drawn from ``numpy.random.default_rng``
with a given seed, so that a draw is reproducible and the spread of what each route recovers
over a few draws can be measured (docs/notes/calibration-routes.md, "Measurement noise").

The default levels are *assumed* lab repeatabilities (one standard deviation); no published
precision statement for ASTM F1887 (COR), F2845 (CCOR, DS) or a DMA master curve was found:

* COR and CCOR: 0.005 absolute (speed gates resolve ~0.3 % of the speeds; ball-to-ball scatter
  of a dozen of one model is of that order);
* dynamic stiffness, peak force (cylinder and flat wall): 2.5 % relative (load-cell calibration
  and the ball's orientation at impact);
* contact time: 2.5 % relative (read from the same force trace);
* DMA storage and loss moduli: 5 % relative each, independently (specimen geometry and
  clamping dominate a DMA's absolute modulus).

The measured BBS (``bbs.toml``) is copied unchanged: it is the reference each route's error is
measured against, so that the spread seen is the calibrations' alone.
"""

from __future__ import annotations

import dataclasses
import shutil
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from batball.calibrate.dma import DmaData, load_dma_csv, write_dma_csv
from batball.calibrate.targets import Target, load_targets, targets_toml
from batball.errors import SpecError

#: Target quantities whose noise is absolute (a restitution); the others' is relative.
ABSOLUTE_QUANTITIES = frozenset({"cor", "ccor"})
#: The data files of a route folder, in the order their noise is drawn.
TARGET_FILES = ("cor-targets.toml", "ccor-targets.toml")
#: The DMA files: shear moduli (a Prony truth's) or compression E', E'' (a foam truth's).
DMA_FILES = ("dma.csv", "dma-tensile.csv")
BBS_FILE = "bbs.toml"


@dataclass(frozen=True)
class NoiseLevels:
    """One standard deviation of each measurement's noise.

    Attributes:
        restitution: COR and CCOR, absolute [-].
        force: dynamic stiffness, peak force and flat-wall peak force, relative [-].
        contact_time: contact time, relative [-].
        dma: each DMA storage and loss modulus, relative [-].
    """

    restitution: float = 0.005
    force: float = 0.025
    contact_time: float = 0.025
    dma: float = 0.05

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if not (np.isfinite(value) and 0.0 <= value < 0.5):
                raise SpecError(f"noise.{f.name}", value, "a standard deviation 0 <= sd < 0.5")

    def standard_deviation(self, quantity: str) -> float:
        """The sd of a target ``quantity`` (absolute for COR/CCOR, else relative)."""
        if quantity in ABSOLUTE_QUANTITIES:
            return self.restitution
        if quantity == "contact_time":
            return self.contact_time
        return self.force


def perturb_targets(
    targets: Sequence[Target], levels: NoiseLevels, rng: np.random.Generator
) -> tuple[Target, ...]:
    """``targets`` with one Gaussian draw each, in order: value + sd z (COR, CCOR) or
    value (1 + sd z) (the others); a draw that would not be positive is a SpecError."""
    out = []
    for target in targets:
        z = float(rng.standard_normal())
        sd = levels.standard_deviation(target.quantity)
        if target.quantity in ABSOLUTE_QUANTITIES:
            value = target.value + sd * z
        else:
            value = target.value * (1.0 + sd * z)
        if not value > 0.0:
            raise SpecError(f"noise.{target.quantity}", value, "a positive noisy value")
        out.append(dataclasses.replace(target, value=value))
    return tuple(out)


def perturb_dma(data: DmaData, level: float, rng: np.random.Generator) -> DmaData:
    """``data`` with relative Gaussian noise of sd ``level`` on every storage, then every loss
    modulus; a loss modulus is kept >= 0 (a passive material's)."""
    n = data.omega.size
    storage = data.storage * (1.0 + level * rng.standard_normal(n))
    loss = data.loss * (1.0 + level * rng.standard_normal(n))
    if np.any(storage <= 0.0):
        raise SpecError("noise.dma", level, "a level that keeps every storage modulus positive")
    return DmaData(data.omega.copy(), storage, np.maximum(loss, 0.0))


def write_noisy_data(
    source_dir: Path, out_dir: Path, *, seed: int, levels: NoiseLevels
) -> dict[str, Path]:
    """Copy the route data of ``source_dir`` into ``out_dir`` with seeded noise.

    Draw order (one ``default_rng(seed)``): the targets of ``cor-targets.toml``, then of
    ``ccor-targets.toml`` (file order), then the DMA storage, then loss moduli (``dma.csv`` or
    ``dma-tensile.csv``). Files absent
    from ``source_dir`` are skipped (their draws too); ``bbs.toml`` is copied as is. Every file
    is written atomically. Returns the written paths by name (``cor``, ``ccor``, ``dma``,
    ``bbs``, ``noise``: a TOML of the seed and levels).
    """
    from batball.results.store import atomic_path, write_text_atomic

    if not source_dir.is_dir():
        raise SpecError("noise.source", str(source_dir), "a folder of synthetic route data")
    rng = np.random.default_rng(seed)
    note = f"with seeded noise (seed {seed}, {levels}) on the data of {source_dir.as_posix()}"
    paths: dict[str, Path] = {}
    for name in TARGET_FILES:
        if (source_dir / name).is_file():
            noisy = perturb_targets(load_targets(source_dir / name), levels, rng)
            paths[name.split("-")[0]] = out_dir / name
            write_text_atomic(out_dir / name, targets_toml(noisy, name + " " + note))
    for name in DMA_FILES:
        if (source_dir / name).is_file():
            # read as is: the noise is relative, whether the moduli are G or E
            exact = load_dma_csv(source_dir / name, modulus="shear")
            paths["dma"] = out_dir / name
            write_dma_csv(paths["dma"], perturb_dma(exact, levels.dma, rng), unit="psi")
    if (source_dir / BBS_FILE).is_file():
        paths["bbs"] = out_dir / BBS_FILE
        with atomic_path(paths["bbs"]) as tmp:
            shutil.copyfile(source_dir / BBS_FILE, tmp)
    record = [f"# {note}", f"seed = {seed}"]
    record += [f"{f.name} = {getattr(levels, f.name)!r}" for f in dataclasses.fields(levels)]
    paths["noise"] = out_dir / "noise.toml"
    write_text_atomic(paths["noise"], "\n".join(record) + "\n")
    return paths


__all__ = [
    "ABSOLUTE_QUANTITIES",
    "NoiseLevels",
    "perturb_dma",
    "perturb_targets",
    "write_noisy_data",
]
