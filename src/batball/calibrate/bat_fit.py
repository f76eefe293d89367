"""Fit chosen bat parameters to measurements: mass properties (seed Table 1), free-free modes
(Table 3), or both together.

A free parameter is named as the user types it:

* ``lumped_mass:<part>``: the lumped (non-structural) mass of a part, e.g. ``lumped_mass:endcap``;
* ``thickness:<label>``: the common thickness of every ply labelled ``<label>`` in the layups,
  e.g. ``thickness:handle-glass``;
* ``angle:<label>``: the common fibre (braid half-) angle of those plies, e.g.
  ``angle:barrel-carbon``;
* ``friction:insert``: the Coulomb coefficient of the insert's interface with the barrel
  (``InsertSpec.friction``: 0 slides, about 5 and more sticks, the limit of a bonded insert),
  which only the tests that load the insert see (:class:`BarrelTargets`).

``thickness`` and ``angle`` may be restricted to some parts: ``angle:barrel-carbon@barrel-1+
barrel-2+barrel-3+endcap`` changes the labelled plies of those four parts only (``insert`` names
the insert's layup). A braid laid on a mandrel of varying diameter changes its angle with the
diameter, so the barrel's braid angle need not be the taper's.

Three kinds of target (:class:`MassTargets`, :class:`ModalTargets`: bending and hoop
frequencies, :class:`BarrelTargets`: Table 2's loads, geometrically nonlinear), and
:class:`JointTargets`, several sets at once with each misfit in units of its
measurement resolution (:func:`joint_resolution`). The residuals are relative misfits, and
:func:`scipy.optimize.least_squares` (trust-region reflective; bounds keep masses >= 0, plies
thicker than 0.001 in and angles within 0..90 deg) drives them to zero when as many parameters
as targets are free, or to their least squares when fewer are. With a prior spread per
parameter (:func:`fit_bat`'s ``prior_sd``) the fit is regularised: the most probable bat under
Gaussian measurement errors and a Gaussian prior around the bat file. Each evaluation remeshes
the bat, so a thickness moves the mid-surface exactly as the final mesh does.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from batball.errors import SimulationError, SpecError
from batball.lab.modal import bat_modes
from batball.lab.props import DEFAULT_PIVOT, bat_mass_properties
from batball.mesh.bat import DEFAULT_AXIAL_SIZE, DEFAULT_CIRCUMFERENTIAL
from batball.specs.bat import MAX_INSERT_FRICTION, BatSpec, InsertSpec, PartSpec, PlySpec
from batball.units import IN, LBF, OZ, OZ_IN2


@dataclass(frozen=True)
class ParameterKind:
    """Bounds (SI), a typical size for scaling (SI), and the unit a person reads."""

    lower: float
    upper: float
    typical: float
    unit: str


#: The kinds of free parameter.
PARAMETER_KINDS: dict[str, ParameterKind] = {
    "lumped_mass": ParameterKind(0.0, math.inf, OZ, "oz"),
    "thickness": ParameterKind(0.001 * IN, math.inf, 0.01 * IN, "in"),
    "angle": ParameterKind(0.0, 0.5 * math.pi, math.radians(10.0), "deg"),
    "friction": ParameterKind(0.0, MAX_INSERT_FRICTION, 0.1, ""),
}

#: Relative misfit below which a mass-property target counts as met (as many parameters as
#: targets); a hoop target's is :attr:`ModalTargets.match`.
MATCH_TOLERANCE = 1e-6

#: The parameters ``batball fit-bat`` frees by default on the embedded bat, per target kind:
#: the mass properties take the end-cap plug and the two labelled ply thicknesses; the hoop
#: modes take the braid angle of the barrel's carbon on the full-diameter parts.
DEFAULT_FREE = ("lumped_mass:endcap", "thickness:handle-glass", "thickness:barrel-carbon")
DEFAULT_HOOP_FREE = ("angle:barrel-carbon@barrel-1+barrel-2+barrel-3+endcap",)
#: ... and the joint fit (Table 1 with Table 3's four frequencies) takes both, and the handle's
#: braid angle (its 15-deg glass: knob and handle; the taper's glass is laid at 22.5 and 30).
DEFAULT_JOINT_FREE = (*DEFAULT_FREE, *DEFAULT_HOOP_FREE,
                      "angle:handle-glass@knob+handle-1+handle-2+handle-3")  # fmt: skip

_FREE_TEXT = ("lumped_mass:<part>, thickness:<ply label>[@<part>+...], "
              "angle:<ply label>[@<part>+...] or friction:insert")


@dataclass(frozen=True)
class FreeParameter:
    """One adjustable quantity of a :class:`BatSpec`.

    Attributes:
        kind: a key of :data:`PARAMETER_KINDS`.
        target: the part name (``lumped_mass``) or the ply label (``thickness``, ``angle``).
        parts: the parts whose labelled plies change (``"insert"`` for the insert); empty: all.
    """

    kind: str
    target: str
    parts: tuple[str, ...] = ()

    @classmethod
    def parse(cls, text: str, *, field: str = "free") -> FreeParameter:
        """``"lumped_mass:endcap"`` -> FreeParameter("lumped_mass", "endcap");
        ``"angle:c@barrel-1+endcap"`` -> FreeParameter("angle", "c", ("barrel-1", "endcap"))."""
        kind, _, rest = text.partition(":")
        target, at, parts = rest.partition("@")
        names = tuple(parts.split("+")) if at else ()
        if kind not in PARAMETER_KINDS or not target or any(not n for n in names) or (
            names and kind in ("lumped_mass", "friction")
        ) or (kind == "friction" and target != "insert"):
            raise SpecError(field, text, _FREE_TEXT)
        return cls(kind, target, names)

    def __str__(self) -> str:
        return f"{self.kind}:{self.target}" + ("@" + "+".join(self.parts) if self.parts else "")

    def _plies(self, spec: BatSpec) -> list[PlySpec]:
        """The plies this parameter sets (labelled ``target``, in ``parts``)."""
        known = {p.name for p in spec.parts} | ({"insert"} if spec.insert is not None else set())
        for name in self.parts:
            if name not in known:
                raise SpecError("free", str(self), f"parts of the bat: {', '.join(sorted(known))}")
        return [ply for layup in self._layups(spec) for ply in layup if ply.label == self.target]

    def _insert(self, spec: BatSpec) -> InsertSpec:
        if spec.insert is None:
            raise SpecError("free", str(self), f"a parameter of bat {spec.name}, which has no "
                            "insert")  # fmt: skip
        return spec.insert

    def _layups(self, spec: BatSpec) -> list[tuple[PlySpec, ...]]:
        layups = [part.layup for part in spec.parts if self._selects(part.name)]
        if spec.insert is not None and self._selects("insert"):
            layups.append(spec.insert.layup)
        return layups

    def _selects(self, name: str) -> bool:
        return not self.parts or name in self.parts

    def value(self, spec: BatSpec) -> float:
        """The current value in ``spec`` (kg, m or rad).

        Raises:
            SpecError: no such part or label, or labelled plies of unequal values.
        """
        if self.kind == "lumped_mass":
            return spec.part(self.target).lumped_mass
        if self.kind == "friction":
            return self._insert(spec).friction
        plies = self._plies(spec)
        values = {p.thickness if self.kind == "thickness" else abs(p.angle) for p in plies}
        if len(values) != 1:
            labels = sorted({p.label for p in _all_plies(spec) if p.label})
            allowed = (f"a label of plies of one {self.kind} in the parts named; labels: "
                       f"{', '.join(labels) or 'none'}")  # fmt: skip
            raise SpecError("free", str(self), allowed)
        return values.pop()

    def apply(self, spec: BatSpec, value: float) -> BatSpec:
        """A copy of ``spec`` with this parameter set to ``value`` (kg, m or rad; an angle keeps
        each ply's sign)."""
        if self.kind == "lumped_mass":
            parts = tuple(
                dataclasses.replace(p, lumped_mass=value) if p.name == self.target else p
                for p in spec.parts
            )
            return dataclasses.replace(spec, parts=parts)
        if self.kind == "friction":
            insert = dataclasses.replace(self._insert(spec), friction=value)
            return dataclasses.replace(spec, insert=insert)

        def change(ply: PlySpec) -> PlySpec:
            if ply.label != self.target:
                return ply
            if self.kind == "thickness":
                return dataclasses.replace(ply, thickness=value)
            return dataclasses.replace(ply, angle=math.copysign(value, ply.angle))

        return _replace_layups(spec, change, self._selects)


def _all_plies(spec: BatSpec) -> list[PlySpec]:
    """Every ply of the parts and the insert."""
    plies = [ply for part in spec.parts for ply in part.layup]
    return plies + (list(spec.insert.layup) if spec.insert is not None else [])


def _replace_layups(spec: BatSpec, change: Callable[[PlySpec], PlySpec],
                    selects: Callable[[str], bool]) -> BatSpec:  # fmt: skip
    """``spec`` with ``change(ply)`` applied to every ply of the selected parts (and insert)."""

    def layup(part: PartSpec) -> PartSpec:
        if not selects(part.name):
            return part
        return dataclasses.replace(part, layup=tuple(change(p) for p in part.layup))

    insert = spec.insert
    if insert is not None and selects("insert"):
        insert = dataclasses.replace(insert, layup=tuple(change(p) for p in insert.layup))
    return dataclasses.replace(spec, parts=tuple(layup(p) for p in spec.parts), insert=insert)


@dataclass(frozen=True)
class MeshOptions:
    """The bat mesh every evaluation of a fit uses."""

    circumferential: int = DEFAULT_CIRCUMFERENTIAL
    axial_size: float = DEFAULT_AXIAL_SIZE


class FitTargets(Protocol):
    """What a fit matches: named measured values and how to compute them for a bat.

    ``names`` carry their unit (``"weight_oz"``); ``wanted`` and ``achieved`` are in those
    units; the residuals are ``achieved / wanted - 1``. ``diff_step`` and ``tolerance`` are
    the optimiser's relative finite-difference step and its x, f and gradient tolerance;
    ``match`` the relative misfit below which a target counts as met.
    """

    @property
    def names(self) -> tuple[str, ...]: ...

    @property
    def wanted(self) -> tuple[float, ...]: ...

    @property
    def description(self) -> str: ...

    @property
    def diff_step(self) -> float: ...

    @property
    def tolerance(self) -> float: ...

    @property
    def match(self) -> float: ...

    def achieved(self, spec: BatSpec, mesh: MeshOptions) -> tuple[float, ...]: ...


@dataclass(frozen=True)
class MassTargets:
    """Measured mass properties to match, SI.

    Attributes:
        weight: kg.
        balance_point: m from the knob end.
        moi_pivot: kg m^2 about the pivot.
        pivot: m from the knob end.
    """

    weight: float
    balance_point: float
    moi_pivot: float
    pivot: float = DEFAULT_PIVOT
    diff_step: float = 1e-7
    tolerance: float = 1e-12
    match: float = MATCH_TOLERANCE

    names = ("weight_oz", "balance_point_in", "moi_pivot_oz_in2")
    description = "weight, balance point and MOI"

    def __post_init__(self) -> None:
        for name, value, unit in (("weight", self.weight / OZ, "oz"),
                                  ("balance-point", self.balance_point / IN, "in"),
                                  ("moi", self.moi_pivot / OZ_IN2, "oz*in**2")):  # fmt: skip
            if not (math.isfinite(value) and value > 0.0):
                raise SpecError(name, f"{value:g} {unit}", f"a positive {name.replace('-', ' ')}")

    @property
    def wanted(self) -> tuple[float, ...]:
        return (self.weight / OZ, self.balance_point / IN, self.moi_pivot / OZ_IN2)

    def achieved(self, spec: BatSpec, mesh: MeshOptions) -> tuple[float, ...]:
        props, _ = bat_mass_properties(spec, circumferential=mesh.circumferential,
                                       axial_size=mesh.axial_size, pivot=self.pivot)  # fmt: skip
        return (props.mass / OZ, props.balance_point / IN, props.moi_pivot / OZ_IN2)


def seed_hoop_hz() -> tuple[float, ...]:
    """Seed Table 3's measured hoop frequencies, Hz (read when a default target is made)."""
    from batball.specs.seed import load_seed_tables

    modal = load_seed_tables().modal
    return (modal.hoop_1_exp, modal.hoop_2_exp)


def seed_bending_hz() -> tuple[float, ...]:
    """Seed Table 3's measured free-free bending frequencies, Hz."""
    from batball.specs.seed import load_seed_tables

    modal = load_seed_tables().modal
    return (modal.bending_1_exp, modal.bending_2_exp)


@dataclass(frozen=True)
class ModalTargets:
    """Measured free-free frequencies to match, Hz: the barrel's hoop (n = 2 ovalling) modes
    and, optionally, the bat's bending modes, all from one modal analysis.

    Each evaluation is a modal analysis (:func:`batball.lab.modal.bat_modes`, ``n_modes``
    lowest, ``insert`` model); the k-th hoop (bending) target is the k-th distinct hoop
    (bending) frequency. With ``runs_dir`` each evaluation's frequencies are stored under
    ``runs_dir/fit-hoop-<hash>/``, so an interrupted fit run again replays the finished ones
    instead of recomputing them (``reuse=False`` recomputes and overwrites them).

    The frequencies carry a noise of about 5e-6 (relative) from the pre-stress solve's contact
    set, a few mHz: the finite-difference step (1e-3 of the parameter, 0.03 deg of a 30-deg
    braid, about 0.2 Hz of hoop frequency) keeps it to a few per cent of the derivative, and the
    fit stops when a step changes the parameter or the squared misfit by less than 1e-4
    (relative): 0.003 deg, far below what the modal test resolves. A target within 1e-4
    (0.15 Hz at 1450 Hz) counts as met.
    """

    hoop_hz: tuple[float, ...] = dataclasses.field(default_factory=seed_hoop_hz)
    bending_hz: tuple[float, ...] = ()
    insert: str = "contact"
    n_modes: int = 30
    runs_dir: Path | None = None
    reuse: bool = True
    diff_step: float = 1e-3
    tolerance: float = 1e-4
    match: float = 1e-4

    def __post_init__(self) -> None:
        if not self.hoop_hz or not all(math.isfinite(f) and f > 0.0 for f in self.hoop_hz):
            raise SpecError("hoop", list(self.hoop_hz), "one or more positive frequencies")
        if not all(math.isfinite(f) and f > 0.0 for f in self.bending_hz):
            raise SpecError("bending", list(self.bending_hz), "positive frequencies")

    @property
    def description(self) -> str:
        return "bending and hoop frequencies" if self.bending_hz else "hoop frequencies"

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"bending_{k + 1}_hz" for k in range(len(self.bending_hz))) + tuple(
            f"hoop_{k + 1}_hz" for k in range(len(self.hoop_hz))
        )

    @property
    def wanted(self) -> tuple[float, ...]:
        return self.bending_hz + self.hoop_hz

    def achieved(self, spec: BatSpec, mesh: MeshOptions) -> tuple[float, ...]:
        from batball.results.store import load_cached_summary, run_folder, write_summary
        from batball.specs.bat import bat_spec_to_toml_dict
        from batball.version import __version__

        folder = None
        if self.runs_dir is not None:
            inputs = {"bat": bat_spec_to_toml_dict(spec), "mesh": dataclasses.asdict(mesh),
                      "n_modes": self.n_modes, "insert": self.insert, "batball": __version__,
                      **({"bending": len(self.bending_hz)} if self.bending_hz else {})}
            folder = run_folder(self.runs_dir, "fit-hoop", inputs)
            cached = load_cached_summary(folder) if self.reuse else None
            if cached is not None:
                return tuple(cached.get("bending_hz", [])) + tuple(cached["hoop_hz"])
        modes = bat_modes(spec, circumferential=mesh.circumferential,
                          axial_size=mesh.axial_size, n_modes=self.n_modes, insert=self.insert)
        found = {label: self._found(modes, spec, label, len(wanted))
                 for label, wanted in (("bending", self.bending_hz), ("hoop", self.hoop_hz))}
        if folder is not None:
            write_summary(folder, {"bat": spec.name, "hoop_hz": list(found["hoop"]),
                                   **({"bending_hz": list(found["bending"])}
                                      if self.bending_hz else {})})  # fmt: skip
        return found["bending"] + found["hoop"]

    def _found(self, modes: Any, spec: BatSpec, label: str, count: int) -> tuple[float, ...]:
        """The ``count`` lowest distinct ``label`` frequencies, or SimulationError."""
        if count == 0:
            return ()
        found = modes.first(label, count)
        if len(found) < count:
            raise SimulationError(
                f"fit-bat: bat {spec.name!r} has {len(found)} distinct {label} modes among its "
                f"{self.n_modes} lowest, {count} wanted; ask for more modes"
            )
        return tuple(float(modes.frequencies[i]) for i in found)


