"""The message of a mesh below mesh.min_quality names the specimen's mesh in plain words."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
import skfem

from vlab.pipeline.prepare import MeshQualityError, checked_quality


@pytest.mark.parametrize("shape,name", [("mesh", "the imported mesh's worst element"),
                                        ("dogbone", "the dogbone mesh's worst element")])
def test_a_poor_mesh_is_refused_with_its_worst_element_named_once(shape, name):
    specimen = SimpleNamespace(shape=shape, mesh=skfem.MeshTet())  # the cube in 5 or 6 tets: quality < 1
    scene = SimpleNamespace(mesh=SimpleNamespace(min_quality=0.999))
    with pytest.raises(MeshQualityError) as err:
        checked_quality(scene, specimen)
    assert str(err.value).startswith(f"mesh.min_quality: {name} (#") and "mesh mesh" not in str(err.value)
