// vlab's interactive view: decode the embedded arrays, draw one model at one level with plotly.
"use strict";
const D = JSON.parse(document.getElementById("vlab-data").textContent);
function bytes(b64) { const s = atob(b64), u = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i); return u.buffer; }
const f32 = b => new Float32Array(bytes(b)), i32 = b => new Int32Array(bytes(b));
const $ = id => document.getElementById(id);
const cache = new Map();
function decoded(m) {
  if (!cache.has(m)) { const M = D.models[m], tri = i32(M.tri), t = i32(M.tcell);
    const n = tri.length / 3, I = new Array(n), J = new Array(n), K = new Array(n);
    for (let e = 0; e < n; e++) { I[e] = tri[3 * e]; J[e] = tri[3 * e + 1]; K[e] = tri[3 * e + 2]; }
    cache.set(m, {X: f32(M.X), I, J, K, tcell: t, outline: f32(M.outline)}); }
  return cache.get(m);
}
function columns(a, stride, n) { const out = [[], [], []];
  for (let p = 0; p < n; p++) for (let c = 0; c < 3; c++) out[c].push(a[stride * p + c]); return out; }
function traces(m, field, level) {
  const M = D.models[m], G = decoded(m), U = f32(M.U[level]), n = M.nv, x = [[], [], []];
  for (let p = 0; p < n; p++) for (let c = 0; c < 3; c++) x[c].push(G.X[3 * p + c] + U[3 * p + c]);
  const values = f32(M.fields[field][level]), intensity = Array.from(G.tcell, c => values[c]);
  const [lo, hi] = D.ranges[field];
  const out = [{type: "mesh3d", x: x[0], y: x[1], z: x[2], i: G.I, j: G.J, k: G.K, intensity,
    intensitymode: "cell", colorscale: "Viridis", cmin: lo, cmax: hi, flatshading: true, name: M.name,
    colorbar: {title: {text: D.fields[field], side: "right"}, exponentformat: "none", len: 0.75},
    lighting: {ambient: 0.55, diffuse: 0.7}, hovertemplate: "%{intensity:.4g}<extra></extra>"}];
  const o = columns(G.outline, 3, G.outline.length / 3);
  out.push({type: "scatter3d", mode: "lines", x: o[0], y: o[1], z: o[2], name: "undeformed outline",
    line: {color: "#888", width: 2}, hoverinfo: "skip", connectgaps: false});
  const named = new Set();  // one legend entry per kind of part (a shear test's two plates: one)
  for (const F of M.fixtures || []) { const P = f32(F.X), T = i32(F.tri), d = F.move[level], k = P.length / 3;
    const q = [[], [], []]; for (let p = 0; p < k; p++) for (let c = 0; c < 3; c++) q[c].push(P[3 * p + c] + d[c]);
    const t = columns(T, 3, T.length / 3);
    out.push({type: "mesh3d", x: q[0], y: q[1], z: q[2], i: t[0], j: t[1], k: t[2], name: F.name, color: F.colour,
      opacity: F.opacity, flatshading: true, hoverinfo: "skip", legendgroup: F.name, showlegend: !named.has(F.name),
      lighting: {ambient: 0.55}}); named.add(F.name); }
  for (const [name, mark] of Object.entries(M.marks)) { const p = columns(f32(mark.xyz[level]), 3, 2);
    out.push({type: "scatter3d", mode: "markers", x: p[0], y: p[1], z: p[2], name,
      marker: {size: 6, color: mark.colour, line: {color: "black", width: 1}}}); }
  return out;
}
const AXIS = {visible: false};
function draw() {
  const m = +$("model").value, field = $("field").value, level = Math.min(+$("level").value,
    D.models[m].levels.length - 1);
  $("label").textContent = D.models[m].levels[level];
  const box = $("view");
  Plotly.react(box, traces(m, field, level), {uirevision: "keep", margin: {l: 0, r: 0, t: 0, b: 0},
    width: box.clientWidth, height: box.clientHeight,
    scene: {aspectmode: "manual", aspectratio: D.view.aspect, camera: {eye: D.view.eye, up: D.view.up},
      xaxis: AXIS, yaxis: AXIS, zaxis: AXIS},
    legend: {x: 0, y: 1}, paper_bgcolor: "white"}, {displaylogo: false});
}
function setModel() { const M = D.models[+$("model").value];
  $("level").max = M.levels.length - 1; $("level").value = M.start; draw(); }
D.models.forEach((M, i) => $("model").add(new Option(M.name, i)));
Object.entries(D.fields).forEach(([k, label]) => $("field").add(new Option(label, k)));
if (D.field in D.fields) $("field").value = D.field;  // the report's colouring (torsion: the shear strain)
$("model").onchange = setModel; $("field").onchange = draw; $("level").oninput = draw;
window.addEventListener("resize", draw);
if (typeof Plotly === "undefined") $("view").textContent = D.plotly_missing;  // moved without ../_assets
else setModel();