def seed_table2_lbf() -> tuple[float, float]:
    """Seed Table 2's measured preload and final load, lbf."""
    from batball.specs.seed import load_seed_tables

    barrel = load_seed_tables().barrel
    return (barrel.preload_exp / LBF, barrel.final_load_exp / LBF)


@dataclass(frozen=True)
class BarrelTargets:
    """Measured barrel-compression loads to match (seed Table 2): the preload (the force at
    the first 0.02 in of platen travel) and the final load (the force over the next 0.05 in),
    lbf, each the mean over ``orientations_deg``.

    Each evaluation is one explicit barrel test (:func:`batball.lab.barrel_run.
    run_explicit_barrel_test`: the insert's fit relaxed, then the platens closed on the
    geometrically nonlinear ``shell`` shells, the insert's friction the bat's own), on the fit's
    mesh. With ``runs_dir`` each test is stored there and an interrupted fit replays it.
    ``correction`` multiplies the computed loads (one factor per load): a fit on a coarse mesh
    aims at the full mesh's loads when it is their ratio at the start (the 32 x 0.2 in mesh
    makes the explicit squeeze's loads 8-11 % stiffer than the 48 x 0.1 in one, docs/fidelity.md).

    The loads are averages over the last part of each hold of a dynamic relaxation, deterministic
    for a given bat: the barrel wall's thickness moved by 0.1 % and by 1 % gives slopes of the
    loads of 1.516 and 1.524 (relative per relative, 32 x 0.2 in), the difference the curvature,
    so the modal targets' finite-difference step (1e-3 of the parameter) serves.
    """

    loads: tuple[str, ...] = ("preload", "final_load")
    wanted_lbf: tuple[float, ...] = ()  # empty: seed Table 2's, for the loads named
    orientations_deg: tuple[float, ...] = (0.0, 90.0, 45.0, -45.0)
    shell: str = "mitc4"
    correction: tuple[float, ...] = ()
    runs_dir: Path | None = None
    reuse: bool = True
    diff_step: float = 1e-3
    tolerance: float = 1e-4
    match: float = 1e-3

    def __post_init__(self) -> None:
        known = ("preload", "final_load")
        if not self.loads or any(load not in known for load in self.loads) or len(
            set(self.loads)) != len(self.loads):  # fmt: skip
            raise SpecError("barrel loads", list(self.loads), "preload and/or final_load")
        if not self.wanted_lbf:
            seed = dict(zip(known, seed_table2_lbf(), strict=True))
            object.__setattr__(self, "wanted_lbf", tuple(seed[load] for load in self.loads))
        if len(self.wanted_lbf) != len(self.loads) or not all(
            math.isfinite(w) and w > 0.0 for w in self.wanted_lbf
        ):
            raise SpecError("barrel targets", list(self.wanted_lbf),
                            f"{len(self.loads)} positive loads in lbf")  # fmt: skip
        if not self.correction:
            object.__setattr__(self, "correction", (1.0,) * len(self.loads))
        if len(self.correction) != len(self.loads) or not all(
            math.isfinite(c) and c > 0.0 for c in self.correction
        ):
            raise SpecError("barrel correction", list(self.correction),
                            f"{len(self.loads)} positive factors")  # fmt: skip
        if not self.orientations_deg:
            raise SpecError("barrel orientations", [], "one or more angles in deg")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{load}_lbf" for load in self.loads)

    @property
    def wanted(self) -> tuple[float, ...]:
        return self.wanted_lbf

    @property
    def description(self) -> str:
        return "barrel " + " and ".join(load.replace("_", " ") for load in self.loads)

    def computed(self, spec: BatSpec, mesh: MeshOptions) -> dict[str, Any]:
        """The explicit barrel test's summary for ``spec`` on ``mesh`` (stored or replayed)."""
        from batball.lab.barrel_explicit import ExplicitBarrelOptions
        from batball.lab.barrel_run import run_explicit_barrel_test
        from batball.models.barrel import BarrelTestOptions

        protocol = BarrelTestOptions(orientations_deg=self.orientations_deg,
                                     curve_orientations=0)  # fmt: skip
        explicit = ExplicitBarrelOptions(circumferential=mesh.circumferential,
                                         axial_size=mesh.axial_size, shell=self.shell)  # fmt: skip
        if self.runs_dir is None:
            import tempfile

            with tempfile.TemporaryDirectory() as scratch:
                return run_explicit_barrel_test(spec, runs_dir=Path(scratch), options=protocol,
                                                explicit=explicit)[0]  # fmt: skip
        return run_explicit_barrel_test(spec, runs_dir=self.runs_dir, options=protocol,
                                        explicit=explicit, reuse=self.reuse)[0]  # fmt: skip

    def achieved(self, spec: BatSpec, mesh: MeshOptions) -> tuple[float, ...]:
        summary = self.computed(spec, mesh)
        return tuple(float(summary[name]) * c for name, c in zip(self.names, self.correction,
                                                                 strict=True))  # fmt: skip


