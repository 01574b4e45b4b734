"""The DIC Challenge 2.0 metrics of a run's camera in results.json (``dic.metrics``) and on the run
page (a table, one line of explanation per metric). Consumes vlab.dic.instrument.Record's noise
floor and spatial resolution (vlab.dic.resolution); computes no physics.
"""

from __future__ import annotations

import html

#: (label, explanation) per row of the run page's table, in order
EXPLANATIONS = {
    "noise": ("Displacement noise floor σ<sub>u</sub>, σ<sub>v</sub>",
              "standard deviation of u, v between two images of the unloaded face with fresh sensor noise "
              "(static pair): the smallest displacement the camera and settings resolve"),
    "strain_noise": ("Strain noise σ<sub>Exx</sub>, σ<sub>Eyy</sub>, σ<sub>Exy</sub>",
                     "standard deviation of the strains over the same static pair"),
    "bias": ("Sub-pixel translation bias",
             "mean error (and scatter) on a rigid shift of the face along both axes, half a pixel: where "
             "the interpolation's bias peaks"),
    "sr_u": ("Displacement spatial resolution",
             "period of a sinusoidal displacement whose measured amplitude is 10 % low: shorter waves are "
             "smoothed away by the subset (closed form for an affine subset of h px: 3.99 h)"),
    "sr_e": ("Strain spatial resolution",
             "the same for the strain E<sub>xy</sub> of the sinusoid: subset and strain window together"),
    "mei_u": ("MEI<sub>u</sub> = σ · SR<sub>u</sub>",
              "Metrological Efficiency Indicator: noise × resolution of the sinusoid's component; a larger "
              "subset trades one for the other, the product changes far less; smaller is better"),
    "mei_e": ("MEI<sub>ε</sub> = σ<sub>Exy</sub> · SR<sub>ε</sub>²",
              "the same for the strain (its noise falls as the square of the resolution)"),
}


def metrics_dict(rec) -> dict:
    """results.json's dic.metrics: the DIC Challenge 2.0 set of the run's camera in one place
    (px, mm, µε; None where not measured): noise floor, strain noise, sub-pixel bias, spatial
    resolution (with its closed form and sweep), MEI, and what measuring them cost (s)."""
    n, r = rec.noise, rec.resolution
    shift = n.get("translation") or {}
    out = {"level": "basic" if r is None else "full",
           "noise_floor_px": {"u": n.get("sigma_u_px"), "v": n.get("sigma_v_px")},
           "noise_floor_mm": n.get("sigma_u_mm"),
           "strain_noise_microstrain": {c: n.get(f"sigma_{c}_microstrain") for c in ("exx", "eyy", "exy")},
           "translation_bias_px": {"shift": shift.get("shift_px"), "u": shift.get("bias_u_px"),
                                   "v": shift.get("bias_v_px"), "std_u": shift.get("std_u_px"),
                                   "std_v": shift.get("std_v_px")},
           "time_s": {"noise_floor_and_bias": rec.timing.get("noise_floor_s"),
                      "spatial_resolution": rec.timing.get("resolution_s")}}
    if r is not None:
        out["spatial_resolution"] = {k: v for k, v in r.items() if k != "mei"}
        out["mei"] = r["mei"]
    return out


def _g(v, digits: int = 3) -> str:
    return "—" if v is None else f"{v:.{digits}g}"


def _resolution(sr: dict | None, name: str) -> str:
    if sr is None:
        return 'not measured (<code>metrics = "basic"</code>)'
    px = sr.get(f"{name}_px")
    if px is None:
        return f"not reached below {sr['longest_period_px']:.0f} px (the region of interest's extent)"
    return (f"{px:.1f} px ({sr[f'{name}_mm']:.3g} mm); closed form {sr['theory'][f'{name}_px']:.1f} px")


def _values(m: dict) -> dict:
    noise, strain, b = m["noise_floor_px"], m["strain_noise_microstrain"], m["translation_bias_px"]
    sr, mei = m.get("spatial_resolution"), m.get("mei") or {}
    mm = m.get("noise_floor_mm")
    return {"noise": f"{_g(noise['u'])}, {_g(noise['v'])} px" + ("" if mm is None else f" ({_g(mm * 1e3)} µm)"),
            "strain_noise": f"{_g(strain['exx'])}, {_g(strain['eyy'])}, {_g(strain['exy'])} µε",
            "bias": f"{_g(b['u'], 2)} px (u), {_g(b['v'], 2)} px (v) on {_g(b['shift'], 2)} px; scatter "
                    f"{_g(b['std_u'], 2)}, {_g(b['std_v'], 2)} px",
            "sr_u": _resolution(sr, "displacement"), "sr_e": _resolution(sr, "strain"),
            "mei_u": "—" if sr is None else f"{_g(mei.get('displacement_px2'))} px² (σ<sub>{sr['component']}</sub>)",
            "mei_e": "—" if sr is None else f"{_g(mei.get('strain_px2'))} px²"}


def metrics_table(m: dict) -> str:
    """The run page's table of dic.metrics (``m``): metric, value, one line of what it is."""
    values = _values(m)
    rows = "".join(f"<tr><th>{label}</th><td>{values[key]}</td><td><small>{why}</small></td></tr>"
                   for key, (label, why) in EXPLANATIONS.items())
    t, sr = m["time_s"], m.get("spatial_resolution")
    cost = f"{_g(t['noise_floor_and_bias'], 2)} s for the noise floor and bias"
    if sr is not None:
        cost += (f", {_g(t['spatial_resolution'], 2)} s for the spatial resolution ({len(sr['rows'])} sinusoids "
                 f"of {sr['amplitude_px']:g} px along image {sr['along']}, periods "
                 f"{sr['rows'][0]['period_px']:.0f}–{sr['rows'][-1]['period_px']:.0f} px)" if sr["rows"] else "")
    return (f"<table><tr><th>DIC Challenge 2.0 metric (this camera, speckle and settings)</th><th>value</th>"
            f"<th>what it is</th></tr>{rows}</table>\n<p><small>Measured in {html.escape(cost)}: "
            "images rendered with the run's camera and speckle through known fields and correlated like the "
            "levels (docs/dic.md).</small></p>")
