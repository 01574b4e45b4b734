"""The VTU writer's own pieces against the libraries they stand in for: the order-1 hexahedron's
VTK node order against scikit-fem's meshio mapping, and the attribute quoting against what an XML
parser reads back."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest
import skfem
import skfem.io.meshio as skfem_meshio

from vlab.post import vtk_cells
from vlab.post.vtu import quoteattr

def test_hex_corners_are_skfems_vtk_order():
    assert np.array_equal(vtk_cells.HEX_CORNERS, skfem_meshio.HEX_MAPPING[:8])

def test_hex_corners_give_positive_vtk_volumes():
    # a unit cube in VTK order: the bottom face counter-clockwise seen from +z, then the top
    mesh = skfem.MeshHex()
    x = mesh.p[:, mesh.t[vtk_cells.HEX_CORNERS, 0]].T
    assert np.allclose(x, vtk_cells._VTK_HEX_CORNERS)

@pytest.mark.parametrize("name", ["displacement", 'a "quoted" name', "it's", "<&>", "σ_vm / MPa", ""])
def test_quoteattr_round_trips_through_an_xml_parser(name):
    element = ET.fromstring(f"<DataArray Name={quoteattr(name)}/>")
    assert element.get("Name") == name