#: Measurement resolution (one standard deviation) assumed for Table 1 and Table 3 when they
#: are fitted together; the seed states none. Absolute, in the target's unit: weight 0.1 oz (a
#: scale's reading), balance point 0.1 in (a knife edge). Relative: MOI 1 % (the swing-weight
#: pendulum's repeatability, ASTM F2398) and every free-free frequency 1 % (the bat-to-bat and
#: support spread, larger than a hammer test's frequency resolution). Table 2's loads (one bat,
#: whole pounds, no scatter stated): the final load 3 % and the preload 5 %, assumed; a load
#: cell reads to well under 1 %, so these stand for the platens' seating, the bat's orientation
#: and bat-to-bat spread, larger on the preload, read where the platens first seat.
JOINT_ABSOLUTE_RESOLUTION = {"weight_oz": 0.1, "balance_point_in": 0.1}
JOINT_RELATIVE_RESOLUTION = {"moi_pivot_oz_in2": 0.01, "frequency_hz": 0.01,
                             "preload_lbf": 0.05, "final_load_lbf": 0.03}  # fmt: skip


def joint_resolution(name: str, wanted: float) -> float:
    """The relative resolution of target ``name`` measured at ``wanted`` (its unit): an
    absolute one of :data:`JOINT_ABSOLUTE_RESOLUTION` over the value, else the relative one
    (any ``*_hz`` target is a frequency).

    Raises:
        SpecError: a target with no assumed resolution.
    """
    if name in JOINT_ABSOLUTE_RESOLUTION:
        return JOINT_ABSOLUTE_RESOLUTION[name] / abs(wanted)
    key = "frequency_hz" if name.endswith("_hz") else name
    if key not in JOINT_RELATIVE_RESOLUTION:
        raise SpecError("resolution", name, "a target with an assumed resolution: weight, "
                        "balance point, MOI, a frequency, preload or final load")  # fmt: skip
    return JOINT_RELATIVE_RESOLUTION[key]


