"""FE against DIC "levelled": the FE field passed through the DIC's own filters before the
difference is taken, so the difference map shows measurement error, not filtering.

At every subset centre (x_px, y_px) of the DIC grid the reference face point (x₁, x₂) mm
(vlab.dic.instrument.View.face_mm) is located on the face; the FE displacement there is
u(X) = Σ_a N_a(ξ(X)) u_a over the face cell's vertices (the interpolation the camera renders,
vlab.dic.inverse_map; for an order-2 space, its vertices), turned into image pixels,

    u_px = s₁ u[a₁] / p,   v_px = −s₂ u[a₂] / p      (image y runs down, against e₂),

masked where the DIC subset failed (the strain window then sees the same points), and the same
strain window (vlab.dic.strain.strain_window: plane fit over w × w grid points, Green–Lagrange)
gives the levelled FE strain. The difference DIC − levelled FE is reported as its rms and largest
magnitude over the points where both are finite.
"""

from __future__ import annotations

import numpy as np

from vlab.dic import icgn
from vlab.dic.inverse_map import reference_points
from vlab.dic.strain import strain_window

COMPONENTS = ("exx", "eyy", "exy")


class FeProbe:
    """The FE displacement at the subset centres of a DIC grid (``field``: any Field of the run)."""

    def __init__(self, view, field):
        self.view = view
        self.x1, self.x2 = view.face_mm(field.x[0], field.y[:, 0])

    def displacement_px(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(U, V) px on the grid from the mesh vertices' displacement ``u`` (n_vertices, 3) mm;
        NaN off the face. The face's own interpolation is inverted the other way round
        (vlab.dic.inverse_map with the deformed nodes as "reference"): it returns φ(X) = X + u(X)
        at the grid points X, so u(X) is the camera's displacement field exactly."""
        face, p = self.view.face, self.view.camera.pitch
        moved = face.X + face.in_plane(u)
        PX, PY, on = reference_points(moved, face.X, face.cells, self.x1, self.x2)
        U = np.where(on, (PX - self.x1[None, :]) / p, np.nan)
        V = np.where(on, -(PY - self.x2[:, None]) / p, np.nan)
        return U, V

    def levelled(self, u: np.ndarray, field) -> dict[str, np.ndarray]:
        """The levelled FE field where the DIC ``field`` converged: u_px, v_px, exx, eyy, exy."""
        U, V = self.displacement_px(u)
        failed = field.status != icgn.OK
        U[failed], V[failed] = np.nan, np.nan
        s = self.view.settings
        exx, eyy, exy = strain_window(U, V, s.step, s.strain_window)
        return {"u_px": U, "v_px": V, "exx": exx, "eyy": eyy, "exy": exy}


def difference(field, fe: dict[str, np.ndarray], mask: np.ndarray | None = None) -> dict:
    """rms and max |DIC − levelled FE| per strain component (and of u, v in px) over the points
    both hold (and ``mask`` if given); None where no point does."""
    out = {}
    pairs = [(c, getattr(field, c), fe[c]) for c in COMPONENTS] + [("u_px", field.u, fe["u_px"]),
                                                                     ("v_px", field.v, fe["v_px"])]
    for name, dic, model in pairs:
        d = dic - model
        ok = np.isfinite(d) if mask is None else np.isfinite(d) & mask
        out[name] = ({"rms": float(np.sqrt(np.mean(d[ok] ** 2))), "max": float(np.abs(d[ok]).max()),
                      "points": int(ok.sum())} if ok.any() else {"rms": None, "max": None, "points": 0})
    return out
