// Lays out the Godot projects that main.gd (run in Godot 4.6 by run_godot.mjs) wrote, and bakes
// their lightmaps the way Godot 4.6's directional LightmapGI stores them — without Godot's GPU
// lightmapper, which the web build lacks:
//   node bake.mjs EMITTED_DIR OUT_DIR
// For every project in EMITTED_DIR/corpus.json, OUT_DIR/<name>/ receives the files Godot wrote
// (emitted as <name>__<path with "/" spelt "__">), project.godot, NAME.exr and NAME.exr.import.
//
// The bake (facts from Godot's modules/lightmapper_rd/lm_compute.glsl and lightmapper_rd.cpp, read,
// not copied; layout as in docs/bakers.md, paragraph "Atlas pages", and formats/bakers/godot4-packed.json):
// - coverage: each user's triangles rasterised at its rectangle of its page as Godot's raster pass
//   does (below: filled + wire, half a texel up-left; atlas position = (uv_scale.position + uv2 ·
//   uv_scale.size) · size, v down), from Godot's own world-space arrays in corpus.json — not from
//   ahdpack's decoders;
// - light: an analytic sky (zenith/horizon gradient, ground below, a soft glow around the sun)
//   integrated as Godot's bounce pass accumulates it, over cosine-weighted directions d about the
//   texel's interpolated normal: L0 = 0.25 · mean(L(d)), L1 = mean(L(d) · (d.y, d.z, d.x))
//   (MODE_BOUNCE_LIGHT, USE_SH_LIGHTMAPS), on a fixed stratified grid instead of random rays; plus
//   a DirectionalLight as the direct pass encodes it (shadeSH below); no occlusion;
// - dilation (MODE_DILATE, Godot 4.4+): every texel takes the first lit texel met along the 8
//   directions (-1,0), (0,1), (1,0), (0,-1), (-1,-1), (-1,1), (1,-1), (1,1) at radius 1, then 2, ...
//   up to 4 · supersampling_factor = 4 (supersampling off); a lit texel keeps its own value only
//   when no neighbour at radius 1 is lit (the shader does not test the texel itself first:
//   godotengine/godot#123749);
// - packing (MODE_PACK_L1_COEFFS): L1 layers store clamp(L1 / (8 · L0 + 1e-6) + 0.5, 0, 1), so
//   empty texels hold 0.5; L0 as is;
// - file: one half-float EXR, channels B, G, R, the layers stacked vertically page-major
//   (page p: rows of layers 4p + 0..3 = L0, L1y, L1z, L1x), ZIP-compressed (Godot's tinyexr
//   writes PIZ; any compression reads the same).
// Not reproduced: shadows and bounces between meshes, the denoiser, seam blending, random noise.
import { readFileSync, writeFileSync, mkdirSync, readdirSync, rmSync, existsSync } from 'node:fs';
import { join, dirname } from 'node:path';
import { createHash } from 'node:crypto';
import { deflateSync } from 'node:zlib';

const [emitted, outRoot] = process.argv.slice(2);
if (!emitted || !outRoot) { console.error('usage: node bake.mjs EMITTED_DIR OUT_DIR'); process.exit(64); }
// Numbers as Godot's float32 (f32_json.mjs may have written them in their shortest form).
const readJson = (f) => JSON.parse(readFileSync(join(emitted, f), 'utf8'), (k, v) => (typeof v === 'number' ? Math.fround(v) : v));
// corpus.json: the projects whose arrays the readers' tests compare (godot_arrays.json); wild.json:
// issue 40's further rows (FBX with its unwrap cache, a cache missing an entry Godot dropped).
const corpus = readJson('corpus.json').concat(existsSync(join(emitted, 'wild.json')) ? readJson('wild.json') : []);
// Issue 40's Godot 4.0 pre-release row, derived from `gltf` (godot40 below): the same two .glb
// instances (their GODOT_single_root extension taken out: Godot 4.0 did not know it, and imported
// every glTF under a root named after the file), the scene in the pre-release text spelling, the
// .lmbake in binary resource format 4 with 4.0's LightmapGIData properties, raw L1.
const gltfProject = corpus.find((p) => p.name === 'gltf');
if (gltfProject) {
  const p40 = JSON.parse(JSON.stringify(gltfProject));
  p40.name = 'godot40', p40.godot40 = true, p40.godot = '4.0 pre-release (derived from Godot 4.6 files)';
  p40.users = p40.users.filter((u) => u.path.slice(3).includes('/'));
  for (const u of p40.users) {
    const [inst, ...rest] = u.path.slice(3).split('/');
    u.path = `../${inst}/${inst.toLowerCase()}/${rest.join('/')}`;
  }
  corpus.push(p40);
}

