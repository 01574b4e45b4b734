"""Is every converged state stable, and has the load passed a limit point?

Newton converging only means the state is stationary. It is a stable equilibrium (a local minimum
of the total energy W) iff the tangent on the free DOFs K_ff is positive definite, so the monitor
counts the negative (and zero) eigenvalues of K_ff by its inertia (:mod:`vlab.fe.inertia`).

Under displacement control a softening material (St. Venant–Kirchhoff in compression: the nominal
stress of a free block peaks at stretch 1/√3) can keep K_ff positive definite past its load
maximum, so the monitor also watches the load path. With u_p = t û_p, the free DOFs follow
du_f/dt = −K_ff⁻¹ K_fp û_p, and the load conjugate to t, Q = ûᵀ f_int (N·mm: Σ_a travel_a ×
force_a), changes at the rate
    dQ/dt = vᵀ K v,   v = (du_f/dt, û_p)                                  (N·mm per unit t),
since (K v)_f = 0: the directional stiffness of the body along the prescribed path (twice the
strain energy of the mode v for a linear body, so never ≤ 0 there). A load limit point is passed
when
    vᵀ K v ≤ 0   or   Q(t) − Q(t_prev) < −tol · |Q(t_prev)|      (t_prev: the last accepted state),
i.e. the work the grips do per unit travel falls although the grips keep moving. A single axis'
force is not the criterion: in a biaxial test with one axis in compression the lateral
(Poisson) push makes that axis' force start with the "wrong" sign and pass through zero, and
its magnitude may peak and fall while the body stiffens along the path it is driven on.

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
"no stable state beyond stretch …" (the state exists, but is not an energy minimum) or
"load limit point beyond stretch …", and the unstable state never enters the curve.
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
from vlab.fe.timers import STABILITY, timed
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
    path_load: float | None = None  # Q = ûᵀ f_int, N·mm
    path_stiffness: float | None = None  # dQ/dt = vᵀ K v, N·mm per unit t (None: not computed)
    stability_method: str = ""  # what vetted it: ldlt-inertia | cholesky | dense-eigenvalues | lobpcg-amg
    eigenpair_residual: float | None = None  # ‖K x − λ x‖ / max|K_ii| of the LOBPCG pair

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class MonitorOptions:
    eigenvalues: bool = False  # lowest eigenvalue of K_ff at every vetted state (shift-invert Lanczos)
    limit_points: bool = True  # reject a falling force (off on a post-buckled path)
    locking_nu: float | None = None  # ν of locking-prone displacement-only elements (vlab.checks.locking)


class StabilityMonitor:
    """``accept(evaluation, t)`` vets a substep; ``monitor(level)`` records a scheduled level.

    ``records`` lists the accepted scheduled levels and every rejected trial, in order.
    """

    def __init__(self, body: HyperelasticBody, partition: Partition, moving_dofs: dict[int, np.ndarray],
                 kind, targets: tuple[float, ...], model: str, u_hat: np.ndarray,
                 options: MonitorOptions = MonitorOptions(), tangents: TangentCache | None = None):
        """``kind`` (vlab.loading.kinds) maps the load parameter t to the control values (grip
        stretches, or the amount of shear) of ``targets`` and words them; ``moving_dofs`` holds
        the load cells watched for limit points, by axis (the kind's)."""
        self.body, self.partition, self.u_hat, self.options = body, partition, u_hat, options
        # shared with the stepper: the tangent factorized here serves its next predictor
        self.tangents = tangents or TangentCache(body, partition)
        self.moving = {a: np.asarray(d) for a, d in moving_dofs.items()}
        self.kind, self.target = kind, targets
        self.direction = [float(np.sign(g)) for g in kind.grip_strain(targets)]  # sign of each grip's travel
        self.model = model
        self.records: list[LevelStability] = []
        self._accepted: LevelStability | None = None
        self._accepted_Kff = None  # (K_ff, K_ff⁻¹) of the last stable state, for its eigenvalue
        self.critical: CriticalState | None = None
        self._trial_plastic_strain: float | None = None  # largest α of the last unstable trial
        self._path_tangent: np.ndarray | None = None  # the last v_f on the iterative path, CG's start

    def stretch_at(self, t: float) -> list[float]:
        return self.kind.at(self.target, t)

    def accept(self, ev: Evaluation, t: float) -> str | None:
        Kpp, Kff, Kfp, found = self._inertia(ev)
        slope = None
        if self.options.limit_points:
            try:
                slope = self._path_stiffness(Kff, Kfp, Kpp, found)
            except SingularSystem:  # a Cholesky that succeeded on a numerically singular K_ff,
                found = self._recount(Kff, found)  # or CG's negative curvature after LOBPCG
                slope = self._path_stiffness(Kff, Kfp, Kpp, found)
        forces = [float(ev.f_int[self.moving[a]].sum()) for a in range(len(self.direction))]
        load = float(self.u_hat @ ev.f_int)
        limit = self._is_limit(load, slope) if self.options.limit_points else False
        unstable = bool(found.negative) or bool(found.zero)
        solve = found.solve if not found.zero else None  # a singular K_ff: factorize K − σI instead
        pair = found.lowest  # LOBPCG finds it anyway; a factorization needs a Lanczos solve
        if pair is None and (unstable or self.options.eigenvalues):
            pair = _eigenpair(Kff, found.negative, solve)
        record = LevelStability(float(t), self.stretch_at(t), found.negative, found.zero,
                                found.method, forces, limit, accepted=not unstable and not limit,
                                lowest_eigenvalue=None if pair is None else pair[0],
                                path_load=load, path_stiffness=slope, stability_method=found.key,
                                eigenpair_residual=found.residual)
        if record.accepted:
            # K_ff is kept only while the state's lowest eigenvalue is unknown (a bracket needs
            # it); LOBPCG's states carry theirs, and a large run then holds one K_ff less
            self._accepted = record
            self._accepted_Kff = (Kff, found.solve) if record.lowest_eigenvalue is None else None
            return None
        self.records.append(record)
        if unstable:
            self.critical = self._critical_state(record, pair, ev)
            self._trial_plastic_strain = _plastic_strain(self.body, ev)
            return self._instability_message(record)
        return self._limit_message(record)

    def __call__(self, level: Level) -> None:
        """Record the (already vetted) state of a scheduled level."""
        if self._accepted is not None and self._accepted.t == level.t:
            self.records.append(self._accepted)

    @timed(STABILITY)
    def _inertia(self, ev: Evaluation):
        """K_pp, K_ff, K_fp and the inertia of K_ff, from the Newton solver's factorization when it
        is conclusive (a Cholesky, or SuperLU's symmetric LDLᵀ), from LOBPCG with the AMG
        hierarchy on the iterative path (no factorization), else from a separate count."""
        try:
            tangent = self.tangents.at(ev)
        except SingularSystem:
            K = self.body.stiffness(ev)
            Kff, Kfp = self.partition.blocks(K)
            return self.partition.prescribed_block(K), Kff, Kfp, inertia(Kff)
        # the stepper verified the unloaded K_ff (no free rigid modes), so a Cholesky here
        # needs no second look for a zero eigenvalue (vlab.fe.stepping._check_restrained)
        found = factorized_inertia(tangent.factor, tangent.Kff, verify_zero=False,
                                   accurate=self.options.eigenvalues)
        return tangent.Kpp, tangent.Kff, tangent.Kfp, found

    def _recount(self, Kff, found):
        """The inertia again after the solve with ``found`` failed: on the iterative path LOBPCG
        with CG's negative-curvature witness in its block (a certificate: λ₁ ≤ pᵀKp/pᵀp ≤ 0),
        else (or if that still finds K_ff definite) the direct count."""
        tangent = self.tangents.holds_any()
        if found.key == "lobpcg-amg" and tangent is not None and tangent.factor.backend == "cg-amg" \
                and tangent.factor.hierarchy.witness is not None:
            again = factorized_inertia(tangent.factor, Kff)
            if again.negative or again.zero:
                return again
        return inertia(Kff)

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
            force_stable=stable.forces if stable else [0.0] * len(self.direction),
            negative_eigenvalues=int(r.negative_eigenvalues or 0),
            lateral_fraction=None if mode is None else lateral_fraction(self.body.space.node_coordinates, mode, axis),
            mode=mode,
            non_elliptic_fraction=self._non_elliptic(ev), locking_nu=self.options.locking_nu)

    def _non_elliptic(self, ev: Evaluation) -> float | None:
        material = self.body.material  # None: the spring network has no tangent field
        if material is None or self.body.space.dim != 3:  # the 2D plane laws: not sampled here
            return None
        history = self.body.history
        if history is not None:  # a history law: the algorithmic tangent K_ff was built from
            return non_elliptic_fraction(material.respond(ev.F, history.state, history.dt, with_tangent=True).tangent)
        return non_elliptic_fraction(material.tangent(ev.F))

    def _path_stiffness(self, Kff, Kfp, Kpp, found) -> float | None:
        """dQ/dt = vᵀ K v along the displacement-controlled path v = (v_f, û_p), v_f = −K_ff⁻¹K_fp û_p,
        by blocks: v_fᵀK_ff v_f + 2 v_fᵀK_fp û_p + û_pᵀK_pp û_p (None if K_ff could not be solved).
        CG (the iterative path) starts from the last state's v_f: the same û_p on a tangent that
        moved little (initial residual 6e-5 between the sphere octant's small first steps)."""
        if found.solve is None or found.negative or found.zero:
            return None
        up = self.u_hat[self.partition.prescribed]
        coupling = Kfp @ up
        if found.key == "lobpcg-amg":
            vf = -found.solve(coupling, x0=None if self._path_tangent is None else -self._path_tangent)
            self._path_tangent = vf
        else:
            vf = -found.solve(coupling)
        return float(vf @ (Kff @ vf) + 2.0 * (vf @ coupling) + up @ (Kpp @ up))

    def _is_limit(self, load: float, slope: float | None) -> bool:
        """The load Q conjugate to t stops rising: its tangent slope vᵀKv ≤ 0, or it fell since
        the last accepted state (the secant catches a maximum stepped over between two states)."""
        if slope is not None and slope <= 0.0:
            return True
        last = self._accepted
        return last is not None and last.path_load is not None and \
            load - last.path_load < -LIMIT_TOL * abs(last.path_load)

    def _fmt(self, values: list[float]) -> str:
        """The control values named by the kind: "stretch 1.2", "shear 0.5", "twist 0.1 rad/mm"."""
        return self.kind.describe(values)

    def _previous_stretch(self) -> str:
        return self._fmt(self._accepted.stretch if self._accepted else self.stretch_at(0.0))

    def _instability_message(self, r: LevelStability) -> str:
        c = self.critical
        if c is not None and c.is_buckling:
            lo, hi = c.strain_bracket()
            return (f"no stable state beyond {self._previous_stretch()}: buckling — loss of "
                    f"stability between grip strain {lo:.4g} and {hi:.4g} ("
                    f"{self._fmt(r.stretch)}: {r.negative_eigenvalues} negative eigenvalue(s); the mode moves "
                    f"whole cross-sections sideways, lateral fraction {c.lateral_fraction:.2f}); set "
                    f"test.imperfection to follow the post-buckled path")
        what = (f"{r.negative_eigenvalues} negative eigenvalue(s)" if r.negative_eigenvalues
                else f"{r.zero_eigenvalues} zero eigenvalue(s)")
        what_lost = "an unconfirmed loss of stability" if c is not None and c.suspect else "loss of stability"
        return (f"no stable state beyond {self._previous_stretch()}: {what_lost} "
                f"at {self._fmt(r.stretch)} — the tangent on the free DOFs has {what}, so the "
                f"converged state is not an energy minimum ({self.model}; {self._kind(c)}"
                f"{self._yield_note()})")

    @staticmethod
    def _kind(c: CriticalState | None) -> str:
        if c is None or c.mode is None:
            return "a bifurcation"
        if c.suspect:
            return (f"not evidence of a physical instability: the material is strongly elliptic at every "
                    f"point and the mode is local, while displacement-only elements at nu = {c.locking_nu:g} "
                    f"lock on this non-uniform field, which can make the discrete tangent indefinite where "
                    f"the solid is stable; mesh.formulation = 'mixed' tells the two apart")
        if c.non_elliptic_fraction:
            return (f"loss of ellipticity: the material tangent admits a deformation band at "
                    f"{100 * c.non_elliptic_fraction:.3g} % of the quadrature points, a material instability")
        if c.sideways:
            return (f"a bifurcation in tension: the mode moves whole cross-sections sideways (lateral "
                    f"fraction {c.lateral_fraction:.2f}), but no grip compresses the specimen, so it "
                    f"is not buckling and no imperfection can follow it")
        return "a structural bifurcation whose mode is local, not a sideways buckle"

    def _yield_note(self) -> str:
        """What a history law measured at the unstable state: its largest plastic strain."""
        alpha = self._trial_plastic_strain
        if alpha is None or not alpha > 0.0:
            return ""
        return (f"; the material has yielded: accumulated plastic strain up to {alpha:.3g} at this "
                f"state, where a plastic material's tangent stiffness is only its hardening")


    def _limit_message(self, r: LevelStability) -> str:
        advice = (" (St. Venant–Kirchhoff softens in compression, limit point at stretch 1/√3 "
                  "≈ 0.577 for a free block; stvk-volumetric and neo-hookean carry on)"
                  if self.model == "stvk" else "")
        last = self._accepted
        measured = (f"the path stiffness dQ/dt = vᵀKv = {r.path_stiffness:.4g} N·mm ≤ 0"
                    if r.path_stiffness is not None and r.path_stiffness <= 0.0 else
                    f"Q fell from {last.path_load:.6g} to {r.path_load:.6g} N·mm")
        return (f"load limit point beyond {self._previous_stretch()}: the grip load along the "
                f"prescribed path (Q = ûᵀf, the work-conjugate of the grip travel) no longer rises at "
                f"{self._fmt(r.stretch)}: {measured}{advice}")


def _plastic_strain(body, ev: Evaluation) -> float | None:
    """Largest accumulated plastic strain α of the (uncommitted) trial state ``ev``, or None."""
    history, material = body.history, body.material
    if history is None or material.history_fields is None:
        return None
    trial = material.update(ev.F, history.state, history.dt)
    alpha = material.history_fields(trial, ev.F).get("plastic_strain")
    return None if alpha is None else float(np.max(alpha))




@timed(STABILITY)
def _eigenpair(Kff, negative, solve):
    """The lowest eigenpair, or None when Lanczos fails: the inertia alone still decides stability,
    the report then shows no eigenvalue or mode rather than stopping the run."""
    try:
        return lowest_eigenpair(Kff, negative, solve)
    except EigenpairNotFound:
        return None
