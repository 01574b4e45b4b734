"""Kind "tension–torsion": torque and axial force against the twist of a solid incompressible
cylinder of radius a held at an axial stretch λ (Rivlin 1949; Ogden, Non-linear Elastic
Deformations, §5.3).

The state, in the convention of vlab's scene (`[test] stretch` and `twist`, vlab.loading.torsion:
the end rotation is ψ L, so ψ is the twist per unit *reference* length, rad/mm):

    r = R/√λ,   θ = Θ + ψ Z,   z = λ Z          (twist per deformed length τ = ψ/λ)

so that at deformed radius r, with k = ψ r, in (e_r, e_θ, e_z)

    B = diag(1/λ, ·, ·) ⊕ [[1/λ + k², k λ], [k λ, λ²]]        (det B = 1)

whose θ–z block has eigenvalues μ± = (b_θθ + b_zz ± D)/2, D = √((b_θθ − b_zz)² + 4 b_θz²), the
principal stretches λ± = √μ± (λ+ λ− = √λ) and λ_r = λ^(−1/2). With w_i the law's principal
Kirchhoff stresses and the angle θ of the μ+ axis from e_θ (cos 2θ = (b_θθ − b_zz)/D,
sin 2θ = 2 b_θz / D):

    σ_θz = (w+ − w−) b_θz / D,   σ_θθ − σ_rr = w+ cos²θ + w− sin²θ − w_r,
    σ_zz − σ_rr = w+ sin²θ + w− cos²θ − w_r                                        (MPa)

and radial equilibrium with σ_rr(a/√λ) = 0 (∫ σ_rr r dr = −½ ∫ (σ_θθ − σ_rr) r dr by parts) gives,
over the deformed section 0 ≤ r ≤ a' = a/√λ,

    torque       M = 2π ∫_0^a' σ_θz r² dr                                          (N·mm)
    axial force  N = 2π ∫_0^a' [(σ_zz − σ_rr) − ½ (σ_θθ − σ_rr)] r dr              (N, tension > 0)

summed by Gauss–Legendre (``NODES`` points, analytic in the card and in λ: complex step). For
Mooney–Rivlin they are M = π ψ a⁴ (C10/λ + C01/λ²) and
N = 2π a² (λ − λ⁻²)(C10 + C01/λ) − (π/2) ψ² a⁴ (C10 + 2 C01/λ)/λ²; at λ = 1 the kind is "torsion".

Columns: ``twist`` ψ (rad/mm, strictly monotonic), ``torque`` (``units``: N*mm or N*m), optional
``axial_force`` (N); ``[data.geometry] radius`` a (mm, undeformed) and ``stretch`` λ (held).
"""

from __future__ import annotations

import numpy as np

from vlab.identify.kinds import torsion
from vlab.identify.kinds.base import FitKind, gauss

__all__ = ["KIND", "STRETCH_RANGE", "cylinder_loads", "principal_stretches", "section_states", "stretched_shear"]

NODES = 32
STRETCH_RANGE = (0.2, 10.0)  # the scene's test.stretch range


def _block(k, lam):
    """(b_θθ, b_zz, b_θz) of B and D = √((b_θθ − b_zz)² + 4 b_θz²)."""
    btt, bzz, btz = 1.0 / lam + k * k, lam * lam, k * lam
    return btt, bzz, btz, np.sqrt((btt - bzz) ** 2 + 4.0 * btz * btz)


def principal_stretches(k, lam):
    """(λ+, λ_r, λ−) at shear k = ψ r and axial stretch λ: λ± = √((b_θθ + b_zz ± D)/2), λ_r = λ^(−1/2)."""
    btt, bzz, _, root = _block(k, lam)
    half = 0.5 * (btt + bzz)
    return np.sqrt(half + 0.5 * root), lam**-0.5 + 0.0 * k, np.sqrt(half - 0.5 * root)


