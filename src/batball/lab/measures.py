"""Ball-impact measurements, defined once, as the standards define them.

* COR (ASTM F1887, flat wall) and CCOR (ASTM F2845, 2.63-in half-cylinder): the rebound speed over
  the inbound speed of the ball's centre of mass, the rebound taken after the ball has separated
  from the target (then the centre-of-mass velocity is constant: no other force acts).
* Dynamic stiffness (ASTM F2845, "normalised by ball weight and speed"): the linear-spring form
  DS = F_peak^2 / (m v_in^2) [lbf/in], which returns k exactly for an undamped spring ball.
* Peak force: the largest load-cell force, i.e. the target's reaction along the flight path.
* Contact time: no standard definition exists (docs/physics.md section 3.3). Here it is the time
  from the first to the last instant the force is at or above ``threshold`` times the peak force
  (default 1 %, as in the OpenRadioss peer run of ``docs/physics.md`` section 9); a threshold
  of 0 gives the span of any non-zero force.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from batball.errors import SpecError


@dataclass(frozen=True)
class ImpactMeasures:
    """Measured quantities of one impact, SI.

    Attributes:
        restitution: rebound over inbound speed (CCOR or COR).
        dynamic_stiffness: F_peak^2 / (m v_in^2) [N/m].
        peak_force: [N]; contact_time: [s]; time_of_peak: [s].
        inbound_speed, rebound_speed: [m/s].
    """

    restitution: float
    dynamic_stiffness: float
    peak_force: float
    contact_time: float
    time_of_peak: float
    inbound_speed: float
    rebound_speed: float


def dynamic_stiffness(peak_force: float, mass: float, speed: float) -> float:
    """DS = F_peak^2 / (m v^2) [N/m] for F [N], m [kg], v [m/s]."""
    return peak_force**2 / (mass * speed**2)


def contact_duration(time: np.ndarray, force: np.ndarray, *, threshold: float) -> float:
    """Span between the first and last sample with force >= threshold * peak [s].

    Args:
        time: (n,) sample times [s]; force: (n,) load-cell force [N].
        threshold: fraction of the peak force, 0 <= threshold < 1 (0: any positive force).
    """
    if not 0.0 <= threshold < 1.0:
        raise SpecError("contact_threshold", threshold, "0 <= threshold < 1 (fraction of peak)")
    peak = float(force.max())
    if not peak > 0:
        return 0.0
    level = threshold * peak
    above = np.flatnonzero(force > level) if threshold == 0 else np.flatnonzero(force >= level)
    return float(time[above[-1]] - time[above[0]])


def measure_impact(
    time: np.ndarray,
    force: np.ndarray,
    com_velocity: np.ndarray,
    *,
    inbound: np.ndarray,
    mass: float,
    threshold: float,
) -> ImpactMeasures:
    """Measure an impact from its histories.

    Args:
        time: (n,) [s]; force: (n,) load-cell force along the flight path [N].
        com_velocity: (n, 3) centre-of-mass velocity [m/s]; the last row must be after separation.
        inbound: (3,) initial velocity [m/s]; mass: ball mass [kg].
        threshold: contact-time threshold, fraction of the peak force.
    """
    v_in = float(np.linalg.norm(inbound))
    direction = inbound / v_in
    rebound = float(-com_velocity[-1] @ direction)
    k = int(np.argmax(force))
    peak = float(force[k])
    return ImpactMeasures(
        restitution=rebound / v_in,
        dynamic_stiffness=dynamic_stiffness(peak, mass, v_in),
        peak_force=peak,
        contact_time=contact_duration(time, force, threshold=threshold),
        time_of_peak=float(time[k]),
        inbound_speed=v_in,
        rebound_speed=rebound,
    )


def max_approach(time: np.ndarray, velocity: np.ndarray, in_contact: np.ndarray) -> float:
    """The ball's deflection in an impact: the largest distance its centre of mass travels
    toward the target after the first contact [m], the time integral (trapezoidal) of
    ``velocity`` (n_steps,) [m/s], its centre-of-mass velocity along the flight line, from the
    first step where ``in_contact`` (n_steps,) is true, over ``time`` (n_steps,) [s]. Of a
    spring ball this is the spring's largest compression (m v^2 / F_peak); it includes the
    penalty's penetration into the target, which it is compared with. 0 without contact."""
    touching = np.flatnonzero(in_contact)
    if touching.size == 0:
        return 0.0
    first = touching[0]
    t, v = time[first:], velocity[first:]
    travel = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    return float(travel.max())
