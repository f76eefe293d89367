"""Short reports of a test's summary for a person: every number with its unit.

The command line prints these unless ``--json`` is given; each reads the keys of the test's
``summary.json``.
"""

from __future__ import annotations

from typing import Any


def describe_compression(s: dict[str, Any]) -> str:
    """A short human report of a compression summary, every number with its unit."""
    return "\n".join(
        [
            f"Compression of ball {s['ball']} ({s['ball_mass_oz']:.2f} oz), "
            f"{s['displacement_in']:.3g} in at {s['rate_in_per_min']:.3g} in/min",
            f"  {'compression':<26} {s['compression_lbf']:.1f} lbf",
            f"  {'kinetic / internal energy':<26} {100 * s['kinetic_to_internal_energy']:.3f} %",
            f"  {'top - bottom plate force':<26} "
            f"{100 * s['plate_force_difference_fraction']:.2f} % of the force",
            f"  {'energy balance error':<26} {100 * s['energy_balance_error']:.3f} %",
            f"  {s['n_cells']} hexes, {s['n_steps']} steps, {s['wall_seconds']:.1f} s",
            f"  results in {s['run_folder']}",
        ]
    )


def describe_modal(s: dict[str, Any]) -> str:
    """A short human report of a modal summary beside the seed's Table 3."""
    table = s["seed_table3"]
    lines = [f"Free-free modes of bat {s['bat']} (insert {s['insert']})",
             f"  {'':<10} {'batball':>16} {'experiment':>16} {'seed LS-DYNA':>16}"]  # fmt: skip
    for key, name in (("bending_hz", "bending"), ("hoop_hz", "hoop")):
        ours = ", ".join(f"{f:.0f}" for f in s[key])
        exp = ", ".join(f"{f:.0f}" for f in table[key]["experiment"])
        dyna = ", ".join(f"{f:.0f}" for f in table[key]["seed_lsdyna"])
        lines.append(f"  {name + ' Hz':<10} {ours:>16} {exp:>16} {dyna:>16}")
    lines.append(f"  {s['n_modes']} modes ({s['n_rigid']} rigid), {s['n_shells']} shells, "
                 f"{s['wall_seconds']:.1f} s")  # fmt: skip
    lines.append(f"  results in {s['run_folder']}")
    return "\n".join(lines)


def describe_props(s: dict[str, Any]) -> str:
    """A short human report of a props summary, every number with its unit."""
    return "\n".join(
        [
            f"Mass properties of bat {s['bat']} ({s['length_in']:.1f} in), ASTM F2398",
            f"  {'weight':<28} {s['weight_oz']:.2f} oz",
            f"  {'balance point from knob end':<28} {s['balance_point_in']:.2f} in",
            f"  {'MOI about the pivot':<28} {s['moi_pivot_oz_in2']:.0f} oz*in^2 "
            f"(pivot {s['pivot_in']:g} in from the knob end)",
            f"  {'MOI about the centre of mass':<28} {s['moi_cm_oz_in2']:.0f} oz*in^2",
            f"  {s['n_shells']} shells, {s['wall_seconds']:.2f} s",
            f"  results in {s['run_folder']}",
        ]
    )


def describe_impact(s: dict[str, Any]) -> str:
    """A short human report of an impact summary, every number with its unit."""
    name = s["test"].upper()
    return "\n".join(
        [
            f"{name} of ball {s['ball']} ({s['ball_mass_oz']:.2f} oz) "
            f"at {s['inbound_mph']:.1f} mph",
            f"  {name:<22} {s[s['test']]:.3f}",
            f"  {'rebound speed':<22} {s['rebound_mph']:.1f} mph",
            f"  {'dynamic stiffness':<22} {s['ds_lbf_per_in']:.0f} lb/in",
            f"  {'peak force':<22} {s['peak_force_lbf']:.0f} lbf",
            f"  {'contact time':<22} {s['contact_time_ms']:.3f} ms",
            f"  {'energy balance error':<22} {100 * s['energy_balance_error']:.2f} %",
            f"  {s['n_cells']} hexes, {s['n_steps']} steps, {s['wall_seconds']:.1f} s",
            f"  results in {s['run_folder']}",
        ]
    )


def describe_barrel(s: dict[str, Any]) -> str:
    """A short human report of a barrel summary beside the seed's Table 2."""
    exp, seed = s["seed_table2"]["experiment"], s["seed_table2"]["seed_lsdyna"]
    return "\n".join([
        f"barrel compression of {s['bat']} (mean of {len(s['orientations_deg'])} orientations)",
        f"  preload    {s['preload_lbf']:7.1f} lbf  (experiment {exp['preload_lbf']:.0f}, "
        f"seed FE {seed['preload_lbf']:.0f})",
        f"  final load {s['final_load_lbf']:7.1f} lbf  (experiment {exp['final_load_lbf']:.0f}, "
        f"seed FE {seed['final_load_lbf']:.0f})",
        f"  solver: {s.get('solver', 'static: linear MITC4 shells')}",
        f"  friction during the squeeze: mu = {s.get('insert_friction', 0.0):g} insert-barrel, "
        f"{s.get('platen_friction', 0.0):g} platens-barrel",
        f"  interference pressure {s['interference_pressure_psi']:.1f} psi (thin rings "
        f"{s['interference_pressure_thin_ring_psi']:.1f} psi)",
        f"  {s['n_shells']} shells, {s['wall_seconds']:.1f} s, results in {s['run_folder']}",
    ])  # fmt: skip


def describe_bbs(s: dict[str, Any]) -> str:
    """A short human report of a batted-ball-speed summary, every number with its unit."""
    return "\n".join([
        f"batted-ball speed of {s['ball']} on {s['bat']} at {s['inbound_mph']:.1f} mph",
        f"  BBS {s['bbs_mph']:.2f} mph (v_p {s['pitch_speed_mph']:.0f}, v_b "
        f"{s['swing_speed_mph']:.0f} mph)",
        f"  e_A {s['collision_efficiency']:.4f}, rebound {s['rebound_mph']:.2f} mph, BBCOR "
        f"{s['bbcor']:.4f} (from the bat's rotation {s['bbcor_from_bat_rotation']:.4f}), k "
        f"{s['k']:.4f}",
        f"  peak force {s['peak_force_lbf']:.0f} lbf, contact {s['contact_time_ms']:.3f} ms, "
        f"energy balance error {100 * s['energy_balance_error']:.2f} %",
        *([f"  insert fit {s['interference_pressure_psi']:.1f} psi, "
           + ("restored from the store" if s.get("prestress_reused") else "relaxed in this run")]
          if s.get("interference_pressure_psi") is not None else []),
        f"  {s['n_shells']} {s.get('bat_shell', 'bt').upper()} shells + {s['n_hexes']} hexes, "
        f"{s['n_steps']} steps, "
        f"{s['wall_seconds']:.1f} s, results in {s['run_folder']}",
    ])  # fmt: skip
