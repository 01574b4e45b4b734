"""Small scene builders shared by the stability tests."""

from __future__ import annotations

from vlab.scene import parse_scene


def block_scene(model: str = "neo-hookean", stretch=1.2, *, grips: str = "roller", nu: float = 0.3,
                cell: str = "hex", size: float = 5.0, steps: int = 5, extent=(10.0, 10.0, 10.0),
                **solver):
    kind = "biaxial" if isinstance(stretch, (list, tuple)) else "uniaxial"
    data = {"name": "t", "specimen": {"shape": "block", "size": list(extent)},
            "mesh": {"size": size, "cell": cell},
            "material": {"model": model, "E": 10.0, "nu": nu},
            "test": {"kind": kind, "grips": grips, "stretch": list(stretch) if kind == "biaxial" else stretch,
                     "steps": steps}}
    if solver:
        data["solver"] = solver
    return parse_scene(data)


def block_toml(name: str, *, material: str = 'model = "linear"\nE = 10.0\nnu = 0.3', mesh: str = "size = 10.0",
               stretch: float = 1.01, steps: int = 1) -> str:
    """A 10 mm cube pulled uniaxially on roller grips, as TOML text: by default the smallest scene
    the CLI tests run (one linear hexahedron to stretch 1.01, well under a second). ``material``
    and ``mesh`` are the tables' lines, as tests replace them."""
    return f"""
name = "{name}"
[specimen]
shape = "block"
size = [10.0, 10.0, 10.0]
[mesh]
{mesh}
[material]
{material}
[test]
kind = "uniaxial"
grips = "roller"
stretch = {stretch:g}
steps = {steps}
"""
