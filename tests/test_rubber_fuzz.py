"""Property test: random rubber cards (valid or not) on a roller/clamped block either are
refused with a SceneError or run to a sane result or a diagnosed stop (fuzz_scenes.run_and_check)."""

from __future__ import annotations

from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from fuzz_scenes import run_and_check

constant = st.one_of(st.floats(0.01, 2.0), st.floats(0.01, 2.0), st.floats(0.01, 2.0), st.sampled_from([-0.3, 0.0, 1e-6]))


@st.composite
def cards(draw) -> dict:
    model = draw(st.sampled_from(["mooney-rivlin", "yeoh", "ogden", "gent", "arruda-boyce"]))
    card = {"model": model}
    if model == "mooney-rivlin":
        card |= {"C10": draw(constant), "C01": draw(constant)}
    elif model == "yeoh":
        card |= {"C10": draw(constant), "C20": draw(st.floats(-0.05, 0.2)), "C30": draw(st.floats(-0.01, 0.05))}
    elif model == "ogden":
        n = draw(st.integers(1, 3))
        card |= {"mu": [draw(constant) for _ in range(n)],
                 "alpha": [draw(st.floats(-4.0, 6.0)) for _ in range(draw(st.sampled_from([n, n, n, n + 1])))]}
    elif model == "gent":
        card |= {"mu": draw(constant), "Jm": draw(st.floats(-1.0, 50.0))}
    else:
        card |= {"mu": draw(constant), "lambda_m": draw(st.floats(0.5, 8.0))}
    bulk = draw(st.sampled_from(["K", "D1", "nu"]))
    card[bulk] = draw({"K": st.floats(0.5, 1e4), "D1": st.floats(0.0, 2.0), "nu": st.floats(-0.9, 0.4999)}[bulk])
    card["volumetric"] = draw(st.sampled_from(["quadratic", "log", "simo-taylor"]))
    return card


@st.composite
def scenes(draw) -> dict:
    kind = draw(st.sampled_from(["uniaxial", "biaxial"]))
    s = draw(st.floats(0.5, 2.5).filter(lambda v: abs(v - 1.0) > 1e-3))
    return {"name": "fuzz-rubber", "specimen": {"shape": "block", "size": [4.0, 3.0, 2.0]},
            "mesh": {"size": 2.0, "cell": "hex", "formulation": draw(st.sampled_from(["displacement", "mixed"]))},
            "material": draw(cards()),
            "test": {"kind": kind, "grips": draw(st.sampled_from(["roller", "clamped"])) if kind == "uniaxial"
                     else "roller", "stretch": s if kind == "uniaxial" else [s, 1.0 + 0.5 * (s - 1.0)],
                     "steps": draw(st.integers(1, 3))},
            "solver": {"max_cutbacks": 5}}


@settings(max_examples=12, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(scenes())
def test_random_rubber_cards_are_refused_cleanly_or_run_sanely(raw):
    outcome = run_and_check(raw)
    assert outcome != "stopped: other", "a stop whose cause is none of the diagnosed kinds"
    event(outcome)
