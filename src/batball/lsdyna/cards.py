"""LS-DYNA keyword card layouts (field names, order and fixed-format widths) and unit systems.

One table serves the deck writer (:mod:`batball.lsdyna.export`) and the reader
(:mod:`batball.lsdyna.deck`). Every layout names its source. The primary source for field
order and widths is the LS-DYNA Keyword User's Manual, Vol. I (R13/R14), read through two public
transcriptions: the generated keyword classes of ``ansys/pydyna`` (``src/ansys/dyna/core/keywords/
keyword_classes/auto/<group>/<keyword>.py``, each field given as name, start column, width) and
Altair's "LS-DYNA Input Interface" pages of the Radioss reference (help.altair.com,
``.../rad/topics/solvers/rad/<keyword>_lsdyna_r.htm``), which OpenRadioss follows when it reads a
deck. Standard format is 8 fields of 10 columns unless said otherwise; in long format (``*NODE +``
or ``*KEYWORD LONG=Y``) every field is 20 columns wide.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from batball.errors import SpecError
from batball.units import IN, LBF

#: One field: name, width in standard format, kind ("i" integer, "f" real, "s" text).
Field = tuple[str, int, str]


def _tens(names: str, kind: str = "f") -> tuple[Field, ...]:
    """Eight-or-fewer 10-column fields of one kind (names blank-separated; "i:" prefix = int)."""
    out = []
    for name in names.split():
        k = kind
        if name.startswith("i:"):
            name, k = name[2:], "i"
        out.append((name, 10, k))
    return tuple(out)


#: Card layouts by keyword (without the leading star): a tuple of cards, each a tuple of fields.
LAYOUTS: dict[str, tuple[tuple[Field, ...], ...]] = {
    # *NODE: NID I8, X Y Z E16, TC RC I8 (pydyna auto/node/node.py; Altair node_lsdyna_r)
    "NODE": ((("nid", 8, "i"), ("x", 16, "f"), ("y", 16, "f"), ("z", 16, "f"),
              ("tc", 8, "i"), ("rc", 8, "i")),),
    # *ELEMENT_SOLID, single-card ("old") format: EID PID N1..N8, all I8 (Keyword Manual Vol I,
    # *ELEMENT_SOLID remarks; the two-card form EID PID / N1..N10 is read as well)
    "ELEMENT_SOLID": ((("eid", 8, "i"), ("pid", 8, "i"),
                       *((f"n{i}", 8, "i") for i in range(1, 9))),),
    # *ELEMENT_SHELL: EID PID N1..N4 I8 (pydyna auto/element/element_shell.py)
    "ELEMENT_SHELL": ((("eid", 8, "i"), ("pid", 8, "i"),
                       *((f"n{i}", 8, "i") for i in range(1, 5))),),
    # *PART: heading (70 columns), then PID SECID MID EOSID HGID GRAV ADPOPT TMID (pydyna
    # auto/part/part.py; Altair part_lsdyna_r)
    "PART": ((("heading", 70, "s"),),
             _tens("i:pid i:secid i:mid i:eosid i:hgid i:grav i:adpopt i:tmid")),
    # *SECTION_SOLID: SECID ELFORM AET (pydyna auto/section/section_solid.py)
    "SECTION_SOLID": (_tens("i:secid i:elform i:aet"),),
    # *SECTION_SHELL: SECID ELFORM SHRF NIP PROPT QR/IRID ICOMP SETYP / T1 T2 T3 T4 NLOC MAREA
    # IDOF EDGSET (pydyna auto/section/section_shell.py)
    "SECTION_SHELL": (_tens("i:secid i:elform shrf i:nip propt qr i:icomp i:setyp"),
                      _tens("t1 t2 t3 t4 nloc marea idof i:edgset")),
    # *MAT_ELASTIC (001): MID RO E PR DA DB K (pydyna auto/mat/mat_elastic.py)
    "MAT_ELASTIC": (_tens("i:mid ro e pr da db k"),),
    # *MAT_VISCOELASTIC (006): MID RO BULK G0 GI BETA (pydyna auto/mat/mat_viscoelastic.py)
    "MAT_VISCOELASTIC": (_tens("i:mid ro bulk g0 gi beta"),),
    # *MAT_RIGID (020): MID RO E PR N COUPLE M ALIAS / CMO CON1 CON2 / LCO-or-A1 A2 A3 V1 V2 V3
    # (pydyna auto/mat/mat_rigid.py and mat_020.py; newer manuals add SPCNID XSPC YSPC ZSPC to
    # card 2, which batball does not read: text there is an error)
    "MAT_RIGID": (_tens("i:mid ro e pr n couple m alias"), _tens("cmo con1 con2"),
                  _tens("a1 a2 a3 v1 v2 v3")),
    # *HOURGLASS: HGID IHQ QM IBQ Q1 Q2 QB QW (pydyna auto/hourglass/hourglass.py)
    "HOURGLASS": (_tens("i:hgid i:ihq qm i:ibq q1 q2 qb qw"),),
    # *CONTROL_TERMINATION: ENDTIM ENDCYC DTMIN ENDENG ENDMAS NOSOL (pydyna
    # auto/control/control_termination.py)
    "CONTROL_TERMINATION": (_tens("endtim i:endcyc dtmin endeng endmas i:nosol"),),
    # *CONTROL_TIMESTEP: DTINIT TSSFAC ISDO TSLIMT DT2MS LCTM ERODE MS1ST (pydyna
    # auto/control/control_timestep.py)
    "CONTROL_TIMESTEP": (_tens("dtinit tssfac i:isdo tslimt dt2ms i:lctm i:erode i:ms1st"),),
    # *CONTROL_HOURGLASS: IHQ QH (pydyna auto/control/control_hourglass.py)
    "CONTROL_HOURGLASS": (_tens("i:ihq qh"),),
    # *CONTROL_BULK_VISCOSITY: Q1 Q2 TYPE BTYPE (pydyna auto/control/control_bulk_viscosity.py)
    "CONTROL_BULK_VISCOSITY": (_tens("q1 q2 i:type i:btype"),),
    # *CONTROL_CONTACT card 1: SLSFAC RWPNAL ISLCHK SHLTHK PENOPT THKCHG ORIEN ENMASS (pydyna
    # auto/control/control_contact.py; cards 2+ are optional and not written)
    "CONTROL_CONTACT": (_tens("slsfac rwpnal i:islchk i:shlthk i:penopt i:thkchg i:orien "
                              "i:enmass"),),
    # *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE: SURFA SURFB SURFATYP SURFBTYP SABOXID SBBOXID SAPR
    # SBPR / FS FD DC VC VDC PENCHK BT DT / SFSA SFSB SAST SBST SFSAT SFSBT FSF VSF / optional
    # card A: SOFT SOFSCL LCIDAB MAXPAR SBOPT DEPTH BSORT FRCFRQ (pydyna
    # auto/contact/contact_automatic_surface_to_surface.py, cards 0-2 and option A)
    "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE": (
        _tens("i:surfa i:surfb i:surfatyp i:surfbtyp i:saboxid i:sbboxid i:sapr i:sbpr"),
        _tens("fs fd dc vc vdc i:penchk bt dt"),
        _tens("sfsa sfsb sast sbst sfsat sfsbt fsf vsf"),
        _tens("i:soft sofscl i:lcidab maxpar i:sbopt i:depth i:bsort i:frcfrq"),
    ),
    # *INITIAL_VELOCITY_GENERATION: ID STYP OMEGA VX VY VZ IVATN ICID / XC YC ZC NX NY NZ PHASE
    # IRIGID (pydyna auto/initial/initial_velocity_generation.py)
    "INITIAL_VELOCITY_GENERATION": (_tens("i:id i:styp omega vx vy vz i:ivatn i:icid"),
                                    _tens("xc yc zc nx ny nz i:phase i:irigid")),
    # *SET_PART_LIST: SID DA1 DA2 DA3 DA4 SOLVER / PID1..PID8 (pydyna auto/set/set_part_list.py)
    "SET_PART_LIST": (_tens("i:sid da1 da2 da3 da4") + (("solver", 10, "s"),),
                      _tens(" ".join(f"i:pid{i}" for i in range(1, 9)))),
    # *SET_NODE_LIST: SID DA1 DA2 DA3 DA4 SOLVER / NID1..NID8 (pydyna auto/set/set_node_list.py)
    "SET_NODE_LIST": (_tens("i:sid da1 da2 da3 da4") + (("solver", 10, "s"),),
                      _tens(" ".join(f"i:nid{i}" for i in range(1, 9)))),
    # *DATABASE_GLSTAT / _MATSUM / _RCFORC / _NODOUT: DT BINARY LCUR IOOPT (pydyna
    # auto/database/database_glstat.py and siblings)
    "DATABASE_GLSTAT": (_tens("dt i:binary i:lcur i:ioopt"),),
    "DATABASE_MATSUM": (_tens("dt i:binary i:lcur i:ioopt"),),
    "DATABASE_RCFORC": (_tens("dt i:binary i:lcur i:ioopt"),),
    "DATABASE_NODOUT": (_tens("dt i:binary i:lcur i:ioopt"),),
    # *DATABASE_BINARY_D3PLOT: DT LCDT BEAM NPLTC PSETID (pydyna
    # auto/database/database_binary_d3plot.py)
    "DATABASE_BINARY_D3PLOT": (_tens("dt i:lcdt i:beam i:npltc i:psetid"),),
    # *DATABASE_HISTORY_NODE: ID1..ID8 (pydyna auto/database/database_history_node.py; Altair
    # database_history_node_lsdyna_r)
    "DATABASE_HISTORY_NODE": (_tens(" ".join(f"i:id{i}" for i in range(1, 9))),),
    # *BOUNDARY_PRESCRIBED_MOTION_RIGID: PID DOF VAD LCID SF VID DEATH BIRTH (pydyna
    # auto/boundary/boundary_prescribed_motion_rigid.py)
    "BOUNDARY_PRESCRIBED_MOTION_RIGID": (_tens("i:pid i:dof i:vad i:lcid sf i:vid death birth"),),
    # *DEFINE_CURVE: LCID SIDR SFA SFO OFFA OFFO DATTYP LCINT / A1 O1 in 20 columns each (pydyna
    # auto/define/define_curve.py)
    "DEFINE_CURVE": (_tens("i:lcid i:sidr sfa sfo offa offo i:dattyp i:lcint"),
                     (("a1", 20, "f"), ("o1", 20, "f"))),
    # *DAMPING_GLOBAL: LCID VALDMP STX STY STZ SRX SRY SRZ; the force on a node is -VALDMP m v
    # (pydyna auto/damping/damping_global.py)
    "DAMPING_GLOBAL": (_tens("i:lcid valdmp stx sty stz srx sry srz"),),
    # --- bat decks (modal, barrel, bbs) ---
    # *PART_COMPOSITE: title (80) / PID ELFORM SHRF NLOC MAREA HGID ADPOPT THSHEL / then one card
    # per two integration points MID1 THICK1 B1 TMID1 MID2 THICK2 B2 TMID2 (pydyna
    # auto/part/part_composite.py; the seed built its bat with this keyword)
    "PART_COMPOSITE": ((("title", 80, "s"),),
                       _tens("i:pid i:elform shrf nloc marea i:hgid i:adpopt i:thshel"),
                       _tens("i:mid1 thick1 b1 i:tmid1 i:mid2 thick2 b2 i:tmid2")),
    # *MAT_COMPOSITE_DAMAGE (022): MID RO EA EB EC PRBA PRCA PRCB / GAB GBC GCA KFAIL AOPT MACF
    # ATRACK / XP YP ZP A1 A2 A3 / V1 V2 V3 D1 D2 D3 BETA / SC XT YT YC ALPH SN SYZ SZX (pydyna
    # auto/mat/mat_composite_damage.py)
    "MAT_COMPOSITE_DAMAGE": (_tens("i:mid ro ea eb ec prba prca prcb"),
                             _tens("gab gbc gca kfail aopt i:macf i:atrack"),
                             _tens("xp yp zp a1 a2 a3"), _tens("v1 v2 v3 d1 d2 d3 beta"),
                             _tens("sc xt yt yc alph sn syz szx")),
    # *CONTROL_IMPLICIT_GENERAL: IMFLAG DT0 IMFORM NSBS IGS CNSTN FORM ZERO_V (pydyna
    # auto/control/control_implicit_general.py)
    "CONTROL_IMPLICIT_GENERAL": (_tens("i:imflag dt0 i:imform i:nsbs i:igs i:cnstn i:form "
                                       "i:zero_v"),),
    # *CONTROL_IMPLICIT_EIGENVALUE card 1: NEIG CENTER LFLAG LFTEND RFLAG RHTEND EIGMTH SHFSCL
    # (pydyna auto/control/control_implicit_eigenvalue.py; later cards optional, not written)
    "CONTROL_IMPLICIT_EIGENVALUE": (_tens("i:neig center i:lflag lftend i:rflag rhtend i:eigmth "
                                          "shfscl"),),
    # *CONTROL_DYNAMIC_RELAXATION card 1: NRCYCK DRTOL DRFCTR DRTERM TSSFDR IRELAL EDTTL IDRFLG
    # (pydyna auto/control/control_dynamic_relaxation.py)
    "CONTROL_DYNAMIC_RELAXATION": (_tens("i:nrcyck drtol drfctr drterm tssfdr i:irelal edttl "
                                         "i:idrflg"),),
    # *CONTACT_SURFACE_TO_SURFACE_INTERFERENCE: the three common contact cards, then LCID1
    # (interface stiffness scale during dynamic relaxation) LCID2 (during the transient) (pydyna
    # auto/contact/contact_surface_to_surface_interference.py)
    "CONTACT_SURFACE_TO_SURFACE_INTERFERENCE": (
        _tens("i:surfa i:surfb i:surfatyp i:surfbtyp i:saboxid i:sbboxid i:sapr i:sbpr"),
        _tens("fs fd dc vc vdc i:penchk bt dt"),
        _tens("sfsa sfsb sast sbst sfsat sfsbt fsf vsf"),
        _tens("i:lcid1 i:lcid2"),
    ),
    # *CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET: the three common contact cards (pydyna
    # auto/contact/contact_tied_shell_edge_to_surface_beam_offset.py)
    "CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET": (
        _tens("i:surfa i:surfb i:surfatyp i:surfbtyp i:saboxid i:sbboxid i:sapr i:sbpr"),
        _tens("fs fd dc vc vdc i:penchk bt dt"),
        _tens("sfsa sfsb sast sbst sfsat sfsbt fsf vsf"),
    ),
    # *BOUNDARY_SPC_SET: NSID CID DOFX DOFY DOFZ DOFRX DOFRY DOFRZ (pydyna
    # auto/boundary/boundary_spc_set.py; Altair boundary_spc_lsdyna_r)
    "BOUNDARY_SPC_SET": (_tens("i:nsid i:cid i:dofx i:dofy i:dofz i:dofrx i:dofry i:dofrz"),),
    # *CONSTRAINED_NODAL_RIGID_BODY_SPC: PID CID NSID PNODE IPRT DRFLAG RRFLAG / CMO CON1 CON2
    # (pydyna auto/constrained/constrained_nodal_rigid_body_spc.py)
    "CONSTRAINED_NODAL_RIGID_BODY_SPC": (_tens("i:pid i:cid i:nsid i:pnode i:iprt i:drflag "
                                               "i:rrflag"),
                                         _tens("cmo con1 con2")),
    # *TITLE: one 80-column line (Keyword Manual Vol I, *TITLE)
    "TITLE": ((("title", 80, "s"),),),
    # *INCLUDE: one file name per card, up to 80 columns (Keyword Manual Vol I, *INCLUDE)
    "INCLUDE": ((("filename", 80, "s"),),),
}  # fmt: skip

#: Alternative names that mean the same keyword (the numbered material names).
ALIASES = {
    "MAT_001": "MAT_ELASTIC",
    "MAT_006": "MAT_VISCOELASTIC",
    "MAT_020": "MAT_RIGID",
    "MAT_022": "MAT_COMPOSITE_DAMAGE",
}


@dataclass(frozen=True)
class UnitSystem:
    """A consistent unit system: the SI size of its length, force and time units.

    Mass, density, pressure and velocity follow (mass = force time^2 / length).
    """

    name: str
    length: float  # m
    force: float  # N
    time: float  # s
    description: str

    @property
    def mass(self) -> float:
        """SI size of the mass unit [kg]."""
        return self.force * self.time**2 / self.length

    @property
    def density(self) -> float:
        """SI size of the density unit [kg/m^3]."""
        return self.mass / self.length**3

    @property
    def pressure(self) -> float:
        """SI size of the pressure unit [Pa]."""
        return self.force / self.length**2

    @property
    def velocity(self) -> float:
        """SI size of the velocity unit [m/s]."""
        return self.length / self.time

    def size(self, dimension: str) -> float:
        """SI size of this system's unit of a material parameter's ``dimension``."""
        sizes = {"pressure": self.pressure, "frequency": 1.0 / self.time, "density": self.density,
                 "dimensionless": 1.0, "length": self.length, "time": self.time,
                 "velocity": self.velocity}  # fmt: skip
        if dimension not in sizes:
            raise SpecError("parameter dimension", dimension, f"one of {sorted(sizes)}")
        return sizes[dimension]


#: The unit systems a deck may be written or read in (in-lbf-s is the seed's Table 4 system).
UNIT_SYSTEMS = {
    "in-lbf-s": UnitSystem(
        "in-lbf-s", IN, LBF, 1.0,
        "length in, force lbf, time s, mass lbf*s^2/in, density lbf*s^2/in^4, stress psi",
    ),
    "m-N-s": UnitSystem("m-N-s", 1.0, 1.0, 1.0, "SI: length m, force N, time s, mass kg, Pa"),
    "mm-N-ms": UnitSystem(
        "mm-N-ms", 1e-3, 1.0, 1e-3,
        "length mm, force N, time ms, mass g, density g/mm^3, stress MPa",
    ),
}  # fmt: skip


def unit_system(name: str) -> UnitSystem:
    """The unit system called ``name``; :class:`SpecError` listing the known ones otherwise."""
    if name not in UNIT_SYSTEMS:
        raise SpecError("units", name, f"one of {', '.join(UNIT_SYSTEMS)}")
    return UNIT_SYSTEMS[name]


def format_real(value: float, width: int) -> str:
    """``value`` right-aligned in ``width`` columns with as many significant digits as fit.

    Tries the shortest exact form, then fixed/exponent forms with fewer digits, then a compact
    exponent without the '+' and leading zeros (``1.23456e-4``, which Fortran and LS-DYNA read).
    """
    if not math.isfinite(value):
        raise SpecError("deck value", value, "a finite number")
    text = repr(float(value))
    if len(text) <= width:
        return text.rjust(width)
    best = ""
    for digits in range(width, 0, -1):
        candidates = [f"{value:.{digits}g}", _compact_exponent(value, digits)]
        fits = [c for c in candidates if len(c) <= width]
        if fits:
            best = min(fits, key=len)
            break
    if not best:
        raise SpecError("deck value", value, f"a number that fits {width} columns")
    return best.rjust(width)


def _compact_exponent(value: float, digits: int) -> str:
    """``value`` as mantissa with ``digits`` significant digits and a bare exponent."""
    mantissa, exponent = f"{value:.{max(digits - 1, 0)}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def format_card(keyword: str, card: int, values: Mapping[str, object], long: bool = False) -> str:
    """One fixed-format card of ``keyword``: each field right-aligned in its columns.

    Fields missing from ``values`` (or None) are left blank (LS-DYNA's default); a name in
    ``values`` that is not a field of the card is a :class:`SpecError`.
    """
    layout = LAYOUTS[keyword][card]
    known = {name for name, _, _ in layout}
    unknown = set(values) - known
    if unknown:
        raise SpecError(f"*{keyword} card {card + 1}", sorted(unknown), f"fields {sorted(known)}")
    parts = []
    for name, standard, kind in layout:
        width = 20 if long and kind != "s" else standard
        value = values.get(name)
        if value is None:
            parts.append(" " * width)
        elif kind == "i":
            text = str(int(value))  # type: ignore[call-overload]
            if len(text) > width:
                raise SpecError(f"*{keyword}.{name}", value, f"an integer of {width} digits")
            parts.append(text.rjust(width))
        elif kind == "f":
            # one blank column kept in front, so neighbouring numbers never touch
            parts.append(" " + format_real(float(value), width - 1))  # type: ignore[arg-type]
        else:
            parts.append(str(value)[:width].ljust(width))
    return "".join(parts).rstrip()


def comment_header(keyword: str, card: int, long: bool = False) -> str:
    """A ``$#`` comment line naming the fields of a card above their columns."""
    parts = []
    for i, (name, standard, kind) in enumerate(LAYOUTS[keyword][card]):
        width = 20 if long and kind != "s" else standard
        parts.append(name.rjust(width) if i else "$#" + name[: width - 2].rjust(width - 2))
    return "".join(parts).rstrip()
