"""Batted-ball speed of a bat with a custom layup against the embedded bat it started from.

The embedded bat ``default`` is written out as TOML, its barrel's carbon plies are turned from
their braid angle toward the bat's axis, and both bats are hit by the seed study's type-1 ball
at the 110-mph lab speed (ASTM F2219, the bat pivoting 6 in from its knob).

    python examples/bbs_custom_layup.py        # 32 shells round, 8-division ball: a few minutes
    BATBALL_EXAMPLE_TINY=1 python examples/bbs_custom_layup.py   # the test suite's coarse run

Writes ``stiff_barrel.toml``, a bat every command takes (``batball props --bat stiff_barrel.toml``).
"""

import dataclasses
import math
import os
from pathlib import Path

import tomli_w

import batball
from batball.specs.bat import bat_spec_to_toml_dict

tiny = bool(os.environ.get("BATBALL_EXAMPLE_TINY"))
mesh = (dict(divisions=2, circumferential=8, axial_size="1 in") if tiny
        else dict(divisions=8, circumferential=32, axial_size="0.25 in"))

base = batball.load_bat("default")


def turned(ply):
    """A barrel carbon ply turned 15 degrees toward the axis; other plies as they are."""
    if ply.label != "barrel-carbon":
        return ply
    angle = math.copysign(max(abs(ply.angle) - math.radians(15.0), 0.0), ply.angle)  # rad
    return dataclasses.replace(ply, angle=angle)


parts = tuple(dataclasses.replace(part, layup=tuple(turned(p) for p in part.layup))
              for part in base.parts)
custom = dataclasses.replace(base, name="stiff-barrel", parts=parts)
Path("stiff_barrel.toml").write_text(tomli_w.dumps(bat_spec_to_toml_dict(custom)),
                                     encoding="utf-8")
assert batball.load_bat("stiff_barrel.toml") == custom  # the file is the bat that was run

for bat in (base, custom):
    props = batball.props(bat, circumferential=mesh["circumferential"],
                          axial_size=mesh["axial_size"]).summary
    hit = batball.bbs(bat, "type1", speed="110 mph", **mesh).summary
    print(f"{bat.name:<13} {props['weight_oz']:.2f} oz, MOI {props['moi_pivot_oz_in2']:.0f} "
          f"oz*in^2: BBS {hit['bbs_mph']:.1f} mph, BBCOR {hit['bbcor']:.3f}")
if tiny:
    print("(coarse meshes: the values are indicative only)")
