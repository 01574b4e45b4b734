"""The field fit's levelling (vlab.identify.field_model) against a closed form: a homogeneous FE
field u = (F − I) X is affine, so its mean over a subset's pixels is its value at the centre and
the strain window's plane fit is exact; the levelled strain must be the Green–Lagrange strain
E = ½ (Fᵀ F − I) of F in image axes (x right, y down against e₂: E_xx = E₁₁, E_yy = E₂₂,
E_xy = −E₁₂) to round-off at every subset, beside holes in the mask too. (docs/dic.md, "The
interpolation bias of a small strain": the levelling is not where the DIC's E_yy bias comes from.)"""

from __future__ import annotations

import numpy as np

from vlab.dic.correlate import Settings, grid
from vlab.dic.face import face_of
from vlab.geometry.block import block_mesh
from vlab.identify.field_model import face_points, levelled, subset_interpolation


def test_levelled_homogeneous_field_is_its_green_lagrange_strain_in_image_axes():
    face = face_of(block_mesh((20.0, 20.0, 2.0), 2.0, "hex"))
    pitch, settings = 0.1, Settings(subset=21, step=6)
    camera = {"pixels": (160, 160), "mm_per_px": pitch, "centre": (10.3, 9.8)}
    xs, ys = grid((160, 160), settings)
    X1, X2 = face_points(camera, xs, ys)
    P, found = subset_interpolation(face, X1, X2, settings.subset, pitch)
    mask = found.reshape(X1.shape)
    mask[3, 4] = mask[7, 2] = False  # failed subsets: the window fits the rest
    F = np.array([[1.01, 0.004], [-0.002, 0.997]])
    u = face.X @ (F - np.eye(2)).T
    E, _ = levelled(P, u, np.zeros((0,) + u.shape), mask, pitch, settings.step, settings.strain_window)
    G = 0.5 * (F.T @ F - np.eye(2))
    assert mask.sum() == mask.size - 2
    for got, want in zip(E, (G[0, 0], G[1, 1], -G[0, 1])):
        assert np.abs(got[mask] - want).max() < 1e-14