def stretched_shear(model, c, k, lam):
    """(σ_θz, σ_θθ − σ_rr, σ_zz − σ_rr), MPa, at shear k = ψ r and axial stretch λ (broadcast)."""
    btt, bzz, btz, root = _block(k, lam)
    wp, wr, wm = model.law.w(c, *principal_stretches(k, lam))
    root = np.where(np.abs(root) < 1e-300, 1.0, root)  # B = 1 (ψ r = 0, λ = 1): w+ = w− = w_r, all 0
    cos2 = 0.5 * (1.0 + (btt - bzz) / root)
    sin2 = 1.0 - cos2
    return (wp - wm) * btz / root, wp * cos2 + wm * sin2 - wr, wp * sin2 + wm * cos2 - wr


def cylinder_loads(model, X, twist, radius: float, stretch):
    """(M, N): (m, n) each, N·mm and N, at twists ψ (n,) rad/mm and axial stretches λ (a scalar,
    (n,) or (m, n): one per twist, or per card and twist) of internal coordinates X (m, n_x)."""
    c, _ = model.split(np.asarray(X)[:, None, :])
    c = [v[..., None] for v in c]                       # (m, 1, 1)
    s, w = gauss(NODES)
    psi = np.asarray(twist, float)[None, :, None]
    lam = np.asarray(stretch)
    lam = (lam if lam.ndim == 2 else np.broadcast_to(lam, psi.shape[1:2])[None, :])[..., None]  # (1|m, n, 1)
    a = radius / np.sqrt(lam)                          # the deformed radius a'
    sig_tz, n1, n2 = stretched_shear(model, c, psi * a * s, lam)
    M = 2.0 * np.pi * a[..., 0] ** 3 * (sig_tz @ (w * s * s))
    N = 2.0 * np.pi * a[..., 0] ** 2 * ((n2 - 0.5 * n1) @ (w * s))
    m = np.asarray(X).shape[0]
    return np.broadcast_to(M, (m, psi.shape[1])), np.broadcast_to(N, (m, psi.shape[1]))


def predict(model, X, d):
    """Torque (and axial force) of data set d: (m, n) or (m, 2n)."""
    g = d.extra["geometry"]
    M, N = cylinder_loads(model, X, d.a, g["radius"], g["stretch"])
    return np.concatenate([M, N], axis=-1) if "axial_force" in d.extra["outputs"] else M


def surface_I1(psi, radius: float, lam):
    """I1 = 2/λ + λ² + (ψ a)²/λ at the surface r = a/√λ (tr B there)."""
    return 2.0 / lam + lam * lam + (np.asarray(psi) * radius) ** 2 / lam


SAMPLES = np.linspace(0.0, 1.0, 9)[1:]  # r / a' of the material points judged for stability


def section_states(psi, radius: float, lam):
    """Principal stretches (3, n·8) along the deformed radius at twists ψ (n,), stretches λ."""
    lam = np.broadcast_to(np.asarray(lam, float), np.shape(psi))[:, None]
    k = np.asarray(psi, float)[:, None] * radius / np.sqrt(lam) * SAMPLES
    return np.array([v.ravel() for v in principal_stretches(k, lam)])


def states(d):
    g = d.extra["geometry"]
    return section_states(d.a, g["radius"], g["stretch"])


def max_I1(d) -> float:
    g = d.extra["geometry"]
    return float(np.max(surface_I1(d.a, g["radius"], g["stretch"])))


KIND = FitKind(
    name="tension-torsion", columns=(("twist", "torque"), ("axial_force",)), control="twist",
    geometry={"radius": "the cylinder's undeformed radius a", "stretch": "the axial stretch λ held during the twist"},
    units={"N*mm": 1.0, "N*m": 1e3}, default_unit="N*mm", measures=(), compressible=False, build=torsion.build,
    predict=predict, max_I1=max_I1,
    labels=("twist ψ (rad/mm, per undeformed length)", {"torque": "torque (N·mm)", "axial_force": "axial force (N)"}),
    geometry_limits={"stretch": ("a ratio: deformed / undeformed length", *STRETCH_RANGE)}, states=states)
