"""Is the set-up restrained? Rigid-body modes the prescribed DOFs leave free.

A body is restrained iff no infinitesimal rigid motion u(X) = a + ω × (X − X̄) vanishes on every
prescribed DOF. With the six basis motions (three in 2D: two translations, the rotation about z)
as columns of R (n_dofs × 6, resp. × 3), the unrestrained motions
are the null space of R_p (the prescribed rows of R). Each of them is a zero-energy mode of K_ff:
the tangent is singular and any "solution" of the Newton system is garbage. Checked exactly here,
before any factorization, and named in terms of translations and rotations.
"""

from __future__ import annotations

import numpy as np

MODE_NAMES = ("translation along x", "translation along y", "translation along z",
              "rotation about x", "rotation about y", "rotation about z")
MODE_NAMES_2D = ("translation along x", "translation along y", "rotation about z")


def rigid_body_modes(X: np.ndarray) -> np.ndarray:
    """(3 n_nodes, 6) rigid motions at nodes X (n_nodes, 3): three translations, three rotations
    about the centroid (scaled by the body size so that all columns are commensurate); for 2D
    nodes X (n_nodes, 2) the (2 n_nodes, 3) in-plane ones."""
    Y = X - X.mean(axis=0)
    size = float(np.max(np.abs(Y), initial=0.0)) or 1.0
    if X.shape[1] == 2:
        R = np.zeros((len(X), 2, 3))
        R[:, 0, 0] = R[:, 1, 1] = 1.0
        R[:, 0, 2], R[:, 1, 2] = -Y[:, 1] / size, Y[:, 0] / size  # e_z × Y
        return R.reshape(-1, 3)
    R = np.zeros((len(X), 3, 6))
    for i in range(3):
        R[:, i, i] = 1.0
        e = np.zeros(3)
        e[i] = 1.0
        R[:, :, 3 + i] = np.cross(e, Y) / size
    return R.reshape(-1, 6)


def unrestrained_modes(X: np.ndarray, prescribed: np.ndarray, tol: float = 1e-8) -> list[str]:
    """Descriptions of the rigid motions the prescribed DOFs do not restrain ([] if restrained)."""
    names_all = MODE_NAMES_2D if X.shape[1] == 2 else MODE_NAMES
    R = rigid_body_modes(X)[np.asarray(prescribed, dtype=np.int64)]
    if len(R) == 0:
        return list(names_all)
    n_modes = len(names_all)
    # all right singular vectors; U only as wide as needed (a full U is n_prescribed² floats)
    _, s, vt = np.linalg.svd(R, full_matrices=len(R) < n_modes)
    s = np.concatenate([s, np.zeros(len(names_all) - len(s))])
    null = vt[s <= tol * max(s[0], 1e-300)]
    names = []
    for v in null:
        parts = [names_all[k] for k in np.flatnonzero(np.abs(v) > 0.1 * np.max(np.abs(v)))]
        names.append(" + ".join(parts))
    return names


def under_constrained_message(modes: list[str]) -> str:
    return ("under-constrained set-up: the grips leave rigid-body mode(s) free ("
            + "; ".join(modes) + "), so the stiffness is singular; add a grip or supports")
