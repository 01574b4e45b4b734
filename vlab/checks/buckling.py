"""Critical states: the first loss of positive definiteness of K_ff, its mode, and whether it is
buckling.

At a bifurcation the lowest eigenvalue of K_ff crosses zero; its eigenvector φ (free DOFs, unit
norm; zero on the prescribed DOFs) is the shape the specimen takes when it leaves the fundamental
path. Two kinds are told apart by the shape of φ along the loading axis x:

* buckling (a structural, Euler-type mode): whole cross-sections move sideways, φ ≈ w(x) e_lateral.
  The slice means φ̄_s = mean of the lateral components of φ over the nodes of cross-section s
  (nodes binned by x) then carry nearly all of the mode,
      lateral_fraction = Σ_s n_s |φ̄_s|² / Σ_nodes |φ_node|²  → 1;
* a material instability (loss of ellipticity, e.g. St. Venant–Kirchhoff near stretch 0.59 in
  compression) or a local wrinkle: the mode varies across each section and its slice means
  nearly cancel, lateral_fraction → 0.

Sideways sections alone do not make buckling: a softened material can also let a stubby block
sway. So the material's strong ellipticity is checked at the critical state
(:mod:`vlab.checks.ellipticity`): the instability is
* buckling — the material is strongly elliptic everywhere, lateral_fraction ≥ BUCKLING_FRACTION
  and a grip axis is in compression (a structural instability; for a stubby block of a softening
  material, tangent-modulus buckling). In tension nothing pushes a section sideways: a sideways
  mode there (a strip of a perfectly plastic material that has lost its tangent stiffness) is a
  "bifurcation in tension", and no imperfection can follow it;
* loss of ellipticity — the material tangent lost strong ellipticity somewhere (a material
  instability: its discrete mode is set by the mesh);
* a structural bifurcation with a local mode — otherwise (wrinkling, barrelling, …), unless the
  elements are displacement-only and near-incompressible on a non-uniform field
  (``locking_nu``, vlab.checks.locking): a locked mesh's spurious stresses can make K_ff indefinite
  where the solid is stable, so such a local mode is ``suspect`` (unconfirmed) until a
  locking-free formulation shows it too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

BUCKLING_FRACTION = 0.5
MAX_SLICES = 200


@dataclass(frozen=True)
class CriticalState:
    """The first loss of stability, bracketed between the last stable and first unstable state.

    Stretches are grip stretches (axis 0 first); eigenvalues in N/mm; ``mode`` is the unit
    eigenvector of the lowest eigenvalue at ``stretch_unstable`` as a full DOF vector (zero on
    the prescribed DOFs), or None when no eigenpair was computed.
    """

    stretch_stable: list[float]
    stretch_unstable: list[float]
    eigenvalue_stable: float | None
    eigenvalue_unstable: float | None
    force_stable: list[float]
    negative_eigenvalues: int
    lateral_fraction: float | None
    mode: np.ndarray | None
    non_elliptic_fraction: float | None = None  # share of quadrature points; None: not checked
    locking_nu: float | None = None  # ν of locking-prone displacement-only elements; None: not prone

    @property
    def compressed(self) -> bool:
        """Some grip axis is in compression (stretch < 1) at the unstable state: buckling needs it."""
        return min(self.stretch_unstable) < 1.0

    @property
    def sideways(self) -> bool:
        return self.lateral_fraction is not None and self.lateral_fraction >= BUCKLING_FRACTION

    @property
    def is_buckling(self) -> bool:
        return not self.non_elliptic_fraction and self.sideways and self.compressed

    @property
    def suspect(self) -> bool:
        """A local mode of locking-prone displacement-only elements in an elliptic material: not
        evidence of a physical instability (module docstring)."""
        return self.locking_nu is not None and not self.non_elliptic_fraction and not self.is_buckling \
            and not self.sideways

    @property
    def kind(self) -> str:
        if self.suspect:
            return "unconfirmed (local mode of locking displacement-only elements)"
        if self.is_buckling:
            return "buckling"
        if self.non_elliptic_fraction:
            return "loss of ellipticity (material instability)"
        if self.mode is None:
            return "loss of stability (negative eigenvalues counted; the eigensolver found no mode)"
        if self.sideways:  # in tension: whole sections sway, but nothing compresses them
            return "bifurcation in tension (sideways mode, not buckling)"
        return "structural bifurcation (local mode)"

    def strain_bracket(self, axis: int = 0) -> tuple[float, float]:
        """|grip strain| of the last stable and first unstable state."""
        return abs(self.stretch_stable[axis] - 1.0), abs(self.stretch_unstable[axis] - 1.0)

    def as_dict(self) -> dict:
        lo, hi = self.strain_bracket()
        return {"kind": self.kind, "stretch_stable": self.stretch_stable,
                "stretch_unstable": self.stretch_unstable, "strain_bracket": [lo, hi],
                "critical_strain": 0.5 * (lo + hi), "eigenvalue_stable": self.eigenvalue_stable,
                "eigenvalue_unstable": self.eigenvalue_unstable, "force_stable": self.force_stable,
                "negative_eigenvalues": self.negative_eigenvalues,
                "lateral_fraction": self.lateral_fraction,
                "non_elliptic_fraction": self.non_elliptic_fraction, "locking_nu": self.locking_nu,
                "units": {"eigenvalue": "N/mm", "force": "N", "strain": "1 (grip)"}}


def _slices(x: np.ndarray) -> np.ndarray:
    """Slice index of each node along the loading axis: exact cross-sections when the mesh has
    few distinct x positions (structured meshes), else MAX_SLICES equal bins."""
    span = float(np.ptp(x)) or 1.0
    keys = np.round((x - x.min()) / span, 9)
    unique, index = np.unique(keys, return_inverse=True)
    if len(unique) <= min(MAX_SLICES, max(2, len(x) // 4)):
        return index
    return np.minimum((keys * MAX_SLICES).astype(np.int64), MAX_SLICES - 1)


def slice_mean_lateral(X: np.ndarray, u: np.ndarray, axis: int = 0) -> np.ndarray:
    """(n_slices, dim - 1) mean lateral displacement of each cross-section normal to ``axis`` (mm)."""
    dim = X.shape[1]  # 3, or 2 for a sheet (one lateral direction)
    lateral = [c for c in range(dim) if c != axis]
    slices = _slices(X[:, axis])
    U = u.reshape(-1, dim)[:, lateral]
    counts = np.bincount(slices).astype(float)
    sums = np.stack([np.bincount(slices, weights=U[:, j], minlength=len(counts))
                     for j in range(len(lateral))], axis=1)
    return sums / np.maximum(counts, 1.0)[:, None]


def lateral_fraction(X: np.ndarray, mode: np.ndarray, axis: int = 0) -> float:
    """Share of the mode's squared norm carried by whole cross-sections moving sideways (0..1)."""
    slices = _slices(X[:, axis])
    counts = np.bincount(slices).astype(float)
    means = slice_mean_lateral(X, mode, axis)
    total = float(np.sum(mode**2))
    if total == 0.0:
        return 0.0
    return float(np.sum(counts[:, None] * means**2) / total)


def lateral_deflection(X: np.ndarray, u: np.ndarray, axis: int = 0) -> float:
    """Largest sideways displacement of a cross-section (mm): the centre-line deflection of a
    buckled specimen. Poisson's expansion is symmetric about the centre line and averages out."""
    return float(np.max(np.linalg.norm(slice_mean_lateral(X, u, axis), axis=1), initial=0.0))