// ---- analytic lighting -------------------------------------------------------------------
const SUN = norm([0.45, 0.8, 0.35]);
const SUN_RGB = [1.5, 1.25, 0.9], SUN_K = 24.0;  // the sky's glow around the sun
const DIRECT_RGB = [2.6, 2.3, 1.8];                 // a DirectionalLight along SUN (static bake)
const ZENITH = [0.25, 0.36, 0.62], HORIZON = [0.62, 0.66, 0.72], GROUND = [0.22, 0.18, 0.13];
function radiance(d, out) {
  const s = Math.exp(SUN_K * (d[0] * SUN[0] + d[1] * SUN[1] + d[2] * SUN[2] - 1));
  for (let c = 0; c < 3; ++c) {
    const sky = d[1] >= 0 ? ZENITH[c] * d[1] + HORIZON[c] * (1 - d[1]) : GROUND[c];
    out[c] = sky + SUN_RGB[c] * s;
  }
}
function norm(v) { const l = Math.hypot(v[0], v[1], v[2]); return [v[0] / l, v[1] / l, v[2] / l]; }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }

// Cosine-weighted directions about n (Godot's frame: generate_ray_dir_from_normal), stratified.
const N1 = 24, N2 = 48;
const LOCAL = [];
for (let i = 0; i < N1; ++i)
  for (let j = 0; j < N2; ++j) {
    const u1 = (i + 0.5) / N1, phi = 2 * Math.PI * (j + 0.5) / N2;
    LOCAL.push([Math.sqrt(u1) * Math.cos(phi), Math.sqrt(u1) * Math.sin(phi), Math.sqrt(1 - u1)]);
  }
const shCache = new Map();
// shadeSH: [L0 rgb, L1y rgb, L1z rgb, L1x rgb] (12 numbers) for the normal n.
function shFor(n) {
  const key = n.map((x) => Math.round(x * 1e5)).join(',');
  const hit = shCache.get(key);
  if (hit) return hit;
  const v0 = Math.abs(n[2]) < 0.999 ? [0, 0, 1] : [0, 1, 0];
  const t = norm(cross(v0, n)), b = norm(cross(t, n));
  const acc = new Float64Array(12), L = [0, 0, 0];
  for (const l of LOCAL) {
    const d = [t[0] * l[0] + b[0] * l[1] + n[0] * l[2], t[1] * l[0] + b[1] * l[1] + n[1] * l[2],
               t[2] * l[0] + b[2] * l[1] + n[2] * l[2]];
    radiance(d, L);
    const c = [0.25, d[1], d[2], d[0]];
    for (let k = 0; k < 4; ++k) for (let ch = 0; ch < 3; ++ch) acc[k * 3 + ch] += L[ch] * c[k];
  }
  const r = Array.from(acc, (x) => x / LOCAL.length);
  // The direct light (MODE_DIRECT_LIGHT, USE_SH_LIGHTMAPS, Godot 4.5+: godotengine/godot#107168):
  // light = colour · (n · l); a = n · l; c_l0 = 1 / (1 + 4a), c_l1 = 1 − c_l0;
  // L0 += light · c_l0, L1 += light · c_l1 / a · (l.y, l.z, l.x); nothing when a <= 0.0001. No shadow.
  const a = n[0] * SUN[0] + n[1] * SUN[1] + n[2] * SUN[2];
  if (a > 0.0001) {
    const c0 = 1 / (1 + 4 * a), c1 = 1 - c0, cs = [c0, c1 / a * SUN[1], c1 / a * SUN[2], c1 / a * SUN[0]];
    for (let k = 0; k < 4; ++k) for (let ch = 0; ch < 3; ++ch) r[k * 3 + ch] += DIRECT_RGB[ch] * a * cs[k];
  }
  for (let i = 0; i < 12; ++i) r[i] = Math.fround(r[i]);
  shCache.set(key, r);
  return r;
}

