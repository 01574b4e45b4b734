"""Why an unloaded tangent that the grips restrain still reads as singular: ill-conditioning.

Before solving, the set-up is checked on the geometry (vlab.loading.restraint): do the prescribed
DOFs remove every rigid-body mode? If they do and the unloaded K_ff still has a pivot (or
eigenvalue) below ``ZERO_TOL`` × its largest diagonal entry, nothing is free: some mode of the
specimen is just that much softer than its stiffest one, and at that ratio double precision
cannot tell it from a free mode (the stability checks would count it as a zero eigenvalue at
every state). A 0.001 mm thick ISO 527-2 1BA dogbone, clamped, meshed 2.5 mm: lowest eigenvalue
6.8e-13 × max K_ii, its mode across the thickness (measured). The diagnosis names what was
measured: that ratio, the direction the softest mode moves in, and the specimen's extents.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from vlab.fe.inertia import ZERO_TOL, EigenpairNotFound, lowest_eigenpair
from vlab.fe.stepping import UNLOADED_SINGULAR, SolveHistory


def conditioning_diagnosis(body, partition, X: np.ndarray, detail: str) -> str:
    """The failure reason for a restrained set-up whose unloaded K_ff reads as singular."""
    Kff = partition.blocks(body.stiffness(body.evaluate(np.zeros(body.space.n_dofs))))[0]
    largest = float(np.max(np.abs(Kff.diagonal()), initial=0.0)) or 1.0
    extents = np.ptp(X, axis=0)
    thin = int(np.argmin(extents))
    span = ", ".join(f"{e:.3g}" for e in extents)
    text = (f"the unloaded tangent K_ff is numerically singular ({detail}), although the grips restrain "
            f"every rigid-body mode (checked on the geometry before solving): ill-conditioning by scale, "
            f"not a free specimen")
    try:
        lam, mode = lowest_eigenpair(Kff, 0, None)
    except EigenpairNotFound:
        return f"{text}; the specimen's extents are {span} mm"
    full = np.zeros(body.space.n_dofs)
    full[partition.free] = mode
    share = np.sum(full.reshape(-1, X.shape[1]) ** 2, axis=0)
    axis = int(np.argmax(share))
    return (f"{text} — its lowest eigenvalue is {lam / largest:.2g} × its largest diagonal entry, below the "
            f"{ZERO_TOL:g} at which a mode counts as free; that mode moves {100 * share[axis] / share.sum():.0f} % "
            f"along {'xyz'[axis]}; the specimen's extents are {span} mm (largest / smallest "
            f"{extents.max() / max(extents[thin], 1e-300):.2g})"
            + (f", so a specimen this thin along {'xyz'[thin]} is a sheet: specimen.shape = \"sheet\" "
               f"(plane stress), or a thicker specimen" if axis == thin else ""))


def restrained_but_singular(history: SolveHistory, body, partition, space) -> SolveHistory:
    """``history`` with its failure reworded when the unloaded tangent read as singular although
    the grips passed the geometric restraint check (vlab.run refuses before solving otherwise)."""
    failure = history.failure
    if failure is None or not failure.reason.startswith(UNLOADED_SINGULAR) or failure.level != 0:
        return history
    detail = failure.reason[len(UNLOADED_SINGULAR):].strip()
    detail = detail[1:-1] if detail.startswith("(") and detail.endswith(")") else detail
    reason = conditioning_diagnosis(body, partition, space.node_coordinates, detail)
    return dataclasses.replace(history, failure=dataclasses.replace(failure, reason=reason))