@dataclass(frozen=True)
class JointTargets:
    """Several target sets matched together (Table 1's mass properties with Table 3's
    frequencies), each target weighted by its measurement resolution.

    Attributes:
        parts: the target sets, evaluated in turn on the same bat.
        resolution: one relative standard deviation per target (``names`` order; default
            :func:`joint_resolution`'s); the fit minimises the sum of squared misfits in these
            units.
    """

    parts: tuple[Any, ...]
    resolution: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if not self.resolution:
            resolution = tuple(map(joint_resolution, self.names, self.wanted))
            object.__setattr__(self, "resolution", resolution)
        if len(self.resolution) != len(self.names) or not all(
            math.isfinite(r) and r > 0.0 for r in self.resolution
        ):
            raise SpecError("resolution", list(self.resolution),
                            f"{len(self.names)} positive relative resolutions")  # fmt: skip

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(n for part in self.parts for n in part.names)

    @property
    def wanted(self) -> tuple[float, ...]:
        return tuple(w for part in self.parts for w in part.wanted)

    @property
    def description(self) -> str:
        return " and ".join(part.description for part in self.parts)

    @property
    def diff_step(self) -> float:
        return max(part.diff_step for part in self.parts)

    @property
    def tolerance(self) -> float:
        return max(part.tolerance for part in self.parts)

    @property
    def match(self) -> float:
        return max(part.match for part in self.parts)

    def achieved(self, spec: BatSpec, mesh: MeshOptions) -> tuple[float, ...]:
        return tuple(v for part in self.parts for v in part.achieved(spec, mesh))