// ---- rasterisation ------------------------------------------------------------------------
// Godot's raster pass (lightmapper_rd.cpp, lm_raster.glsl): per page, every triangle drawn filled,
// then every triangle drawn again as lines ("draw wire", which covers the thin parts a
// centre-sampled fill misses), both at the same depth so the first texel written stays; the
// geometry shifted by half a texel up and left (uv_offset = -0.5 / atlas_size, godotengine/godot
// #81872, Godot 4.2+). A texel's normal is the vertex normals interpolated at its sample point.
// Lines are rasterised as Vulkan's diamond rule (a texel is hit where the segment passes within
// 0.5 of its centre in the L1 norm), on segment samples every 1/64 texel.
function bakeProject(p) {
  const S = p.size, pages = [];
  for (let k = 0; k < p.pages; ++k) pages.push({ cov: new Uint8Array(S * S), sh: new Float32Array(S * S * 12), owner: new Int32Array(S * S).fill(-1) });
  const tris = [];  // per page: [page, user index, P (pixel space), normals]
  p.users.forEach((u, ui) => {
    const [rx, ry, rw, rh] = u.uv_scale, shift = p.godot40 ? 0 : 0.5;  // the half texel: Godot 4.2+
    for (const s of u.surfaces) {
      const V = s.vertex, N = s.normal, T = s.uv2;
      const idx = s.index || [...Array(V.length / 3).keys()];
      for (let f = 0; f + 2 < idx.length; f += 3) {
        const ids = [idx[f], idx[f + 1], idx[f + 2]];
        tris.push({ page: u.page, user: ui,
                    P: ids.map((i) => [(rx + T[2 * i] * rw) * S - shift, (ry + T[2 * i + 1] * rh) * S - shift]),
                    N: ids.map((i) => [N[3 * i], N[3 * i + 1], N[3 * i + 2]]) });
      }
    }
  });
  const put = (pg, t, ui, n) => { pg.cov[t] = 1; pg.owner[t] = ui; pg.sh.set(shFor(norm(n)), t * 12); };
  const lerpN = (N, w0, w1, w2) => [0, 1, 2].map((c) => w0 * N[0][c] + w1 * N[1][c] + w2 * N[2][c]);
  for (const { page, user, P, N } of tris) {  // filled
    const pg = pages[page];
    const area = (P[1][0] - P[0][0]) * (P[2][1] - P[0][1]) - (P[2][0] - P[0][0]) * (P[1][1] - P[0][1]);
    if (area === 0) continue;
    const x0 = Math.max(0, Math.floor(Math.min(P[0][0], P[1][0], P[2][0]))), x1 = Math.min(S - 1, Math.ceil(Math.max(P[0][0], P[1][0], P[2][0])));
    const y0 = Math.max(0, Math.floor(Math.min(P[0][1], P[1][1], P[2][1]))), y1 = Math.min(S - 1, Math.ceil(Math.max(P[0][1], P[1][1], P[2][1])));
    for (let y = y0; y <= y1; ++y)
      for (let x = x0; x <= x1; ++x) {
        const cx = x + 0.5, cy = y + 0.5, t = y * S + x;
        if (pg.cov[t]) continue;
        const w0 = ((P[1][0] - cx) * (P[2][1] - cy) - (P[2][0] - cx) * (P[1][1] - cy)) / area;
        const w1 = ((P[2][0] - cx) * (P[0][1] - cy) - (P[0][0] - cx) * (P[2][1] - cy)) / area;
        const w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        put(pg, t, user, lerpN(N, w0, w1, w2));
      }
  }
  for (const { page, user, P, N } of tris) {  // wire
    const pg = pages[page];
    for (let e = 0; e < 3; ++e) {
      const a = P[e], b = P[(e + 1) % 3], na = N[e], nb = N[(e + 1) % 3];
      const steps = Math.max(1, Math.ceil(64 * Math.hypot(b[0] - a[0], b[1] - a[1])));
      for (let i = 0; i <= steps; ++i) {
        const f = i / steps, sx = a[0] + f * (b[0] - a[0]), sy = a[1] + f * (b[1] - a[1]);
        const x = Math.floor(sx), y = Math.floor(sy);
        if (x < 0 || y < 0 || x >= S || y >= S) continue;
        if (Math.abs(sx - x - 0.5) + Math.abs(sy - y - 0.5) >= 0.5) continue;
        const t = y * S + x;
        if (!pg.cov[t]) put(pg, t, user, [0, 1, 2].map((c) => (1 - f) * na[c] + f * nb[c]));
      }
    }
  }
  const stats = p.users.map((u, ui) => {
    let texels = 0;
    for (const pg of pages) for (const o of pg.owner) texels += o === ui;
    if (texels === 0) throw new Error(`${p.name}: ${u.path} covers no texel`);
    return `${u.path} p${u.page} ${texels}`;
  });
  return { pages, stats };
}

