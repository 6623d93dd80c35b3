// The 3D view of `ahdpack preview` (src/cli/preview_3d.h). A classic script (the page works from
// file://): window.THREE from three_classic.js, window.AHD_VIEW from view3d_data.js. Everything
// is drawn on demand; <body data-status> is "ok" after the first frame, "error: …" otherwise.
// No MSAA: on a software rasteriser (SwiftShader, the tests') it costs seconds per frame.
(function () {
'use strict';
const $ = (id) => document.getElementById(id);
function status(s) { document.body.dataset.status = s; $('status').textContent = s; }
window.addEventListener('error', (e) => status('error: ' + e.message));
const V = window.AHD_VIEW, T = window.THREE;
if (!V || !T) { status('error: three_classic.js or view3d_data.js did not load'); return; }

function bytes(b64) { const s = atob(b64), u = new Uint8Array(s.length); for (let i = 0; i < s.length; ++i) u[i] = s.charCodeAt(i); return u; }
const f32 = (b64) => new Float32Array(bytes(b64).buffer);
const W = V.width, H = V.height, TAU = 2 * Math.PI;
const LUMA = [0.2126, 0.7152, 0.0722];
const lum = (c) => LUMA[0] * c[0] + LUMA[1] * c[1] + LUMA[2] * c[2];

// --- the planes: decoded values per page and level (the reference decoder's), and the textures.
const pages = V.pages.map((pg) => pg.levels.map((l) => ({ w: l.w, h: l.h, iz: f32(l.iz), d: f32(l.d), ratio: f32(l.ratio) })));
const coverage = V.coverage ? bytes(V.coverage) : null;
const rules = V.source ? bytes(V.source.rules) : null;
const mesh = { pos: f32(V.mesh.positions), st: f32(V.mesh.st), idx: new Uint32Array(bytes(V.mesh.indices).buffer) };
// A placed scene (a Godot project, --mesh with --placement) gives each triangle's atlas page: the
// shown page's triangles are drawn, in 3D and on the lightmap.
const triPage = V.mesh.page ? new Int32Array(bytes(V.mesh.page).buffer) : null;
function pageIndices() {
  if (!triPage) return mesh.idx;
  const out = [];
  for (let t = 0; t < triPage.length; ++t)
    if (triPage[t] === state.page) out.push(mesh.idx[3 * t], mesh.idx[3 * t + 1], mesh.idx[3 * t + 2]);
  return new Uint32Array(out);
}

// The reference decode (fit/ahd_decode.h decode_irradiance) for the readout.
function decodeE(iz, d, ratio, n, dzMin) {
  let len = Math.hypot(d[0], d[1], d[2]);
  let u = len > 0 ? [d[0] / len, d[1] / len, d[2] / len] : [0, 0, 1];
  if (u[2] < dzMin) {
    const rxy = Math.hypot(u[0], u[1]);
    u = rxy > 1e-12 ? [u[0] * Math.sqrt(1 - dzMin * dzMin) / rxy, u[1] * Math.sqrt(1 - dzMin * dzMin) / rxy, dzMin] : [0, 0, 1];
  }
  const nd = Math.max(0, n[0] * u[0] + n[1] * u[1] + n[2] * u[2]);
  return [0, 1, 2].map((c) => { const ca = ratio[c] * iz[c]; return ca + nd * ((iz[c] - ca) / u[2]); });
}
// Hemi-octahedral encoding of a decoded direction (the inverse of ahd_hemi_oct_decode): the dir
// texture holds what the plane file holds, so the GPU filters the same values an engine would.
function hemiOct(d) {
  const s = Math.abs(d[0]) + Math.abs(d[1]) + Math.abs(d[2]) || 1, px = d[0] / s, py = d[1] / s;
  return [(px + py) * 0.5 + 0.5, (px - py) * 0.5 + 0.5];
}

let renderer = null, gl = null;
try {
  renderer = new T.WebGLRenderer({ canvas: $('view'), antialias: false, preserveDrawingBuffer: true });
  gl = renderer.getContext();
} catch (e) { renderer = null; }
const notes = [];
const floatLinear = gl && !!gl.getExtension('OES_texture_float_linear');

function floatTexture(levels, pick) {
  const mips = levels.map((l) => {
    const n = l.w * l.h, a = new Float32Array(n * 4);
    for (let i = 0; i < n; ++i) { const v = pick(l, i); a[i * 4] = v[0]; a[i * 4 + 1] = v[1]; a[i * 4 + 2] = v[2]; a[i * 4 + 3] = 1; }
    return { data: a, width: l.w, height: l.h };
  });
  const t = new T.DataTexture(mips[0].data, mips[0].width, mips[0].height, T.RGBAFormat, T.FloatType);
  t.mipmaps = mips;
  t.colorSpace = T.NoColorSpace;
  t.flipY = false;
  t.generateMipmaps = false;
  t.magFilter = floatLinear ? T.LinearFilter : T.NearestFilter;
  t.minFilter = floatLinear ? (mips.length > 1 ? T.LinearMipmapLinearFilter : T.LinearFilter) : T.NearestMipmapNearestFilter;
  t.wrapS = t.wrapT = T.ClampToEdgeWrapping;
  t.needsUpdate = true;
  return t;
}
const at3 = (a, i) => [a[i * 3], a[i * 3 + 1], a[i * 3 + 2]];

const state = { mode: 'ahd', nm: false, ev: 0, mip: -1, page: 0, yaw: 0.6, pitch: 0.7, dist: 0, zoom: 0, wire: true, cov: true };

let material = null, textures = [];
function buildTextures() {
  for (const t of textures) t.dispose();
  const lv = pages[state.page];
  textures = [floatTexture(lv, (l, i) => at3(l.iz, i)),
              floatTexture(lv, (l, i) => { const h = hemiOct(at3(l.d, i)); return [h[0], h[1], 0]; }),
              floatTexture(lv, (l, i) => at3(l.ratio, i))];
  if (material) { material.uniforms.izTex.value = textures[0]; material.uniforms.dirTex.value = textures[1]; material.uniforms.ratioTex.value = textures[2]; }
}

const FRAG = `
precision highp float;
precision highp sampler2DArray;
uniform sampler2D izTex, dirTex, ratioTex;
uniform sampler2DArray shTex;
uniform sampler2D covTex;   // coverage of level 0 (1 = covered); all 1 when unknown
uniform int mode, useNm;
uniform float expo, lod, dzMin;
in vec2 vSt;
` + V.decode_glsl + `
vec4 smp(sampler2D s) { return lod < 0.0 ? texture(s, vSt) : textureLod(s, vSt, lod); }
// The built-in detail normal map (tangent space of the lightmap texel): bumps h = sin·sin.
vec3 detailN(vec2 st) {
  const float F = 8.0;
  return normalize(vec3(-0.5 * cos(6.2831853 * F * st.x) * sin(6.2831853 * F * st.y),
                        -0.5 * sin(6.2831853 * F * st.x) * cos(6.2831853 * F * st.y), 1.0));
}
vec3 ahdE(vec3 n) { return ahd_irradiance(smp(izTex).rgb, smp(dirTex).rg, smp(ratioTex).rgb, n, dzMin); }
vec3 plainE() { return smp(izTex).rgb; }
vec3 shE(vec3 n) {
  float f[32];
  for (int k = 0; k < 8; ++k) { vec4 v = texture(shTex, vec3(vSt, float(k))); f[4*k] = v.x; f[4*k+1] = v.y; f[4*k+2] = v.z; f[4*k+3] = v.w; }
  vec3 e;
  for (int c = 0; c < 3; ++c) {
    int o = c * 10;
    e[c] = f[o] + f[o+1] * n.x + f[o+2] * n.y + f[o+3] * n.z + f[o+4] * n.x * n.x + f[o+5] * n.y * n.y + f[o+6] * n.z * n.z
         + 2.0 * (f[o+7] * n.x * n.y + f[o+8] * n.x * n.z + f[o+9] * n.y * n.z);
  }
  return max(e, vec3(0.0));
}
float L(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
vec3 heat(float x) { x = clamp(x, 0.0, 1.0); return vec3(clamp(3.0 * x, 0.0, 1.0), clamp(3.0 * x - 1.0, 0.0, 1.0), clamp(3.0 * x - 2.0, 0.0, 1.0)); }
void main() {
  vec3 n = useNm == 1 ? detailN(vSt) : vec3(0.0, 0.0, 1.0);
  vec3 c;
  if (mode == 0) c = ahdE(n) * expo;
  else if (mode == 1) c = shE(n) * expo;
  else if (mode == 2) c = plainE() * expo;
  else {
    // Gutters (dilated texels, no source value) are shown grey rather than as a huge difference.
    if (mode == 3 && texture(covTex, vSt).r < 0.5) { gl_FragColor = vec4(vec3(0.18), 1.0); return; }
    vec3 a = ahdE(n), b = mode == 3 ? shE(n) : plainE();
    gl_FragColor = vec4(heat(abs(L(a) - L(b)) / max(L(b), 1e-6) / 0.25), 1.0);
    return;
  }
  gl_FragColor = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}`;
const VERT = `
in vec2 st;
out vec2 vSt;
void main() { vSt = st; gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0); }`;

let scene, camera, geometry = null, center = new T.Vector3(), radius = 1;
function setup3d() {
  const g = new T.BufferGeometry();
  g.setAttribute('position', new T.BufferAttribute(mesh.pos, 3));
  g.setAttribute('st', new T.BufferAttribute(mesh.st, 2));
  g.setIndex(new T.BufferAttribute(pageIndices(), 1));
  geometry = g;
  g.computeBoundingSphere();
  center.copy(g.boundingSphere.center);
  radius = g.boundingSphere.radius || 1;
  state.dist = radius * 2.6;
  let shTex;
  if (V.source) {
    shTex = new T.DataArrayTexture(f32(V.source.poly), W, H, 8);
    shTex.format = T.RGBAFormat; shTex.type = T.FloatType;
    shTex.magFilter = shTex.minFilter = floatLinear ? T.LinearFilter : T.NearestFilter;
    shTex.needsUpdate = true;
  } else {
    shTex = new T.DataArrayTexture(new Float32Array(32), 1, 1, 8);
    shTex.format = T.RGBAFormat; shTex.type = T.FloatType; shTex.needsUpdate = true;
  }
  const covData = new Uint8Array(W * H * 4).fill(255);
  if (coverage) for (let i = 0; i < W * H; ++i) covData[i * 4] = coverage[i] ? 255 : 0;
  const covTex = new T.DataTexture(covData, W, H, T.RGBAFormat, T.UnsignedByteType);
  covTex.magFilter = covTex.minFilter = T.NearestFilter;
  covTex.flipY = false;
  covTex.needsUpdate = true;
  buildTextures();
  material = new T.ShaderMaterial({
    vertexShader: VERT, fragmentShader: FRAG, side: T.DoubleSide,
    uniforms: { izTex: { value: textures[0] }, dirTex: { value: textures[1] }, ratioTex: { value: textures[2] }, shTex: { value: shTex }, covTex: { value: covTex },
                mode: { value: 0 }, useNm: { value: 0 }, expo: { value: 1 }, lod: { value: -1 }, dzMin: { value: V.dz_min } } });
  scene = new T.Scene();
  scene.add(new T.Mesh(g, material));
  camera = new T.PerspectiveCamera(40, 600 / 450, radius * 0.01, radius * 100);
}

const MODES = { ahd: 0, sh: 1, plain: 2, 'diff-sh': 3, 'diff-plain': 4 };
function render3d() {
  if (!renderer) return;
  const u = material.uniforms;
  u.mode.value = MODES[state.mode];
  u.useNm.value = state.nm ? 1 : 0;
  u.expo.value = Math.pow(2, state.ev) / V.white;
  u.lod.value = state.mip;
  const cp = Math.cos(state.pitch);
  camera.position.set(center.x + state.dist * cp * Math.sin(state.yaw), center.y + state.dist * Math.sin(state.pitch),
                      center.z + state.dist * cp * Math.cos(state.yaw));
  camera.lookAt(center);
  renderer.render(scene, camera);
}

// --- the lightmap view: I_z of the shown level and page, exposure as the 3D view, coverage
// (uncovered texels tinted magenta) and the mesh's triangles in lightmap UV space.
function level() { const lv = pages[state.page]; return lv[Math.max(0, Math.min(lv.length - 1, state.mip < 0 ? 0 : state.mip))]; }
function lmScale(l) { return state.zoom > 0 ? state.zoom : Math.min(480 / l.w, 440 / l.h); }
function draw2d() {
  const l = level(), s = lmScale(l), c = $('lm');
  c.width = Math.max(1, Math.round(l.w * s)); c.height = Math.max(1, Math.round(l.h * s));
  const img = new ImageData(l.w, l.h), k = Math.pow(2, state.ev) / V.white;
  const cov = coverage && l.w === W && l.h === H && state.cov ? coverage : null;
  for (let i = 0; i < l.w * l.h; ++i) {
    for (let c3 = 0; c3 < 3; ++c3) img.data[i * 4 + c3] = 255 * Math.pow(Math.min(1, Math.max(0, l.iz[i * 3 + c3] * k)), 1 / 2.2);
    if (cov && !cov[i]) { img.data[i * 4] = 0.6 * img.data[i * 4] + 100; img.data[i * 4 + 2] = 0.6 * img.data[i * 4 + 2] + 100; img.data[i * 4 + 1] *= 0.6; }
    img.data[i * 4 + 3] = 255;
  }
  const off = document.createElement('canvas');
  off.width = l.w; off.height = l.h;
  off.getContext('2d').putImageData(img, 0, 0);
  const ctx = c.getContext('2d');
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(off, 0, 0, c.width, c.height);
  if (state.wire) {
    ctx.strokeStyle = 'rgba(0,255,255,0.7)'; ctx.lineWidth = 1; ctx.beginPath();
    const idx = pageIndices();
    for (let t = 0; t + 2 < idx.length; t += 3)
      for (let e = 0; e < 3; ++e) {
        const a = idx[t + e], b = idx[t + (e + 1) % 3];
        ctx.moveTo(mesh.st[a * 2] * c.width, mesh.st[a * 2 + 1] * c.height);
        ctx.lineTo(mesh.st[b * 2] * c.width, mesh.st[b * 2 + 1] * c.height);
      }
    ctx.stroke();
  }
}

const RULES = [[1, 'no direction (d = z)'], [2, 'horizon rule (d tilted to d_z = ε)'], [4, 'negative I_z clamped'], [8, 'black (ratio 1)'], [16, 'non-finite input']];
const fmt = (a) => '(' + Array.from(a, (v) => (Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(4) : v.toFixed(5))).join(', ') + ')';
// The readout of texel (x, y) of the shown level and page: the planes' values and E for the
// surface normal and four 45° tilts (the reference decoder's math), coverage and rules (level 0).
function readout(x, y) {
  const l = level(), lvIndex = state.mip < 0 ? 0 : state.mip, i = y * l.w + x;
  const iz = at3(l.iz, i), d = at3(l.d, i), ratio = at3(l.ratio, i), t = Math.SQRT1_2;
  const normals = [[0, 0, 1], [t, 0, t], [-t, 0, t], [0, t, t], [0, -t, t]];
  const e = normals.map((n) => decodeE(iz, d, ratio, n, V.dz_min));
  const full = l.w === W && l.h === H;
  const cov = coverage && full ? coverage[i] : null;
  const fired = rules && full && state.page === 0 ? RULES.filter(([b]) => rules[i] & b).map(([, s]) => s) : null;
  const r = { x, y, level: lvIndex, page: state.page, iz, d, ratio, normals, e, coverage: cov, rules: fired };
  const el = $('readout');
  el.dataset.texel = JSON.stringify(r);
  el.textContent =
    `texel (${x}, ${y})  level ${lvIndex} (${l.w}×${l.h})  page ${state.page}\n` +
    `I_z      ${fmt(iz)}\nd        ${fmt(d)}\nratio    ${fmt(ratio)}\n` +
    `E(z)     ${fmt(e[0])}\nE(±x45°) ${fmt(e[1])} ${fmt(e[2])}\nE(±y45°) ${fmt(e[3])} ${fmt(e[4])}\n` +
    `coverage ${cov === null ? (full ? 'unknown (no --source or --mesh)' : 'level 0 only') : cov ? 'covered' : 'not covered (dilated guard texel)'}\n` +
    `rules    ${fired === null ? (V.source ? 'level 0, page 0 only' : 'unknown (no --source)') : fired.length ? fired.join('; ') : 'none'}`;
  return r;
}
$('lm').addEventListener('click', (ev) => {
  const l = level(), s = lmScale(l), rc = $('lm').getBoundingClientRect();
  const x = Math.floor((ev.clientX - rc.left) / s), y = Math.floor((ev.clientY - rc.top) / s);
  if (x >= 0 && y >= 0 && x < l.w && y < l.h) readout(x, y);
});

// --- controls
function update() { render3d(); draw2d(); }
for (const el of document.querySelectorAll('input[name=mode]')) el.addEventListener('change', () => { if (el.checked) { state.mode = el.value; render3d(); } });
$('nm').addEventListener('change', () => { state.nm = $('nm').checked; render3d(); });
$('ev').addEventListener('input', () => { state.ev = Number($('ev').value); $('evv').textContent = state.ev; update(); });
$('zoom').addEventListener('change', () => { state.zoom = Number($('zoom').value); draw2d(); });
$('wire').addEventListener('change', () => { state.wire = $('wire').checked; draw2d(); });
$('cov').addEventListener('change', () => { state.cov = $('cov').checked; draw2d(); });
$('mip').add(new Option('auto (trilinear)', '-1'));
for (let l = 0; l < pages[0].length; ++l) $('mip').add(new Option(l + ' (' + pages[0][l].w + '×' + pages[0][l].h + ')', String(l)));
$('mip').addEventListener('change', () => { state.mip = Number($('mip').value); update(); });
for (let p = 0; p < pages.length; ++p) $('page').add(new Option(String(p), String(p)));
$('page').disabled = pages.length < 2;
$('page').addEventListener('change', () => {
  state.page = Number($('page').value);
  if (renderer) buildTextures();
  if (geometry && triPage) geometry.setIndex(new T.BufferAttribute(pageIndices(), 1));
  update();
});
if (!V.source) {
  for (const id of ['mode-sh', 'mode-diff-sh']) $(id).disabled = true;
  notes.push('No --source: the source-SH A/B and difference need the SH the conversion was made from.');
} else if (V.layers > 1) notes.push('The source SH is page 0 only.');
notes.push('The source SH is level 0 (the mip control changes the AHD and plain views only).');
if (!coverage) notes.push('Coverage unknown: give --source or --mesh.');
if (V.frame !== 'tangent') notes.push('World-space conversion: the views use each texel\'s local frame (z = surface normal).');

let drag = null;
$('view').addEventListener('pointerdown', (e) => { drag = [e.clientX, e.clientY]; $('view').setPointerCapture(e.pointerId); });
$('view').addEventListener('pointermove', (e) => {
  if (!drag) return;
  state.yaw -= (e.clientX - drag[0]) * 0.01; state.pitch = Math.max(-1.5, Math.min(1.5, state.pitch + (e.clientY - drag[1]) * 0.01));
  drag = [e.clientX, e.clientY]; render3d();
});
$('view').addEventListener('pointerup', () => { drag = null; });
$('view').addEventListener('wheel', (e) => { e.preventDefault(); state.dist *= Math.exp(e.deltaY * 0.001); render3d(); }, { passive: false });

if (!renderer) notes.push('WebGL2 is not available in this browser: the 3D view is off; the lightmap view and readout work.');
else if (!floatLinear) notes.push('No OES_texture_float_linear: the 3D view samples the planes without filtering.');
$('notes').textContent = notes.join(' ');
if (renderer) setup3d();
update();
readout(Math.floor(level().w / 2), Math.floor(level().h / 2));
if (!document.body.dataset.status.startsWith('error')) status('ok');
})();
