"""Material cards of the rubber models used across the tests (K as given; overridden per test)."""

from vlab.materials.card import parse_material

CARDS = {
    "mooney-rivlin": {"model": "mooney-rivlin", "C10": 0.3, "C01": 0.08},
    "yeoh": {"model": "yeoh", "C10": 0.4, "C20": -0.02, "C30": 0.004},
    "ogden": {"model": "ogden", "mu": [0.63, 0.0012, -0.01], "alpha": [1.3, 5.0, -2.0]},
    "gent": {"model": "gent", "mu": 0.5, "Jm": 12.0},
    "arruda-boyce": {"model": "arruda-boyce", "mu": 0.45, "lambda_m": 2.8},
}
NAMES = tuple(CARDS)


def card(name: str, **bulk) -> dict:
    """The test card of ``name`` with its bulk key (default K = 20 MPa)."""
    return CARDS[name] | (bulk or {"K": 20.0})


def law(name: str, **bulk):
    """The validated one-field law of the test card."""
    from vlab.materials import build_material

    return build_material(parse_material(card(name, **bulk)))
