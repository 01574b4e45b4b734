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


def one_element_block_toml(name: str, steps: int = 1) -> str:
    """The smallest scene the CLI tests run: one linear hexahedron pulled to stretch 1.01 on roller
    grips (a run takes well under a second), as TOML text named ``name``."""
    return f"""
name = "{name}"
[specimen]
shape = "block"
size = [10.0, 10.0, 10.0]
[mesh]
size = 10.0
[material]
model = "linear"
E = 10.0
nu = 0.3
[test]
kind = "uniaxial"
grips = "roller"
stretch = 1.01
steps = {steps}
"""