// ---- Godot 4.6's dilation -------------------------------------------------------------------
const DIRS = [[-1, 0], [0, 1], [1, 0], [0, -1], [-1, -1], [-1, 1], [1, -1], [1, 1]];
const MAX_RADIUS = 4;
function dilate(page, S) {
  const cov = new Uint8Array(S * S), sh = new Float32Array(S * S * 12);
  for (let y = 0; y < S; ++y)
    for (let x = 0; x < S; ++x) {
      let src = y * S + x, lit = page.cov[src] === 1;
      for (let r = 1; r <= MAX_RADIUS; ++r) {
        let found = -1;
        for (const [dx, dy] of DIRS) {
          const xx = x + dx * r, yy = y + dy * r;
          if (xx < 0 || yy < 0 || xx >= S || yy >= S) continue;
          if (page.cov[yy * S + xx]) { found = yy * S + xx; break; }
        }
        if (found >= 0) { src = found; lit = true; }
        if (lit) break;
      }
      const t = y * S + x;
      cov[t] = lit ? 1 : 0;
      if (lit) sh.set(page.sh.subarray(src * 12, src * 12 + 12), t * 12);
    }
  return { cov, sh };
}

// Godot 4.0-4.3's dilation (lm_compute.glsl before godotengine/godot#100765): a lit texel keeps
// its value; an empty one takes the first lit texel of a fixed list of offsets within 2 texels —
// sides, corners, far sides, far-mid corners, far corners.
const DIRS40 = [[-1, 0], [0, 1], [1, 0], [0, -1], [-1, -1], [-1, 1], [1, -1], [1, 1], [-2, 0], [0, 2], [2, 0], [0, -2],
                [-2, -1], [-2, 1], [2, -1], [2, 1], [-1, -2], [1, -2], [-1, 2], [1, 2], [-2, -2], [-2, 2], [2, -2], [2, 2]];
