"""Material cards for other solvers: ``vlab export``, ``vlab import-card`` and ``vlab fit --export``.

One file per target (vlab.export.abaqus, calculix, ansys, lsdyna, febio, felupe_script) with its
writer, reader and convention; the registry and its contract in vlab.export.registry; the card
and its source in vlab.export.card; the header and units in vlab.export.header; the commands in
vlab.export.command.
"""

import vlab as _vlab
from vlab.export.abaqus import ABAQUS
from vlab.export.ansys import ANSYS
from vlab.export.calculix import CALCULIX
from vlab.export.febio import FEBIO
from vlab.export.felupe_script import FELUPE
from vlab.export.lsdyna import LSDYNA
from vlab.export.registry import EXPORTERS, register

for _e in (ABAQUS, CALCULIX, ANSYS, LSDYNA, FEBIO, FELUPE):
    register(_e)

__all__ = ["EXPORTERS"]

_vlab._command_module(__name__)  # vlab.export(...) is the Python API's command (vlab/__init__.py)
