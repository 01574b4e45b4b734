"""Randomly perturbed copies of structured specimen meshes, for robustness checks.

Nodes move by up to ``fraction`` of the local cell size along every axis on which they do not lie
on a boundary plane of the bounding box, so faces stay planar and grips still see whole faces.
The result is a valid mesh with distorted elements (checked by the caller, e.g. the mesh check).
"""

from __future__ import annotations

import dataclasses

import numpy as np


def perturbed(spec, fraction: float, seed: int):
    """A copy of the specimen ``spec`` with its interior node coordinates jittered (seeded)."""
    p = spec.mesh.p.copy()
    rng = np.random.default_rng(seed)
    lo, hi = p.min(axis=1, keepdims=True), p.max(axis=1, keepdims=True)
    h = np.array([np.min(np.diff(np.unique(np.round(row, 9)))) for row in p])[:, None]
    interior = (p > lo + 1e-9) & (p < hi - 1e-9)
    p += interior * rng.uniform(-fraction, fraction, p.shape) * h
    return dataclasses.replace(spec, mesh=type(spec.mesh)(p, spec.mesh.t))
