"""Every exported card re-evaluated in its target's own convention.

For each (model, target) the test reads the numbers the card file holds with its own small
parser, codes the target's strain energy as the target's manual writes it (not vlab's model
classes), and compares the homogeneous incompressible nominal stress in uniaxial tension and
compression, equibiaxial and planar tension at λ = 0.7 … 4 with vlab's closed-form prediction
(vlab.identify.states.response) of the same card: 1e-9 relative. The bulk term is checked the
same way: the target's initial bulk modulus (2/D1, 2/d, k, K from PR) and, where vlab claims
the same U(J), the target's U at J = 0.8 and 1.25.

Target energies (J = 1, so Ī = I and λ̄ = λ):
- Abaqus / CalculiX: MR C10(I1 − 3) + C01(I2 − 3); REDUCED POLYNOMIAL Σ Ci0 (I1 − 3)^i;
  OGDEN Σ 2μ/α² (Σ λ^α − 3); ARRUDA-BOYCE μ Σ Ci/λm^(2i−2) (I1^i − 3^i)
- ANSYS: MOONEY, YEOH as above; OGDEN Σ μ/α (Σ λ^α − 3); BOYCE as Abaqus; GENT −μJm/2 ln(1 − (I1 − 3)/Jm)
- LS-DYNA: 077_H Σ Cpq (I1 − 3)^p (I2 − 3)^q; 077_O Σᵢ Σⱼ μⱼ/αⱼ (λᵢ^αⱼ − 1)
- FEBio: Mooney-Rivlin c1, c2; Yeoh Σ cᵢ (I1 − 3)^i; Ogden Σ cᵢ/mᵢ² (Σ λ^mᵢ − 3); Gent −G Jm/2 ln(…);
  neo-Hookean μ/2 (I1 − 3) − μ ln J + λ/2 ln²J with μ = E/(2(1 + v)), λ = Ev/((1 + v)(1 − 2v))
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from export_cases import PAIRS, card_for
from vlab.export import EXPORTERS
from vlab.export.header import UNITS
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, response

AB = (1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750)  # Abaqus §22.5.1 / ANSYS §4.6.1 series
STRETCH = np.geomspace(0.7, 4.0, 41)
KINDS = ("uniaxial", "equibiaxial", "planar")
H = 1e-30


def _inv(l1, l2, l3):
    return l1 * l1 + l2 * l2 + l3 * l3, 1 / (l1 * l1) + 1 / (l2 * l2) + 1 / (l3 * l3)


def _ogden(terms, l1, l2, l3, coef):
    return sum(coef(m, a) * (l1 ** a + l2 ** a + l3 ** a - 3) for m, a in terms)


# --- each target's file, read by the test, and its energy ------------------------------------
def _abaqus(text):
    lines = [l for l in text.splitlines() if l.strip() and not l.startswith("**")]
    i = next(i for i, l in enumerate(lines) if l.upper().startswith("*HYPERELASTIC"))
    v = []
    for l in lines[i + 1:]:
        if l.startswith("*"):
            break
        v += [float(x) for x in l.split(",")]
    opt = lines[i].upper()
    if "MOONEY" in opt:
        return (lambda l1, l2, l3: (lambda I: v[0] * (I[0] - 3) + v[1] * (I[1] - 3))(_inv(l1, l2, l3))), 2 / v[2], \
            ("quadratic", 2 / v[2])
    if "REDUCED POLYNOMIAL" in opt:
        return (lambda l1, l2, l3: sum(v[i] * (_inv(l1, l2, l3)[0] - 3) ** (i + 1) for i in range(3))), 2 / v[3], \
            ("quadratic", 2 / v[3])
    if "OGDEN" in opt:
        n = int(re.search(r"N=(\d)", opt).group(1))
        terms = [(v[2 * i], v[2 * i + 1]) for i in range(n)]
        return (lambda l1, l2, l3: _ogden(terms, l1, l2, l3, lambda m, a: 2 * m / a ** 2)), 2 / v[2 * n], \
            ("quadratic", 2 / v[2 * n])
    mu, lm, D = v
    return (lambda l1, l2, l3: mu * sum(c / lm ** (2 * i) * (_inv(l1, l2, l3)[0] ** (i + 1) - 3 ** (i + 1))
                                        for i, c in enumerate(AB))), 2 / D, ("simo-taylor", 2 / D)


def _ansys(text):
    tb = re.search(r"^TB,HYPER,1,1,(\d*),(\w+)", text, re.M)
    data = {}
    for start, rest in re.findall(r"^TBDATA,(\d+),(.*)$", text, re.M):
        for k, x in enumerate(rest.split(",")):
            data[int(start) + k] = float(x)
    v = [data[i] for i in sorted(data)]
    opt = tb.group(2)
    if opt == "MOONEY":
        return (lambda l1, l2, l3: (lambda I: v[0] * (I[0] - 3) + v[1] * (I[1] - 3))(_inv(l1, l2, l3))), 2 / v[2], \
            ("quadratic", 2 / v[2])
    if opt == "YEOH":
        return (lambda l1, l2, l3: sum(v[i] * (_inv(l1, l2, l3)[0] - 3) ** (i + 1) for i in range(3))), 2 / v[3], \
            ("quadratic", 2 / v[3])
    if opt == "OGDEN":
        n = int(tb.group(1))
        terms = [(v[2 * i], v[2 * i + 1]) for i in range(n)]
        return (lambda l1, l2, l3: _ogden(terms, l1, l2, l3, lambda m, a: m / a)), 2 / v[2 * n], \
            ("quadratic", 2 / v[2 * n])
    a, b, d = v
    if opt == "BOYCE":
        return (lambda l1, l2, l3: a * sum(c / b ** (2 * i) * (_inv(l1, l2, l3)[0] ** (i + 1) - 3 ** (i + 1))
                                           for i, c in enumerate(AB))), 2 / d, ("simo-taylor", 2 / d)
    return (lambda l1, l2, l3: -a * b / 2 * np.log(1 - (_inv(l1, l2, l3)[0] - 3) / b)), 2 / d, ("simo-taylor", 2 / d)


def _lsdyna(text):
    lines = text.splitlines()
    i = next(i for i, l in enumerate(lines) if l.startswith("*MAT_"))
    rows = [[float(x) for x in l.split()] for l in lines[i + 1:] if l.strip() and not l.startswith("$")]
    nu = rows[0][2]
    if "OGDEN" in lines[i]:
        terms = list(zip(rows[1], rows[2]))
        G0 = 0.5 * sum(m * a for m, a in terms)
        K = 2 * G0 * (1 + nu) / (3 * (1 - 2 * nu))
        return (lambda l1, l2, l3: sum(m / a * (l ** a - 1) for m, a in terms for l in (l1, l2, l3))), K, None
    C10, C01, C11, C20, C02, C30 = rows[1]
    K = 2 * 2 * (C10 + C01) * (1 + nu) / (3 * (1 - 2 * nu))

    def W(l1, l2, l3):
        I1, I2 = _inv(l1, l2, l3)
        x, y = I1 - 3, I2 - 3
        return C10 * x + C01 * y + C11 * x * y + C20 * x * x + C02 * y * y + C30 * x ** 3
    return W, K, ("quadratic", K)


def _febio(text):
    el = ET.fromstring(text).find("material")
    p = {c.tag: float(c.text) for c in el}
    t = el.get("type")
    if t == "neo-Hookean":
        E, v = p["E"], p["v"]
        mu, lm = E / (2 * (1 + v)), E * v / ((1 + v) * (1 - 2 * v))
        return (lambda l1, l2, l3: mu / 2 * (_inv(l1, l2, l3)[0] - 3)), lm + 2 * mu / 3, None
    k = p["k"]
    if t == "Mooney-Rivlin":
        W = lambda l1, l2, l3: (lambda I: p["c1"] * (I[0] - 3) + p["c2"] * (I[1] - 3))(_inv(l1, l2, l3))
    elif t == "Yeoh":
        W = lambda l1, l2, l3: sum(p[f"c{i}"] * (_inv(l1, l2, l3)[0] - 3) ** i for i in (1, 2, 3))
    elif t == "Gent":
        W = lambda l1, l2, l3: -p["G"] * p["Jm"] / 2 * np.log(1 - (_inv(l1, l2, l3)[0] - 3) / p["Jm"])
    else:
        terms = [(p[f"c{i}"], p[f"m{i}"]) for i in range(1, 7) if f"c{i}" in p]
        W = lambda l1, l2, l3: _ogden(terms, l1, l2, l3, lambda c, m: c / m ** 2)
    return W, k, ("log", k)


ORACLE = {"abaqus": _abaqus, "calculix": _abaqus, "ansys": _ansys, "lsdyna": _lsdyna, "febio": _febio}
U = {"quadratic": lambda K, J: K / 2 * (J - 1) ** 2,          # (J − 1)²/D1 with D1 = 2/K
     "simo-taylor": lambda K, J: K / 2 * ((J * J - 1) / 2 - np.log(J)),  # (1/D)((J² − 1)/2 − ln J)
     "log": lambda K, J: K / 2 * np.log(J) ** 2}             # FEBio k/2 (ln J)²


def _stress(W, kind, lam):
    """Incompressible nominal stress (w1 − w3)/λ1, w_i = λ_i ∂W/∂λ_i by complex steps."""
    l1, l2 = lam, {"uniaxial": lam ** -0.5, "equibiaxial": lam, "planar": np.ones_like(lam)}[kind]
    l3 = 1 / (l1 * l2)
    w1 = l1 * np.imag(W(l1 + 1j * H, l2 + 0j, l3 + 0j)) / H
    w3 = l3 * np.imag(W(l1 + 0j, l2 + 0j, l3 + 1j * H)) / H
    return (w1 - w3) / l1


def _vlab(card, kind, lam):
    law = law_for(card.model, card.terms)
    p = card.params
    c = {"neo-hookean": lambda: [p["mu"]], "mooney-rivlin": lambda: [p["C10"], p["C01"]],
         "yeoh": lambda: [p["C10"], p["C20"], p["C30"]], "gent": lambda: [p["mu"], p["Jm"]],
         "arruda-boyce": lambda: [p["mu"], p["lambda_m"]], "ogden": lambda: list(p["mu"]) + list(p["alpha"])}
    x = np.linalg.solve(law.transform, np.array(c[card.model](), float))
    return response(Constitutive(law), x[None, :], kind, lam)[0]


ORACLE_PAIRS = [(l, t) for l, t in PAIRS if t in ORACLE]


@pytest.mark.parametrize("label,target", ORACLE_PAIRS)
def test_the_exported_card_in_its_targets_own_energy_equals_vlabs_closed_form(label, target):
    card = card_for(label, target)
    W, K, _ = ORACLE[target](EXPORTERS[target].write(card, UNITS["mm"]))
    for kind in KINDS:
        got, want = _stress(W, kind, STRETCH), _vlab(card, kind, STRETCH)
        scale = np.max(np.abs(want))
        assert np.all(np.abs(got - want) <= 1e-9 * np.maximum(np.abs(want), 1e-6 * scale)), (kind, got - want)
    K_card = card.K if card.K is not None else card.params["lambda"] + 2 * card.params["mu"] / 3
    assert abs(K / K_card - 1) < 1e-12


@pytest.mark.parametrize("label,target", [(l, t) for l, t in ORACLE_PAIRS if not card_for(l, t).stand_in])
def test_the_targets_volumetric_energy_is_the_cards(label, target):
    from vlab.materials.card import build_material, parse_material
    from vlab.export.card import material_table

    card = card_for(label, target)
    _, _, vol = ORACLE[target](EXPORTERS[target].write(card, UNITS["mm"]))
    law = build_material(parse_material(material_table(card)))
    J = np.array([0.8, 1.25])
    if vol is None:  # FEBio's coupled neo-Hookean: the whole energy at a compressible state
        text = EXPORTERS[target].write(card, UNITS["mm"])
        p = {c.tag: float(c.text) for c in ET.fromstring(text).find("material")}
        E, v = p["E"], p["v"]
        mu, lm = E / (2 * (1 + v)), E * v / ((1 + v) * (1 - 2 * v))
        F = np.diag([1.2, 0.9, 0.95])
        Jf, I1 = np.linalg.det(F), np.sum(F * F)
        febio = mu / 2 * (I1 - 3) - mu * np.log(Jf) + lm / 2 * np.log(Jf) ** 2
        assert abs(febio / law.energy(F[..., None])[0] - 1) < 1e-12
        return
    name, K = vol
    assert name == card.volumetric
    assert np.allclose(U[name](K, J), law.U(J - 1.0), rtol=1e-12, atol=0)


def test_ansys_and_lsdyna_ogden_mu_are_twice_vlabs_over_alpha_and_abaqus_mu_are_vlabs():
    card = card_for("ogden-3", "ansys")
    text = EXPORTERS["ansys"].write(card, UNITS["mm"])
    first = [float(x) for x in re.search(r"^TBDATA,1,(.*)$", text, re.M).group(1).split(",")]
    mu, alpha = card.params["mu"], card.params["alpha"]
    assert np.allclose(first[0:6:2], [2 * m / a for m, a in zip(mu, alpha)], rtol=1e-15)
    ab = EXPORTERS["abaqus"].write(card_for("ogden-3", "abaqus"), UNITS["mm"])
    line = ab.split("\n*HYPERELASTIC, OGDEN, N=3\n")[1].splitlines()[0]
    assert np.allclose([float(x) for x in line.split(",")][0:6:2], mu, rtol=1e-15)


def test_si_units_scale_the_moduli_by_1e6_and_the_density_by_1e12():
    card = card_for("mooney-rivlin", "abaqus")
    mm, si = (EXPORTERS["abaqus"].write(card, UNITS[u]) for u in ("mm", "SI"))
    num = lambda t, k: [float(x) for x in t.split(f"\n{k}\n")[1].split("\n")[0].split(",")]  # noqa: E731
    a, b = num(mm, "*HYPERELASTIC, MOONEY-RIVLIN"), num(si, "*HYPERELASTIC, MOONEY-RIVLIN")
    assert np.allclose(b[:2], np.array(a[:2]) * 1e6, rtol=1e-15) and abs(b[2] / a[2] - 1e-6) < 1e-15
    assert abs(num(si, "*DENSITY")[0] - 1100.0) < 1e-9 and abs(num(mm, "*DENSITY")[0] - 1.1e-9) < 1e-24