@dataclass(frozen=True)
class BatFit:
    """The outcome of :func:`fit_bat`.

    Attributes:
        spec: the bat with the fitted values.
        parameters: the free parameters.
        initial: their starting values, SI.
        values: their fitted values, SI.
        achieved: the fitted bat's values of the targets, in the targets' units.
        residuals: relative misfits, one per target.
        n_evaluations: target evaluations used (a repeated point counted once).
        success: the optimiser's verdict.
        match: relative misfit below which a target counts as met.
        regularised: the fit weighed the parameters' distances from their starts (a least-
            squares fit whatever the counts).
    """

    spec: BatSpec
    parameters: tuple[FreeParameter, ...]
    initial: tuple[float, ...]
    values: tuple[float, ...]
    achieved: tuple[float, ...]
    residuals: tuple[float, ...]
    n_evaluations: int
    success: bool
    match: float = MATCH_TOLERANCE
    regularised: bool = False

    @property
    def least_squares(self) -> bool:
        """Fewer parameters than targets, or a regularised fit: the fit minimises the misfits,
        it cannot zero them."""
        return self.regularised or len(self.parameters) < len(self.residuals)

    @property
    def at_bound(self) -> tuple[FreeParameter, ...]:
        """The parameters a bound stopped."""
        return tuple(p for p, v in zip(self.parameters, self.values, strict=True)
                     if _at_bound(v, PARAMETER_KINDS[p.kind]))  # fmt: skip

    @property
    def matched(self) -> bool:
        """Converged with no parameter at a bound, and, unless a least-squares fit, every target
        met to the relative ``match``."""
        if not self.success or self.at_bound:
            return False
        return self.least_squares or max(abs(r) for r in self.residuals) < self.match


