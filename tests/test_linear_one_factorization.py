"""The linear model needs one factorization for the whole test: the tangent predictor is exact."""

from vlab.fe import linsolve, newton
from vlab.run import run_scene
from vlab.scene import parse_scene


def test_linear_model_factorizes_once(monkeypatch):
    calls = []
    real = linsolve.factorize

    def counting(K):
        calls.append(K.shape)
        return real(K)

    from vlab.fe import tangents

    monkeypatch.setattr(newton, "factorize", counting)
    monkeypatch.setattr(tangents, "factorize", counting)  # the tangent cache's factorizations
    scene = parse_scene({
        "name": "lin", "specimen": {"shape": "block", "size": [2.0, 2.0, 2.0]},
        "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": "linear", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "stretch": 1.2, "steps": 5},
    })
    result = run_scene(scene)
    assert result.converged
    assert len(result.history.levels) > 5  # the modulus-window levels as well
    assert sum(level.iterations for level in result.history.levels) == 0
    assert result.history.factorizations == 1
    assert len(calls) == 1
