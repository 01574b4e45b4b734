"""Is every converged state stable, and has the load passed a limit point?

Newton converging only means the state is stationary. It is a stable equilibrium (a local minimum
of the total energy W) iff the tangent on the free DOFs K_ff is positive definite, so the monitor
counts the negative (and zero) eigenvalues of K_ff by its inertia (:mod:`vlab.fe.inertia`).

Under displacement control a softening material (St. Venant–Kirchhoff in compression: the nominal
stress of a free block peaks at stretch 1/√3) can keep K_ff positive definite past its load
maximum, so the monitor also watches the load path. With u_p = t û_p, the free DOFs follow
du_f/dt = −K_ff⁻¹ K_fp û_p, and the grip force of axis a changes at the rate
    k_a = df_a/dt = Σ_{moving DOFs of a} (K v)_i,   v = (du_f/dt, û_p)      (N per unit t),
the slope of the load–displacement curve at the state itself. A load limit point is passed when
    s_a k_a < 0   or   s_a (f_a(t) − f_a(t_prev)) < −tol · |f_a(t_prev)|,   s_a = sign(λ_a − 1),
i.e. the force magnitude decreases although the grip keeps moving away from 1 (t_prev: the last
accepted state).

With ``MonitorOptions.eigenvalues`` (asked for by a study or the stability suite; off by default
because it costs a shift-invert Lanczos solve per state) every vetted state also records the
lowest eigenvalue of K_ff. Whatever the option, the lowest eigenpair is computed where the sign
changes: at every rejected unstable state and at the last stable state before it. The unstable
state nearest the last stable one is kept as the critical state
(:class:`vlab.checks.buckling.CriticalState`): the bracketed critical stretch, the eigenvalues
on both sides and the eigenvector (the mode shape), classified as buckling or not. A scene that
follows a post-buckled path (``[test] imperfection``) switches the load-limit check off
(``limit_points = False``): there the force falling while K_ff stays positive definite is the
physics being measured, not a collapse.

The monitor vets every converged substep (``Stepping.accept``). A rejected substep makes the
stepper cut back from the last accepted state, which both avoids false alarms (a large step can
land Newton on an unstable branch that a finer path never visits) and brackets the critical
stretch to within the final increment; if the instability persists the test stops with
"no admissible state beyond stretch …" and the unstable state never enters the curve.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from dataclasses import replace as dataclass_replace

import numpy as np

from vlab.fe.assembly import Partition
from vlab.fe.inertia import EigenpairNotFound, factorized_inertia, inertia, lowest_eigenpair
from vlab.fe.linsolve import SingularSystem
from vlab.fe.newton import TangentCache
from vlab.fe.problem import Evaluation, HyperelasticBody
from vlab.fe.stepping import Level
from vlab.checks.buckling import CriticalState, lateral_fraction
from vlab.checks.ellipticity import non_elliptic_fraction

LIMIT_TOL = 1e-9


@dataclass(frozen=True)
class LevelStability:
    """Stability of one converged state (``accepted`` False for a rejected trial)."""

    t: float
    stretch: list[float]
    negative_eigenvalues: int | None
    zero_eigenvalues: int | None
    inertia_method: str
    forces: list[float]
    limit_point: bool
    accepted: bool
    lowest_eigenvalue: float | None = None  # N/mm; only when asked for, or near a sign change

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class MonitorOptions:
    eigenvalues: bool = False  # lowest eigenvalue of K_ff at every vetted state (shift-invert Lanczos)
    limit_points: bool = True  # reject a falling force (off on a post-buckled path)


class StabilityMonitor:
    """``accept(evaluation, t)`` vets a substep; ``monitor(level)`` records a scheduled level.

    ``records`` lists the accepted scheduled levels and every rejected trial, in order.
    """

    def __init__(self, body: HyperelasticBody, partition: Partition, moving_dofs: dict[int, np.ndarray],
                 target_stretch: tuple[float, ...], model: str, u_hat: np.ndarray,
                 options: MonitorOptions = MonitorOptions(), tangents: TangentCache | None = None):
        self.body, self.partition, self.u_hat, self.options = body, partition, u_hat, options
        # shared with the stepper: the tangent factorized here serves its next predictor
        self.tangents = tangents or TangentCache(body, partition)
        self.moving = {a: np.asarray(d) for a, d in moving_dofs.items()}
        self.target = target_stretch
        self.model = model
        self.records: list[LevelStability] = []
        self._accepted: LevelStability | None = None
        self._accepted_Kff = None  # (K_ff, K_ff⁻¹) of the last stable state, for its eigenvalue
        self.critical: CriticalState | None = None

    def stretch_at(self, t: float) -> list[float]:
        return [1.0 + t * (s - 1.0) for s in self.target]

    def accept(self, ev: Evaluation, t: float) -> str | None:
        K, Kff, Kfp, found = self._inertia(ev)
        slopes = None
        if self.options.limit_points:
            try:
                slopes = self._path_stiffness(K, Kfp, found)
            except SingularSystem:  # a Cholesky that succeeded on a numerically singular K_ff
                found = inertia(Kff)
                slopes = self._path_stiffness(K, Kfp, found)
        forces = [float(ev.f_int[self.moving[a]].sum()) for a in range(len(self.target))]
        limit_axis = self._limit_axis(forces, slopes) if self.options.limit_points else None
        unstable = bool(found.negative) or bool(found.zero)
        solve = found.solve if not found.zero else None  # a singular K_ff: factorize K − σI instead
        pair = _eigenpair(Kff, found.negative, solve) if unstable or self.options.eigenvalues else None
        record = LevelStability(float(t), self.stretch_at(t), found.negative, found.zero,
                                found.method, forces, limit_axis is not None,
                                accepted=not unstable and limit_axis is None,
                                lowest_eigenvalue=None if pair is None else pair[0])
        if record.accepted:
            self._accepted, self._accepted_Kff = record, (Kff, found.solve)
            return None
        self.records.append(record)
        if unstable:
            self.critical = self._critical_state(record, pair, ev)
            return self._instability_message(record)
        return self._limit_message(record, limit_axis)

    def __call__(self, level: Level) -> None:
        """Record the (already vetted) state of a scheduled level."""
        if self._accepted is not None and self._accepted.t == level.t:
            self.records.append(self._accepted)

    def _inertia(self, ev: Evaluation):
        """K, K_ff, K_fp and the inertia of K_ff, from the Newton solver's factorization when it
        is conclusive (a Cholesky, or SuperLU's symmetric LDLᵀ), else from a separate count."""
        try:
            tangent = self.tangents.at(ev)
        except SingularSystem:
            K = self.body.stiffness(ev)
            Kff, Kfp = self.partition.blocks(K)
            return K, Kff, Kfp, inertia(Kff)
        Kff = self.partition.blocks(tangent.K)[0]
        # the stepper verified the unloaded K_ff (no free rigid modes), so a Cholesky here
        # needs no second look for a zero eigenvalue (vlab.fe.stepping._check_restrained)
        return tangent.K, Kff, tangent.Kfp, factorized_inertia(tangent.factor, Kff, verify_zero=False)

    def _critical_state(self, r: LevelStability, pair, ev: Evaluation) -> CriticalState:
        """The bracket [last stable, this unstable state] with both lowest eigenvalues and the
        mode; each later rejection lies nearer the last stable state, so it replaces the last."""
        stable = self._accepted
        eig_stable = stable.lowest_eigenvalue if stable is not None else None
        if stable is not None and eig_stable is None and self._accepted_Kff is not None:
            Kff_stable, solve_stable = self._accepted_Kff
            found = _eigenpair(Kff_stable, 0, solve_stable)
            eig_stable = None if found is None else found[0]
            self._accepted = stable = dataclass_replace(stable, lowest_eigenvalue=eig_stable)
        mode = None
        if pair is not None:
            mode = np.zeros(self.body.space.n_dofs)
            mode[self.partition.free] = pair[1]
        axis = 0
        return CriticalState(
            stretch_stable=stable.stretch if stable else self.stretch_at(0.0), stretch_unstable=r.stretch,
            eigenvalue_stable=eig_stable, eigenvalue_unstable=None if pair is None else pair[0],
            force_stable=stable.forces if stable else [0.0] * len(self.target),
            negative_eigenvalues=int(r.negative_eigenvalues or 0),
            lateral_fraction=None if mode is None else lateral_fraction(self.body.space.node_coordinates, mode, axis),
            mode=mode,
            non_elliptic_fraction=self._non_elliptic(ev))

    def _non_elliptic(self, ev: Evaluation) -> float | None:
        material = getattr(self.body, "material", None)  # the spring network has no tangent field
        if material is None or self.body.space.dim != 3:  # the 2D plane laws: not sampled here
            return None
        if hasattr(material, "respond"):  # a history law: the algorithmic tangent K_ff was built from
            state = getattr(self.body, "state", None)
            if state is None:
                return None
            return non_elliptic_fraction(material.respond(ev.F, state, self.body.dt, with_tangent=True).tangent)
        return non_elliptic_fraction(material.tangent(ev.F))

    def _path_stiffness(self, K, Kfp, found) -> list[float] | None:
        """df_a/dt along the displacement-controlled path (None if K_ff could not be solved)."""
        if found.solve is None or found.negative or found.zero:
            return None
        up = self.u_hat[self.partition.prescribed]
        v = self.u_hat.copy()
        v[self.partition.free] = -found.solve(Kfp @ up)
        Kv = K @ v
        return [float(Kv[self.moving[a]].sum()) for a in range(len(self.target))]

    def _limit_axis(self, forces: list[float], slopes: list[float] | None) -> int | None:
        last = self._accepted
        for a, f_new in enumerate(forces):
            sign = np.sign(self.target[a] - 1.0)
            if sign == 0:
                continue
            if slopes is not None and sign * slopes[a] < 0.0:
                return a
            f_old = last.forces[a] if last is not None else None
            if f_old is not None and sign * (f_new - f_old) < -LIMIT_TOL * abs(f_old):
                return a
        return None

    def _previous_stretch(self) -> str:
        return _fmt(self._accepted.stretch if self._accepted else self.stretch_at(0.0))

    def _instability_message(self, r: LevelStability) -> str:
        c = self.critical
        if c is not None and c.is_buckling:
            lo, hi = c.strain_bracket()
            return (f"no admissible state beyond stretch {self._previous_stretch()}: buckling — loss of "
                    f"stability between grip strain {lo:.4g} and {hi:.4g} (stretch "
                    f"{_fmt(r.stretch)}: {r.negative_eigenvalues} negative eigenvalue(s); the mode moves "
                    f"whole cross-sections sideways, lateral fraction {c.lateral_fraction:.2f}); set "
                    f"test.imperfection to follow the post-buckled path")
        what = (f"{r.negative_eigenvalues} negative eigenvalue(s)" if r.negative_eigenvalues
                else f"{r.zero_eigenvalues} zero eigenvalue(s)")
        return (f"no admissible state beyond stretch {self._previous_stretch()}: loss of stability "
                f"at stretch {_fmt(r.stretch)} — the tangent on the free DOFs has {what}, so the "
                f"converged state is not an energy minimum ({self.model}; {self._kind(c)})")

    @staticmethod
    def _kind(c: CriticalState | None) -> str:
        if c is None or c.mode is None:
            return "a bifurcation"
        if c.non_elliptic_fraction:
            return (f"loss of ellipticity: the material tangent admits a deformation band at "
                    f"{100 * c.non_elliptic_fraction:.3g} % of the quadrature points, a material instability")
        return "a structural bifurcation whose mode is local, not a sideways buckle"


    def _limit_message(self, r: LevelStability, axis: int) -> str:
        advice = (" (St. Venant–Kirchhoff softens in compression, limit point at stretch 1/√3 "
                  "≈ 0.577 for a free block; stvk-volumetric and neo-hookean carry on)"
                  if self.model == "stvk" else "")
        return (f"no admissible state beyond stretch {self._previous_stretch()}: load limit point — "
                f"|force| along {'xy'[axis]} peaked and fell at stretch {_fmt(r.stretch)}{advice}")


def _fmt(stretch: list[float]) -> str:
    return ", ".join(f"{s:.4g}" for s in stretch) if len(stretch) > 1 else f"{stretch[0]:.4g}"


def _eigenpair(Kff, negative, solve):
    """The lowest eigenpair, or None when Lanczos fails: the inertia alone still decides stability,
    the report then shows no eigenvalue or mode rather than stopping the run."""
    try:
        return lowest_eigenpair(Kff, negative, solve)
    except EigenpairNotFound:
        return None