function dilate40(page, S) {
  const cov = new Uint8Array(S * S), sh = new Float32Array(S * S * 12);
  for (let y = 0; y < S; ++y)
    for (let x = 0; x < S; ++x) {
      let src = page.cov[y * S + x] ? y * S + x : -1;
      for (const [dx, dy] of DIRS40) {
        if (src >= 0) break;
        const xx = x + dx, yy = y + dy;
        if (xx >= 0 && yy >= 0 && xx < S && yy < S && page.cov[yy * S + xx]) src = yy * S + xx;
      }
      if (src < 0) continue;
      cov[y * S + x] = 1;
      sh.set(page.sh.subarray(src * 12, src * 12 + 12), (y * S + x) * 12);
    }
  return { cov, sh };
}

// Godot's binary resource (core/io/resource_format_binary.cpp) holding a LightmapGIData as Godot
// 4.0 saves it: format 4, flags NAMED_SCENE_IDS | UIDS, 11 reserved words, the string table, the
// lightmap as external resource 1, the data as the one internal resource with 4.0's properties
// light_texture (the external resource), uses_spherical_harmonics and user_data (per user:
// NodePath, Rect2 uv_scale, int slice, int sub_instance -1; scene/3d/lightmap_gi.cpp). probe_data
// is left out (no probes baked); there is no _uses_packed_directional (4.4+).
function lmbake40(users, exrRes, size) {
  const strings = [], sid = (t) => { let i = strings.indexOf(t); if (i < 0) i = strings.push(t) - 1; return i; };
  const str = (t) => { const b = Buffer.from(t + '\0', 'utf8'); return Buffer.concat([u32le(b.length), b]); };
  const props = [];
  props.push(Buffer.concat([u32le(sid('light_texture')), u32le(24), u32le(3), u32le(0)]));  // OBJECT, external #0
  props.push(Buffer.concat([u32le(sid('uses_spherical_harmonics')), u32le(2), u32le(1)]));  // BOOL true
  const ud = [u32le(sid('user_data')), u32le(30), u32le(users.length * 4)];               // ARRAY
  for (const u of users) {
    const names = u.path.split('/');
    ud.push(u32le(22), Buffer.from([names.length, 0, 0, 0]));                              // NODE_PATH, names, no subnames
    for (const n of names) ud.push(u32le(sid(n)));
    ud.push(u32le(11), f32s(...u.uv_scale));                                                 // RECT2
    ud.push(u32le(3), u32le(u.page), u32le(3), i32s(-1));                                    // INT slice, INT sub_instance
  }
  props.push(Buffer.concat(ud));
  const res = Buffer.concat([str('LightmapGIData'), u32le(props.length), ...props]);
  const head = Buffer.concat([Buffer.from('RSRC'), u32le(0), u32le(0), u32le(4), u32le(0), u32le(4), str('LightmapGIData'),
                              Buffer.alloc(8), u32le(3), Buffer.alloc(8, 0xff), Buffer.alloc(44)]);
  const table = Buffer.concat([u32le(strings.length), ...strings.map(str)]);
  const ext = Buffer.concat([u32le(1), str('CompressedTexture2DArray'), str(exrRes), Buffer.alloc(8, 0xff)]);
  const intName = str('local://LightmapGIData_1');
  const before = head.length + table.length + ext.length + 4 + intName.length + 8;
  const offset = Buffer.alloc(8);
  offset.writeBigUInt64LE(BigInt(before));
  return Buffer.concat([head, table, ext, u32le(1), intName, offset, res, Buffer.from('RSRC')]);
}

