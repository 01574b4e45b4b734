import itertools
import math

import pytest

from vlab.moduli import KEYS, Moduli, ModuliError, from_pair

E_VALUES = (1e-3, 10.0, 2.1e5)
NU_VALUES = (-0.9, -0.5, -0.2, 0.0, 0.3, 0.49, 0.4999)
PAIRS = list(itertools.combinations(KEYS, 2))


def reference(E, nu):
    return {
        "E": E,
        "nu": nu,
        "lambda": E * nu / ((1 + nu) * (1 - 2 * nu)),
        "mu": E / (2 * (1 + nu)),
        "K": E / (3 * (1 - 2 * nu)),
        "M": E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)),
    }


def assert_same(got: Moduli, ref: dict, E: float, label: str):
    for key, val in got.as_dict().items():
        scale = 1.0 if key == "nu" else E
        assert math.isclose(val, ref[key], rel_tol=1e-10, abs_tol=1e-13 * scale), (
            f"{label}: {key} = {val!r}, expected {ref[key]!r}")


def test_pairs_cover_all_fifteen():
    assert len(PAIRS) == 15


@pytest.mark.parametrize("E", E_VALUES)
@pytest.mark.parametrize("nu", NU_VALUES)
@pytest.mark.parametrize("pair", PAIRS, ids=lambda p: "-".join(p))
def test_round_trip(E, nu, pair):
    if pair == ("nu", "lambda") and nu == 0.0:
        pytest.skip("(lambda, nu) is undefined at nu = 0")
    ref = reference(E, nu)
    root = "minus" if (pair == ("E", "M") and nu < 0) else "plus"
    got = from_pair({k: ref[k] for k in pair}, root=root)
    assert_same(got, ref, E, f"{pair} E={E} nu={nu}")


def test_as_dict_keys_and_aliases():
    m = from_pair({"E": 10.0, "nu": 0.3})
    assert tuple(m.as_dict()) == KEYS
    assert from_pair({"E": 10.0, "G": m.mu}) == from_pair({"E": 10.0, "mu": m.mu})
    got = from_pair({"lmbda": m.lmbda, "G": m.mu})
    assert math.isclose(got.E, 10.0) and math.isclose(got.nu, 0.3)


def test_e_m_roots():
    ref = reference(10.0, -0.3)
    plus = from_pair({"E": 10.0, "M": ref["M"]}, root="plus")
    minus = from_pair({"E": 10.0, "M": ref["M"]}, root="minus")
    assert plus.nu >= 0 and math.isclose(minus.nu, -0.3)
    # M == E: both roots coincide at nu = 0
    assert from_pair({"E": 5.0, "M": 5.0}, root="minus").nu == 0.0
    assert from_pair({"E": 5.0, "M": 5.0}, root="plus").nu == 0.0


@pytest.mark.parametrize("values, fragments", [
    ({"E": 10.0, "nu": 0.5}, ["material.nu", "0.5", "-1 < nu < 0.5", "incompressible", "0.4999"]),
    ({"E": 10.0, "nu": 0.7}, ["material.nu", "0.7", "-1 < nu < 0.5"]),
    ({"E": 10.0, "nu": -1.0}, ["material.nu", "-1 < nu < 0.5"]),
    ({"E": -1.0, "nu": 0.3}, ["material.E must be > 0 (got -1)"]),
    ({"E": 0.0, "nu": 0.3}, ["material.E must be > 0"]),
    ({"mu": 0.0, "nu": 0.3}, ["material.mu must be > 0"]),
    ({"G": -2.0, "nu": 0.3}, ["material.mu must be > 0"]),
    ({"K": -2.0, "nu": 0.3}, ["material.K must be > 0"]),
    ({"M": 0.0, "E": 3.0}, ["material.M must be > 0"]),
    ({"E": float("nan"), "nu": 0.3}, ["material.E", "finite"]),
    ({"E": float("inf"), "nu": 0.3}, ["material.E", "finite"]),
    ({"lambda": float("-inf"), "mu": 1.0}, ["material.lambda", "finite"]),
    ({"E": "10", "nu": 0.3}, ["material.E", "number"]),
    ({"E": True, "nu": 0.3}, ["material.E", "number"]),
    ({"E": 10.0, "nu": 0.3, "mu": 3.0}, ["give exactly two of E, nu, lambda, mu, K, M; got E, nu, mu"]),
    ({"E": 10.0}, ["give exactly two", "got E"]),
    ({}, ["give exactly two"]),
    ({"E": 10.0, "poisson": 0.3}, ["material.poisson", "unknown"]),
    ({"mu": 1.0, "G": 1.0}, ["material.mu", "twice"]),
    ({"lambda": 1.0, "nu": 0.0}, ["lambda", "nu", "undefined at nu = 0"]),
])
def test_invalid_input(values, fragments):
    with pytest.raises(ModuliError) as exc:
        from_pair(values)
    for frag in fragments:
        assert frag in str(exc.value)


@pytest.mark.parametrize("values, fragments", [
    ({"E": 30.0, "mu": 10.0}, ["material.E = 30", "material.mu = 10", "nu = 0.5", "incompressible"]),
    ({"E": 40.0, "mu": 10.0}, ["material.E = 40", "material.mu = 10", "nu = 1"]),
    ({"E": 10.0, "K": 1.0}, ["material.E = 10", "material.K = 1", "nu"]),
    ({"E": 10.0, "M": 5.0}, ["material.E = 10", "material.M = 5", "no real nu"]),
    ({"E": 10.0, "M": 1.0}, ["material.E = 10", "material.M = 1", "nu"]),
    ({"nu": 0.3, "lambda": -1.0}, ["material.nu = 0.3", "material.lambda = -1", "mu"]),
    ({"lambda": -5.0, "mu": 2.0}, ["material.lambda = -5", "material.mu = 2"]),
    ({"lambda": -5.0, "mu": 5.0}, ["material.lambda = -5", "material.mu = 5"]),
    ({"lambda": 5.0, "K": 2.0}, ["material.lambda = 5", "material.K = 2", "mu"]),
    ({"lambda": 5.0, "M": 5.0}, ["material.lambda = 5", "material.M = 5", "mu = 0"]),
    ({"lambda": -5.0, "M": 5.0}, ["material.lambda = -5", "material.M = 5"]),
    ({"mu": 5.0, "M": 5.0}, ["material.mu = 5", "material.M = 5"]),
    ({"mu": 5.0, "M": 6.0}, ["material.mu = 5", "material.M = 6", "nu"]),
    ({"K": 5.0, "M": 5.0}, ["material.K = 5", "material.M = 5", "mu = 0"]),
    ({"K": 5.0, "M": 4.0}, ["material.K = 5", "material.M = 4", "mu"]),
])
def test_non_physical_pairs(values, fragments):
    with pytest.raises(ModuliError) as exc:
        from_pair(values)
    msg = str(exc.value)
    for frag in fragments:
        assert frag in msg
    assert "mu > 0 and -1 < nu < 0.5" in msg


def test_bad_root():
    with pytest.raises(ModuliError, match="material.root"):
        from_pair({"E": 1.0, "M": 2.0}, root="up")


def test_moduli_error_is_value_error():
    assert issubclass(ModuliError, ValueError)
