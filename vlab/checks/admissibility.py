"""Requests that have no admissible state are refused before any solve.

Some models have no equilibrium at all beyond a certain stretch. St. Venant–Kirchhoff in uniaxial
tension with free lateral faces needs a lateral stretch t with
    t² = 1 − ν (λ² − 1)   (P₂₂ = 0),
which is real only for λ < √(1 + 1/ν); beyond it no state exists, and a finite-element solver would
either fail or (worse) return the numbers of a collapsed mesh. The test kind's analytic
homogeneous state (vlab.loading.kinds: ``state``, from :mod:`vlab.materials.homogeneous`) decides
this for any model and kind (free thickness, P₃₃ = 0, in biaxial and planar tests as well). The
check runs on the target; the message it returns always contains "no admissible state beyond
stretch".
"""

from __future__ import annotations

from vlab.materials.homogeneous import InadmissibleState


def inadmissible_request(material, kind, targets: tuple[float, ...], shape: str | None = None) -> str | None:
    """Why no homogeneous equilibrium of test ``kind`` on ``shape`` exists at ``targets`` (None if
    one does, or if the kind has no state there: ``TestKind.has_state``)."""
    if material is None or material.is_linear or not kind.has_state(shape):  # spring network: no oracle;
        return None  # torsion, a membrane's volume ratio: no homogeneous state to decide it
    try:
        kind.state(material, targets)
    except InadmissibleState as exc:
        return f"request refused before solving: {exc}"
    return None