// The scene `gltf` as a Godot 4.0 pre-release writes it: load_steps, no unique_id, instance nodes
// without a type, a space inside every constructor's parentheses (ExtResource( "1" ),
// Transform3D( ... )); the Yard (a PlaneMesh) left out.
function tscn40(text) {
  text = text.replace(/\[sub_resource[^\]]*\]\n(?:[^\[\n][^\n]*\n)*\n/g, '')
             .replace(/\[node name="Yard"[^\]]*\]\n(?:[^\[\n][^\n]*\n)*\n/, '')
             .replace(/ unique_id=\d+/g, '').replace(/ type="Node3D"( parent="[^"]*" instance=)/g, '$1')
             .replace(/\b(ExtResource|SubResource|Transform3D|NodePath|Vector2i|Vector2|Vector3)\(([^()]*)\)/g, '$1( $2 )');
  const steps = (text.match(/^\[ext_resource /gm) || []).length + 1;
  return text.replace('[gd_scene format=3]', `[gd_scene load_steps=${steps} format=3]`);
}

// A .glb without the GODOT_single_root extension (JSON chunk rewritten, padded to 4 bytes).
function glbWithoutSingleRoot(buf) {
  const n = buf.readUInt32LE(12), j = JSON.parse(buf.subarray(20, 20 + n).toString('utf8'));
  delete j.extensionsUsed;
  for (const sc of j.scenes || []) delete sc.extensions;
  let js = Buffer.from(JSON.stringify(j), 'utf8');
  js = Buffer.concat([js, Buffer.alloc((4 - js.length % 4) % 4, 0x20)]);
  const rest = buf.subarray(20 + n), out = Buffer.concat([buf.subarray(0, 12), u32le(js.length), buf.subarray(16, 20), js, rest]);
  out.writeUInt32LE(out.length, 8);
  return out;
}

// ---- half floats and the EXR ------------------------------------------------------------------
const f32 = new Float32Array(1), u32 = new Uint32Array(f32.buffer);
function toHalf(v) {  // round to nearest even; finite inputs in range here
  f32[0] = v;
  const x = u32[0], sign = (x >>> 16) & 0x8000;
  let e = ((x >>> 23) & 0xff) - 127 + 15, m = x & 0x7fffff;
  if (e >= 31) return sign | 0x7c00;
  if (e <= 0) {
    if (e < -10) return sign;
    m |= 0x800000;
    const shift = 14 - e, half = m >>> shift, rem = m & ((1 << shift) - 1), mid = 1 << (shift - 1);
    return sign | (half + (rem > mid || (rem === mid && (half & 1)) ? 1 : 0));
  }
  const half = (e << 10) | (m >>> 13), rem = m & 0x1fff;
  return sign | (half + (rem > 0x1000 || (rem === 0x1000 && (half & 1)) ? 1 : 0));
}

function attr(name, type, data) {
  return Buffer.concat([Buffer.from(name + '\0' + type + '\0', 'latin1'), u32le(data.length), data]);
}
function u32le(v) { const b = Buffer.alloc(4); b.writeUInt32LE(v); return b; }
function i32s(...v) { const b = Buffer.alloc(4 * v.length); v.forEach((x, i) => b.writeInt32LE(x, 4 * i)); return b; }
function f32s(...v) { const b = Buffer.alloc(4 * v.length); v.forEach((x, i) => b.writeFloatLE(x, 4 * i)); return b; }

// An EXR of width × height half-float B, G, R texels; rgbAt(x, y) gives [r, g, b] (row 0 first).
function writeExr(width, height, rgbAt) {
  const chl = Buffer.concat(['B', 'G', 'R'].map((c) => Buffer.concat([Buffer.from(c + '\0', 'latin1'), i32s(1), Buffer.from([0, 0, 0, 0]), i32s(1, 1)])).concat([Buffer.from([0])]));
  const header = Buffer.concat([
    Buffer.from([0x76, 0x2f, 0x31, 0x01]), u32le(2),
    attr('channels', 'chlist', chl),
    attr('compression', 'compression', Buffer.from([3])),  // ZIP, 16 scanlines a block
    attr('dataWindow', 'box2i', i32s(0, 0, width - 1, height - 1)),
    attr('displayWindow', 'box2i', i32s(0, 0, width - 1, height - 1)),
    attr('lineOrder', 'lineOrder', Buffer.from([0])),
    attr('pixelAspectRatio', 'float', f32s(1)),
    attr('screenWindowCenter', 'v2f', f32s(0, 0)),
    attr('screenWindowWidth', 'float', f32s(1)),
    Buffer.from([0]),
  ]);
  const blocks = [];
  for (let y0 = 0; y0 < height; y0 += 16) {
    const lines = Math.min(16, height - y0), raw = Buffer.alloc(lines * width * 3 * 2);
    let o = 0;
    for (let y = y0; y < y0 + lines; ++y)
      for (const c of [2, 1, 0])  // B, G, R
        for (let x = 0; x < width; ++x) { raw.writeUInt16LE(toHalf(rgbAt(x, y)[c]), o); o += 2; }
    // OpenEXR's ZIP: bytes split into even/odd halves, then a delta predictor, then zlib.
    const t = Buffer.alloc(raw.length);
    for (let i = 0, a = 0, b = (raw.length + 1) >> 1; i < raw.length; ++i) t[i & 1 ? b++ : a++] = raw[i];
    for (let i = t.length - 1; i > 0; --i) t[i] = (t[i] - t[i - 1] + 128 + 256) & 0xff;
    const z = deflateSync(t, { level: 9 });
    const data = z.length < raw.length ? z : raw;
    blocks.push(Buffer.concat([i32s(y0, data.length), data]));
  }
  const table = Buffer.alloc(8 * blocks.length);
  let pos = header.length + table.length;
  blocks.forEach((b, i) => { table.writeBigUInt64LE(BigInt(pos), 8 * i); pos += b.length; });
  return Buffer.concat([header, table, ...blocks]);
}

// ---- the projects --------------------------------------------------------------------------------
const files = readdirSync(emitted);
// Files for negative tests (negative__NAME): OUT_DIR/negative/NAME.
for (const f of files.filter((f) => f.startsWith('negative__'))) {
  mkdirSync(join(outRoot, 'negative'), { recursive: true });
  writeFileSync(join(outRoot, 'negative', f.slice('negative__'.length)), readFileSync(join(emitted, f)));
}
for (const p of corpus) {
  const dir = join(outRoot, p.name);
  if (existsSync(dir)) rmSync(dir, { recursive: true });
  const from = p.godot40 ? 'gltf' : p.name;
  for (const f of files.filter((f) => f.startsWith(from + '__'))) {
    const rel = f.slice(from.length + 2).split('__').join('/');
    mkdirSync(dirname(join(dir, rel)), { recursive: true });
    let data = readFileSync(join(emitted, f));
    if (p.godot40 && rel.endsWith('.glb')) data = glbWithoutSingleRoot(data);
    if (p.godot40 && rel.endsWith('.tscn')) data = Buffer.from(tscn40(data.toString('utf8')), 'utf8');
    if (p.godot40 && rel.endsWith('.lmbake')) data = lmbake40(p.users.map((u) => ({ ...u, path: u.path })), p.lightmap + '.exr', p.size);
    writeFileSync(join(dir, rel), data);
    // An .fbx imported with Static Lightmaps: Godot 4.6's scene importer's file (the options the
    // reader reads: meshes/light_baking = 2, the texel size the cache was keyed with, ufbx).
    if (rel.endsWith('.fbx'))
      writeFileSync(join(dir, rel) + '.import', `[remap]\n\nimporter="scene"\nimporter_version=1\ntype="PackedScene"\n\n` +
        `[deps]\n\nsource_file="res://${rel}"\n\n[params]\n\nnodes/root_type=""\nnodes/root_name=""\n` +
        `meshes/ensure_tangents=true\nmeshes/generate_lods=true\nmeshes/create_shadow_meshes=true\n` +
        `meshes/light_baking=2\nmeshes/lightmap_texel_size=0.2\nfbx/importer=0\n`);
  }
  const features = p.godot40 ? '"4.0", "Vulkan Clustered"' : '"4.6", "Forward Plus"';
  writeFileSync(join(dir, 'project.godot'),
    `; Engine configuration file.\n; Made by tests/tools/godot/gen/corpus (files written by Godot ${p.godot}).\n\n` +
    `config_version=5\n\n[application]\n\nconfig/name="${p.name}"\nrun/main_scene="${p.scene}"\n` +
    `config/features=PackedStringArray(${features})\n`);
  const { pages, stats } = bakeProject(p);
  const S = p.size, layers = 4 * p.pages;
  const dil = pages.map((pg) => (p.godot40 ? dilate40(pg, S) : dilate(pg, S)));
  const px = [0, 0, 0];
  const exr = writeExr(S, S * layers, (x, y) => {
    const layer = Math.floor(y / S), page = dil[layer >> 2], k = layer & 3, t = (y % S) * S + x;
    for (let c = 0; c < 3; ++c) {
      const l0 = page.sh[t * 12 + c];
      if (p.godot40) px[c] = k === 0 ? l0 : page.sh[t * 12 + 3 * k + c];  // raw L1 (before 4.4)
      else px[c] = k === 0 ? l0 : Math.min(1, Math.max(0, Math.fround(page.sh[t * 12 + 3 * k + c] / Math.fround(l0 * 8 + 1e-6)) + 0.5));
    }
    return px;
  });
  const exrRes = p.lightmap + '.exr', exrPath = join(dir, exrRes.replace('res://', ''));
  mkdirSync(dirname(exrPath), { recursive: true });
  writeFileSync(exrPath, exr);
  const md5 = createHash('md5').update(exrRes).digest('hex');
  const uid = 'uid://' + BigInt('0x' + md5.slice(0, 15)).toString(36);
  const dest = `res://.godot/imported/${exrRes.split('/').pop()}-${md5}.ctexarray`;
  // Godot 4.6's 2d_array_texture importer file (the parameters its LightmapGI sets for a bake).
  writeFileSync(exrPath + '.import', `[remap]\n\nimporter="2d_array_texture"\ntype="CompressedTexture2DArray"\nuid="${uid}"\n` +
    `path="${dest}"\nmetadata={\n"vram_texture": false\n}\n\n[deps]\n\nsource_file="${exrRes}"\ndest_files=["${dest}"]\n\n` +
    `[params]\n\ncompress/mode=3\ncompress/high_quality=false\ncompress/lossy_quality=0.7\ncompress/uastc_level=0\n` +
    `compress/rdo_quality_loss=0.0\ncompress/hdr_compression=1\ncompress/channel_pack=1\nmipmaps/generate=false\n` +
    `mipmaps/limit=-1\nslices/horizontal=1\nslices/vertical=${layers}\n`);
  // Per page: texels covered, lit after dilation, and lit at a Chebyshev distance of 4 from the
  // coverage (the part of Godot 4.4+'s ring beyond 3 texels).
  const ring = pages.map((pg, k) => {
    let cov = 0, lit = 0, at4 = 0;
    for (let y = 0; y < S; ++y)
      for (let x = 0; x < S; ++x) {
        cov += pg.cov[y * S + x];
        if (!dil[k].cov[y * S + x]) continue;
        ++lit;
        let d = 99;
        for (let dy = -MAX_RADIUS; dy <= MAX_RADIUS; ++dy)
          for (let dx = -MAX_RADIUS; dx <= MAX_RADIUS; ++dx) {
            const xx = x + dx, yy = y + dy;
            if (xx >= 0 && yy >= 0 && xx < S && yy < S && pg.cov[yy * S + xx]) d = Math.min(d, Math.max(Math.abs(dx), Math.abs(dy)));
          }
        if (d > 4) throw new Error(`${p.name}: page ${k}: texel ${x},${y} lit beyond the dilation`);
        at4 += d === 4;
      }
    return `page ${k}: ${cov} covered, ${lit} lit, ${at4} at 4 texels`;
  });
  console.log(`bake: ${p.name}: ${p.users.length} users on ${p.pages} page(s) of ${S}x${S}; ${ring.join('; ')}; ` +
              `${exr.length} bytes EXR (texels per user: ${stats.join(', ')})`);
}
