"""The instruments and measures of the test kinds, provided by the measure layer for what each kind
declares (vlab/loading/kinds: a kind is in the layer below and names what it needs, never imports
it):

- ``gauge``: the strain instruments, ``"extensometers"`` (one extensometer along each loaded axis,
  the width and, in 3D, the thickness extensometer) or ``"shear-gauge"`` (gauge marks across the
  gap, γ_g = (u_x(b) − u_x(a)) / (Y_b − Y_a), with width and thickness extensometers);
- ``readers``: other readings by name, ``"normal-force"`` (the y reaction of the moving grip, N)
  , ``"centre-cauchy"`` (σ̄_xx, σ̄_yy, σ̄_zz, σ̄_xy over the centre region, MPa) and
  ``"volume-pressure"`` (the volume ratio J̄ and the pressure p̄ over the body, measure/confined.py),
  ``"torque"`` (the torque and axial stretch of a turning grip, measure/torsion.py),
  ``"cavity-pressure"`` (the pressure in a volume-controlled cavity, measure/inflation.py);
- ``field_probe``: results.json → homogeneity, ``"gauge-section"`` (a dumb-bell's gauge section),
  ``"pure-shear"`` (the distance from pure shear) or ``"simple-shear"``;
- ``fit``: the constants it measures over the modulus window, ``"uniaxial"`` (E, ν), ``"biaxial"``,
  ``"planar"`` (E/(1 − ν²), ν, E), ``"shear"`` (G, N₁), ``"confined"`` (M, K) or ``"torsion"``
  (the torsional stiffness and G) or ``"inflation"`` (the pressure's limit point); ``crosshead_fit``: ``"crosshead"`` (the
  modulus from grip strain) or None.

A new kind that measures as an existing one declares its names; one that needs a new instrument
or fit adds its function to the table here under a new name.
"""

from __future__ import annotations

from vlab.measure.confined import confined_constants, volume_pressure_readers
from vlab.measure.elastic_constants import biaxial_constants, crosshead_modulus, uniaxial_constants
from vlab.measure.homogeneity import HomogeneityProbe
from vlab.measure.inflation import cavity_pressure_readers, inflation_constants
from vlab.measure.instruments import LoadCell, ShearGauge, extensometers
from vlab.measure.planar import PureShearProbe, planar_constants
from vlab.measure.shear import ShearFieldProbe, centre_cauchy_readers, shear_constants
from vlab.measure.torsion import torque_readers, torsion_constants

__all__ = ["GAUGES", "READERS", "PROBES", "FITS", "CROSSHEAD_FITS", "gauges", "extra_readers", "probe",
           "measure", "crosshead"]


def _extensometers(kind, space, specimen):
    marks = [specimen.extensometers[a] for a in kind.axes] + [specimen.transverse[0]]
    if space.dim == 3:
        marks.append(specimen.thickness)
    found = extensometers(space, marks, specimen.symmetry)
    thickness = found.pop() if space.dim == 3 else None
    width = found.pop()
    return dict(zip(kind.axes, found)), width, thickness


def _shear_gauge(kind, space, specimen):
    width, thickness = extensometers(space, [specimen.transverse[0], specimen.thickness])
    return {0: ShearGauge(space, specimen.extensometers[1])}, width, thickness  # marks across the gap (y)


def _normal_force(space, specimen, loading, material) -> dict:
    cell = LoadCell(loading.moving_dofs[1])
    return {"normal_force": lambda level: cell.read(level.evaluation.f_int)}


GAUGES = {"extensometers": _extensometers, "shear-gauge": _shear_gauge}
READERS = {"normal-force": _normal_force, "volume-pressure": volume_pressure_readers, "torque": torque_readers,
           "cavity-pressure": cavity_pressure_readers,
           "centre-cauchy": lambda space, specimen, loading, material: centre_cauchy_readers(space, specimen, material)}
PROBES = {"gauge-section": HomogeneityProbe.build, "pure-shear": PureShearProbe.build,
          "simple-shear": ShearFieldProbe.build}
FITS = {"uniaxial": uniaxial_constants, "biaxial": biaxial_constants, "planar": planar_constants,
        "shear": shear_constants, "confined": confined_constants, "torsion": torsion_constants,
        "inflation": inflation_constants}
CROSSHEAD_FITS = {"crosshead": crosshead_modulus}


def gauges(kind, space, specimen) -> tuple[dict, object, object]:
    """(axis -> strain instrument, width extensometer, thickness extensometer or None on a sheet)."""
    return GAUGES[kind.gauge](kind, space, specimen)


def extra_readers(kind, space, specimen, loading, material) -> dict:
    """Readings beyond load cells and strain gauges: name -> reader(level) -> float."""
    readers: dict = {}
    for name in kind.readers:
        readers |= READERS[name](space, specimen, loading, material)
    return readers


def probe(kind, space, specimen, material):
    """The field probe read at every level (results.json → homogeneity)."""
    return PROBES[kind.field_probe](space, specimen, material)


def measure(kind, curve, window, method):
    """The kind's constants fitted over the modulus window (an ElasticConstants)."""
    return FITS[kind.fit](curve, window, method)


def crosshead(kind, curve, window, method) -> dict | None:
    """The modulus from grip (crosshead) strain, where the kind has one (uniaxial)."""
    return None if kind.crosshead_fit is None else CROSSHEAD_FITS[kind.crosshead_fit](curve, window, method)
