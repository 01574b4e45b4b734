"""Requests that have no admissible state are refused before any solve.

Some models have no equilibrium at all beyond a certain stretch. St. Venant–Kirchhoff in uniaxial
tension with free lateral faces needs a lateral stretch t with
    t² = 1 − ν (λ² − 1)   (P₂₂ = 0),
which is real only for λ < √(1 + 1/ν); beyond it no state exists, and a finite-element solver would
either fail or (worse) return the numbers of a collapsed mesh. The analytic homogeneous state of
:mod:`vlab.materials.homogeneous` decides this for any model and for biaxial tests as well (free
thickness, P₃₃ = 0). The check runs on the target stretch; the message it returns always contains
"no admissible state beyond stretch".
"""

from __future__ import annotations

from vlab.materials.homogeneous import InadmissibleState, homogeneous_state


def inadmissible_request(material, stretch: tuple[float, ...]) -> str | None:
    """Why no homogeneous equilibrium exists at the grip ``stretch`` (None if one does)."""
    if material is None or getattr(material, "is_linear", False):  # spring network: no oracle
        return None
    try:
        homogeneous_state(material, stretch)
    except InadmissibleState as exc:
        return f"request refused before solving: {exc}"
    return None
