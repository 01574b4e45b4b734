"""The fitted Ogden–Roxburgh softening (``[model] mullins``) over the ground law, along a
homogeneous history, written for the complex step (vlab.materials.mullins is the run's form).

    mullins = true                  # fit r, m and mullins_beta with the ground law
    mullins = { beta = 0.0 }        # fit r and m, hold β fixed

The state is W_max, the largest ground energy ψ0 reached so far (MPa); below it the stress is
η P0 with

    z = max(0, (W_max − ψ0) / (m + β W_max)),   η = 1 − erf(z) / r,

and on the primary path (ψ0 ≥ W_max) η = 1. `vlab run` updates W_max after each converged level
and evaluates the next level with the previous W_max; since η = 1 whenever ψ0 ≥ W_max, that is the
running maximum over the history including the current point, used here. In an incompressible
homogeneous state the pressure is scaled with the rest (the traction-free direction stays free),
so the nominal stress is P_1 = η (w_1 − w_f) / λ1. The ground energies ψ0(λ1, λ2, λ3) at J = 1
(MPa; vlab's compressible Neo-Hookean reduces to μ/2 (I1 − 3) there):

    neo-hookean μ/2 (I1 − 3); mooney-rivlin C10 (I1 − 3) + C01 (I2 − 3); yeoh Σ C_k0 (I1 − 3)^k;
    gent −μ Jm/2 ln(1 − (I1 − 3)/Jm); arruda-boyce μ Σ c_i λm^(2−2i) (I1^i − 3^i);
    ogden Σ 2μ_p/α_p² (λ1^α_p + λ2^α_p + λ3^α_p − 3).

erf is scipy's, analytic in a complex argument; the max and the running maximum choose by the
real part, so a complex-step derivative flows through the chosen branch exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table

__all__ = ["MullinsSpec", "parse_mullins", "energy", "softened_stress"]

_AB = (1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750)


@dataclass(frozen=True)
class MullinsSpec:
    beta: float | None = None  # fixed β; None: fitted

    @property
    def names(self) -> tuple[str, ...]:
        return ("r", "m") + (("mullins_beta",) if self.beta is None else ())

    def split(self, X):
        """(r, m, β), each (m_rows, 1), from the trailing entries of X."""
        k = len(self.names)
        r, m = X[:, -k][:, None], X[:, -k + 1][:, None]
        beta = X[:, -1][:, None] if self.beta is None else np.full_like(r, self.beta)
        return r, m, beta


def parse_mullins(raw) -> MullinsSpec | None:
    if raw is None or raw is False:
        return None
    if raw is True:
        return MullinsSpec()
    if not isinstance(raw, dict):
        raise SceneError(f"model.mullins must be true, false or {{ beta = ... }} (β held fixed), got {fields.show(raw)}")
    t = Table("model.mullins", raw, ("beta",))
    return MullinsSpec(t.number("beta", gt=None, ge=0.0, note=" (dimensionless; held fixed)"))


def energy(law, c, l1, l2, l3):
    """ψ0 (MPa) of the law at an incompressible state (card values c broadcast with λ)."""
    sq = (l1 * l1, l2 * l2, l3 * l3)
    I1 = sq[0] + sq[1] + sq[2]
    I2 = sq[0] * sq[1] + sq[1] * sq[2] + sq[0] * sq[2]
    if law.model == "neo-hookean":
        return 0.5 * c[0] * (I1 - 3.0)
    if law.model == "mooney-rivlin":
        return c[0] * (I1 - 3.0) + c[1] * (I2 - 3.0)
    if law.model == "yeoh":
        return sum(c[k] * (I1 - 3.0) ** (k + 1) for k in range(3))
    if law.model == "gent":
        return -0.5 * c[0] * c[1] * np.log(1.0 - (I1 - 3.0) / c[1])
    if law.model == "arruda-boyce":
        return c[0] * sum(a * c[1] ** (2 - 2 * i) * (I1 ** i - 3.0 ** i) for i, a in enumerate(_AB, start=1))
    n = law.terms
    return sum(2.0 * c[p] / c[n + p] ** 2 * (sum(np.exp(c[n + p] * np.log(s) / 2.0) for s in sq) - 3.0)
               for p in range(n))


def softened_stress(law, spec: MullinsSpec, X, c, P0, l1, l2, l3):
    """η P0 along the history (rows of X the parameter points; columns the record's points)."""
    from scipy.special import erf

    psi = energy(law, c, l1[None, :], l2[None, :], l3[None, :]) + 0.0 * P0
    order = np.maximum.accumulate(np.real(psi[0]))  # the real history is the same in every row
    idx = np.maximum.accumulate(np.where(np.real(psi[0]) >= order, np.arange(psi.shape[1]), 0))
    W = psi[:, idx]
    r, m, beta = spec.split(X)
    z = (W - psi) / (m + beta * W)
    z = np.where(np.real(z) > 0, z, 0.0 * z)
    return (1.0 - erf(z) / r) * P0