def _at_bound(value: float, kind: ParameterKind) -> bool:
    near = 1e-6 * max(abs(value), kind.typical)
    return value <= kind.lower + near or value >= kind.upper - near


def fit_bat(
    spec: BatSpec,
    targets: FitTargets,
    parameters: tuple[FreeParameter, ...],
    *,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
    prior_sd: tuple[float, ...] | None = None,
) -> BatFit:
    """Adjust ``parameters`` of ``spec`` so its ``targets`` match (least squares).

    Targets with a ``resolution`` (:class:`JointTargets`) weigh each misfit by it. With
    ``prior_sd`` (SI, one per parameter: its plausible spread) the fit is regularised: each
    parameter's distance from its value in ``spec``, in those spreads, is one more residual (the
    most probable bat under a Gaussian prior around ``spec`` and Gaussian measurement errors).

    Raises:
        SpecError: an unknown part or label, or a fit that leaves the bat invalid.
        SimulationError: a target that cannot be evaluated (too few hoop modes).
    """
    from scipy.optimize import least_squares

    mesh = MeshOptions(circumferential, axial_size)
    for part in getattr(targets, "parts", (targets,)):
        if isinstance(part, MassTargets) and not part.balance_point < spec.length:
            raise SpecError("balance-point", f"{part.balance_point / IN:g} in",
                            f"a point on the bat, within its {spec.length / IN:g} in")  # fmt: skip
    kinds = [PARAMETER_KINDS[p.kind] for p in parameters]
    initial = np.array([p.value(spec) for p in parameters])
    scale = np.maximum(np.abs(initial), [k.typical for k in kinds])
    lower = np.array([k.lower for k in kinds]) / scale
    upper = np.array([k.upper for k in kinds]) / scale
    wanted = np.asarray(targets.wanted, dtype=float)
    weight = 1.0 / np.asarray(getattr(targets, "resolution", None) or np.ones(wanted.size))
    prior = None if prior_sd is None else np.asarray(prior_sd, dtype=float)
    if prior is not None and (prior.shape != initial.shape or not np.all(prior > 0.0)):
        raise SpecError("prior", list(prior_sd or ()), f"{initial.size} positive spreads")
    seen: dict[bytes, tuple[float, ...]] = {}

    def with_values(scaled: np.ndarray) -> BatSpec:
        fitted = spec
        for p, value in zip(parameters, scaled * scale, strict=True):
            fitted = p.apply(fitted, float(value))
        return fitted

    def achieved(scaled: np.ndarray) -> tuple[float, ...]:
        key = np.asarray(scaled, dtype=float).tobytes()
        if key not in seen:
            seen[key] = targets.achieved(with_values(scaled), mesh)
        return seen[key]

    def misfit(scaled: np.ndarray) -> np.ndarray:
        relative = (np.asarray(achieved(scaled)) / wanted - 1.0) * weight
        if prior is None:
            return relative
        # the regularisation: each parameter's distance from its start in prior spreads
        return np.concatenate([relative, (scaled * scale - initial) / prior])

    start = np.clip(initial / scale, lower, upper)
    tol = targets.tolerance
    result = least_squares(misfit, start, bounds=(lower, upper), x_scale=1.0, xtol=tol,
                           ftol=tol, gtol=tol, diff_step=targets.diff_step)  # fmt: skip
    values = result.x * scale
    final = achieved(result.x)
    return BatFit(
        spec=with_values(result.x), parameters=parameters, initial=tuple(initial.tolist()),
        values=tuple(values.tolist()), achieved=final,
        residuals=tuple((np.asarray(final) / wanted - 1.0).tolist()), n_evaluations=len(seen),
        success=bool(result.success), match=targets.match, regularised=prior is not None,
    )  # fmt: skip


