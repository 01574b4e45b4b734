"""Test protocols: how the grips move in time (``[test] protocol``).

The grips prescribe u_p = t · û_p, where û_p moves the grips to the scene's ``stretch`` (for
``cyclic``: the largest amplitude), so the grip stretch is λ(t) = 1 + t (λ_max − 1). Only the grip
strain λ − 1 at t = 1 enters here: a simple-shear test passes 1 + γ (its kind's ``grip_strain``). A protocol
becomes a list of *levels*: the load parameter t_k, the physical time τ_k (s) and whether the
moving grip is held by displacement or by force there.

- ``monotonic``    1 → stretch (today's test; time only if a rate is given)
- ``load-unload``  1 → stretch → 1
- ``cyclic``       1 → a₁ → λ_min → a₂ → λ_min → … (``amplitudes`` rising; λ_min =
                   ``min_stretch``, default 1); simple shear: fully reversed cycles
                   0 → γ₁ → −γ₁ → γ₂ → −γ₂ → … → 0 (``reversed``)
- ``relaxation``   1 → stretch, then the stretch held for ``hold_time`` s
- ``creep``        1 → stretch under displacement control, then the force reached there held
                   for ``hold_time`` s (force control: the crosshead position is an unknown
                   whose conjugate load is the held force; see vlab.fe.force_control);
                   with ``force`` (N) the ramp itself is force-controlled, 0 → force linearly
                   over ``ramp_time`` s in ``steps`` levels, and that force is held

Time: ``strain_rate`` (s⁻¹) is the grip strain rate |dλ/dt| of every ramp; or ``ramp_time`` (s)
is the duration of the first ramp 1 → stretch (the same rate then applies to every ramp).
Holds are sampled at ``hold_steps`` levels whose spacing grows geometrically, because a
relaxation or creep transient is fast at first and slow at the end.

The first ramp carries the extra levels of the modulus window (vlab.loading.schedule), so E and ν
are still fitted from the first loading.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.loading.schedule import monotonic_schedule

PROTOCOLS = ("monotonic", "load-unload", "cyclic", "relaxation", "creep")
HOLDS = ("relaxation", "creep")


@dataclass(frozen=True)
class ProtocolSpec:
    name: str = "monotonic"
    amplitudes: tuple[float, ...] = ()  # cyclic: peak grip stretches, rising
    min_stretch: float = 1.0  # cyclic: grip stretch each cycle returns to
    strain_rate: float | None = None  # 1/s, grip strain rate of every ramp
    ramp_time: float | None = None  # s, duration of the first ramp 1 -> stretch
    hold_time: float = 0.0  # s (relaxation, creep)
    hold_steps: int = 20  # levels over the hold
    force: float | None = None  # N, creep: the load ramped to under force control and held
    reversed: bool = False  # cyclic: fully reversed cycles 0 → a₁ → −a₁ → a₂ → … → 0 (amplitudes in
    #                         the control's own units, e.g. the amount of shear γ)

    @property
    def timed(self) -> bool:
        return self.strain_rate is not None or self.ramp_time is not None

    @property
    def has_hold(self) -> bool:
        return self.name in HOLDS

    @property
    def unloads(self) -> bool:
        return self.name in ("load-unload", "cyclic")


@dataclass(frozen=True)
class Levels:
    """Load parameter t_k, physical time τ_k in s (None if the test is quasi-static) and, per
    level, True where the moving grip is force-controlled (the creep hold); ``force`` the
    grip force (N) each force-controlled level reaches (None: hold the force reached)."""

    t: np.ndarray
    time: np.ndarray | None
    force_held: np.ndarray
    force: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.t)


def protocol_levels(protocol: ProtocolSpec, stretch: tuple[float, ...], steps: int,
                    window: tuple[float, float], modulus_points: int) -> Levels:
    """The levels of a protocol; ``steps`` is the number of increments of a ramp over the full
    range 1 → stretch (shorter ramps get proportionally fewer, at least one)."""
    if protocol.force is not None:
        return _force_ramp_levels(protocol, steps)
    targets = _turning_points(protocol, stretch)
    peak = targets[0]
    peak_stretch = tuple(1.0 + peak * (s - 1.0) for s in stretch)
    first = peak * monotonic_schedule(peak_stretch, max(1, int(np.ceil(peak * steps - 1e-9))),
                                      window, modulus_points)
    t = list(first)
    for a, b in zip(targets[:-1], targets[1:]):
        n = max(1, int(np.ceil(abs(b - a) * steps - 1e-9)))
        t.extend(a + (b - a) * np.arange(1, n + 1) / n)
    t_arr = np.array(t)
    n_ramp = len(t_arr)
    if protocol.has_hold:
        t_arr = np.concatenate([t_arr, np.full(protocol.hold_steps, t_arr[-1])])
    held = np.zeros(len(t_arr), dtype=bool)
    if protocol.name == "creep":
        held[n_ramp:] = True
    return Levels(t_arr, _times(protocol, stretch, t_arr, n_ramp), held)


def _force_ramp_levels(protocol: ProtocolSpec, steps: int) -> Levels:
    """Creep with a given force: ``steps`` levels of a linear force ramp over ``ramp_time``,
    then the hold; every level force-controlled. t holds the force fraction (for the times);
    the grip position is solved for."""
    fraction = np.arange(1, steps + 1) / steps
    n = len(fraction) + protocol.hold_steps
    t = np.concatenate([fraction, np.ones(protocol.hold_steps)])
    ramp = ProtocolSpec(name=protocol.name, ramp_time=protocol.ramp_time, hold_time=protocol.hold_time,
                        hold_steps=protocol.hold_steps)
    return Levels(t, _times(ramp, (2.0,), t, len(fraction)), np.ones(n, dtype=bool), protocol.force * t)


def _turning_points(protocol: ProtocolSpec, stretch: tuple[float, ...]) -> list[float]:
    """Load parameters where the ramps after the first one start and end."""
    if protocol.name == "load-unload":
        return [1.0, 0.0]
    if protocol.name == "cyclic" and protocol.reversed:
        top = protocol.amplitudes[-1]
        return [x for a in protocol.amplitudes for x in (a / top, -a / top)] + [0.0]
    if protocol.name == "cyclic":
        top = stretch[0] - 1.0
        low = (protocol.min_stretch - 1.0) / top
        points = [(protocol.amplitudes[0] - 1.0) / top]
        for a in protocol.amplitudes[1:]:
            points += [low, (a - 1.0) / top]
        return points + [low]
    return [1.0]


def first_peak(protocol: ProtocolSpec, stretch: tuple[float, ...]) -> float:
    """Load parameter at the end of the first ramp."""
    return _turning_points(protocol, stretch)[0]


def _times(protocol: ProtocolSpec, stretch: tuple[float, ...], t: np.ndarray, n_ramp: int):
    if not protocol.timed:
        return None
    span = max(abs(s - 1.0) for s in stretch)  # grip strain at t = 1
    rate = protocol.strain_rate if protocol.strain_rate is not None else span / protocol.ramp_time
    ramp_dt = np.abs(np.diff(np.concatenate([[0.0], t[:n_ramp]]))) * span / rate
    times = np.cumsum(ramp_dt)
    if n_ramp == len(t):
        return times
    n = len(t) - n_ramp
    first = min(protocol.hold_time / n, float(np.min(ramp_dt[ramp_dt > 0], initial=protocol.hold_time)))
    hold = np.geomspace(first, protocol.hold_time, n) if n > 1 else np.array([protocol.hold_time])
    return np.concatenate([times, times[-1] + hold])
