"""The optional capabilities of a material law, declared once with their defaults.

Every law (vlab.materials.base.Material, the rubber frame vlab.materials.isochoric, the laws with
memory of vlab.materials.history, the 2D reductions of vlab.materials.plane) inherits
:class:`LawCapabilities`, so the solver, the checks and post-processing read a capability as an
attribute (``law.tangent_terms is not None``) instead of probing for it with hasattr/getattr.
A law that has the capability defines the member; one that has not keeps the default:

- ``is_linear`` (bool, False): a constant tangent (small-strain elasticity), one linear solve;
  the homogeneous oracles and admissibility checks do not apply to it as to a finite-strain law.
- ``tangent_terms(F) -> TangentTerms`` (None): A = ∂P/∂F as a short sum of outer products
  (vlab.materials.structure), which the assembly pulls back term by term and the compiled kernel
  (vlab.fe.compiled) takes in its isotropic form, never forming the (3,3,3,3,*batch) tangent.
- ``tangent_forms(F) -> list[IsotropicTangent]`` (None): A as a sum of the compiled kernel's
  isotropic forms (the rubber models).
- ``history_fields(state, F=None) -> {name: (*batch) array}`` (None): the named internal
  variables of a law with memory (plastic strain, Mullins damage, viscous strains), for the
  stability monitor, the VTU cells and the report.
- ``locking_note`` (str, None): where a law with a limiting chain extensibility locks (Gent),
  for the messages of a test past it;
- ``plane`` (str, ""): "stress" or "strain" for a 2D reduction of a 3D law, which is then its
  ``base`` (vlab.materials.plane); "" for a 3D law.
"""

from __future__ import annotations

from typing import ClassVar

__all__ = ["LawCapabilities"]


class LawCapabilities:
    """The optional members of a law at their defaults (module docstring)."""

    is_linear: ClassVar[bool] = False
    tangent_terms = None
    tangent_forms = None
    history_fields = None
    locking_note: ClassVar[str | None] = None
    plane: ClassVar[str] = ""