def fit_summary(fit: BatFit, targets: FitTargets) -> dict[str, Any]:
    """A JSON-able summary of a fit: parameters with units, achieved values against targets."""
    from batball.units import format_quantity

    def text(p: FreeParameter, value: float) -> str:
        kind = PARAMETER_KINDS[p.kind]
        return format_quantity(value, kind.unit, digits=6)

    return {
        "bat": fit.spec.name,
        "fitted_to": targets.description,
        "success": fit.success,
        "n_evaluations": fit.n_evaluations,
        "parameters": {
            str(p): {"initial": text(p, v0), "fitted": text(p, v)}
            for p, v0, v in zip(fit.parameters, fit.initial, fit.values, strict=True)
        },
        "properties": dict(zip(targets.names, fit.achieved, strict=True)),
        "targets": dict(zip(targets.names, targets.wanted, strict=True)),
        "error_percent": {k: 100.0 * r for k, r in zip(targets.names, fit.residuals, strict=True)},
        "least_squares": fit.least_squares,
        "matched": fit.matched,
        "at_bound": [str(p) for p in fit.at_bound],
    }


def write_fitted_bat(path: Path, fit: BatFit) -> None:
    """Write the fitted bat as a bat-spec TOML file (atomically)."""
    import tomli_w

    from batball.results.store import write_text_atomic
    from batball.specs.bat import bat_spec_to_toml_dict

    header = "# Written by batball fit-bat: " + ", ".join(str(p) for p in fit.parameters) + "\n"
    write_text_atomic(path, header + tomli_w.dumps(bat_spec_to_toml_dict(fit.spec)))
