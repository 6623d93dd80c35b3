// ahdpack AHD lightmaps in three.js (tested with three r187, WebGL2). An ES module; the page maps
// 'three' and 'three/addons/' with an import map. docs/engine-integration.md explains each choice.
//
//   const lm  = await loadAhdLightmap(renderer, 'conv/scene.json');   // the manifest written by convert
//   const mat = ahdMaterial(lm, await (await fetch('ahd_decode.glsl')).text(), { exposure: 1 });
//   mesh.material = mat;                                                 // lightmap UVs: 'uv1' or 'uv'
//
// Planes are loaded with three's own KTX2Loader. Its raw (non-Basis) path maps BC4, BC5, RGBA16F,
// R11G11B10 (B10G11R11_UFLOAT) and RGB9E5 (E5B9G9R9_UFLOAT), RG8, R8 and RGBA8, but NOT
// VK_FORMAT_BC6H_UFLOAT_BLOCK (143; r187 throws "Unsupported vkFormat"), and it makes 2D textures
// of array files (layerCount > 1). For those two cases loadAhdPlane parses the file with the
// ktx-parse copy three ships and builds the CompressedTexture / array texture itself.
import * as THREE from 'three';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';
import { read as readKtx2 } from 'three/addons/libs/ktx-parse.module.js';
import { ZSTDDecoder } from 'three/addons/libs/zstddec.module.js';

const VK_FORMAT_BC6H_UFLOAT_BLOCK = 143;

// Every plane is linear data (sRGB off), filtered bilinearly with trilinear mips, clamped at the
// atlas edge (the converter dilated the charts), no flip: KTXorientation is "rd" (row 0 at the
// top of the image, which is UV v = 0 in glTF and, with flipY = false, texture t = 0 in WebGL).
function setSampling(tex, levels) {
  tex.colorSpace = THREE.NoColorSpace;
  tex.magFilter = THREE.LinearFilter;
  tex.minFilter = levels > 1 ? THREE.LinearMipmapLinearFilter : THREE.LinearFilter;
  tex.wrapS = tex.wrapT = THREE.ClampToEdgeWrapping;
  tex.flipY = false;
  tex.generateMipmaps = false;
  tex.needsUpdate = true;
  return tex;
}

// One plane file -> a THREE texture (array texture when the file has layers = atlas pages).
export async function loadAhdPlane(loader, url) {
  const bytes = new Uint8Array(await (await fetch(url)).arrayBuffer());
  const c = readKtx2(bytes);
  if (c.supercompressionScheme !== 0) throw new Error(url + ': a --zstd file: load it with loadAhdPlaneArray');
  const layers = Math.max(1, c.layerCount);
  if (c.vkFormat !== VK_FORMAT_BC6H_UFLOAT_BLOCK && layers === 1) {
    const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
    const tex = await new Promise((resolve, reject) => loader.parse(buffer, resolve, reject));
    return setSampling(tex, c.levels.length);
  }
  // The formats KTX2Loader leaves out: we build the texture as three's loader would.
  const mipmaps = c.levels.map((lv, i) => ({
    data: lv.levelData, width: Math.max(1, c.pixelWidth >> i), height: Math.max(1, c.pixelHeight >> i) }));
  let tex;
  if (c.vkFormat === VK_FORMAT_BC6H_UFLOAT_BLOCK) {
    tex = layers > 1
      ? new THREE.CompressedArrayTexture(mipmaps, c.pixelWidth, c.pixelHeight, layers, THREE.RGB_BPTC_UNSIGNED_Format, THREE.UnsignedByteType)
      : new THREE.CompressedTexture(mipmaps, c.pixelWidth, c.pixelHeight, THREE.RGB_BPTC_UNSIGNED_Format, THREE.UnsignedByteType);
  } else {
    // Array files of the other formats: let KTX2Loader read page 0 for the format, then stack the pages.
    throw new Error(url + ': array planes (atlas pages) other than BC6H are not wired in this example yet');
  }
  return setSampling(tex, c.levels.length);
}

// The manifest and its planes. Returns { manifest, textures: {iz, dir, ratio} or {iz, dirratio} }.
export async function loadAhdLightmap(renderer, manifestUrl) {
  const manifest = await (await fetch(manifestUrl)).json();
  if (manifest.format !== 'ahdpack-manifest' || manifest.version !== 1) throw new Error(manifestUrl + ': not an ahdpack manifest v1');
  if (manifest.container !== 'ktx2') throw new Error(manifestUrl + ': three.js loads the KTX2 container; convert with -o NAME.ktx2');
  const loader = new KTX2Loader().detectSupport(renderer);
  const base = new URL(manifestUrl, document.baseURI);
  const textures = {};
  for (const p of manifest.planes) textures[p.name] = await loadAhdPlane(loader, new URL(p.file, base).href);
  loader.dispose();
  return { manifest, textures };
}

// The vertex and fragment shaders. `ahd_decode.glsl` (formats/shaders/) is pasted in unchanged.
// Defines: AHD_PACKED (dirratio plane), AHD_RATIO_RGB (ratio_form "rgb"), AHD_DIRECTIONAL,
// AHD_UV1 (lightmap UVs in the second set), and the uniform useDetail (the built-in detail normal).
// three compiles both as GLSL ES 3.00 (gl_FragColor is its alias of the output).
export const AHD_VERTEX = /* glsl */ `
#ifdef AHD_UV1
  #define AHD_LM_UV uv1
#else
  #define AHD_LM_UV uv
#endif
out vec2 vLmUv;
void main() {
  vLmUv = AHD_LM_UV;
  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

export const AHD_FRAGMENT_MAIN = /* glsl */ `
uniform sampler2D izMap;
#ifdef AHD_PACKED
uniform sampler2D dirratioMap;
#else
uniform sampler2D dirMap;
uniform sampler2D ratioMap;
#endif
uniform float dzMin;
uniform float exposure;   // linear multiplier on E (no 1/pi here: E, as the manifest says)
uniform float lodBias;    // < 0: sample the chain normally; >= 0: force that mip level
uniform int useDetail;    // 1: the built-in detail normal, 0: the flat normal (0,0,1)
in vec2 vLmUv;

vec4 ahd_sample(sampler2D s, vec2 uv) { return lodBias < 0.0 ? texture(s, uv) : textureLod(s, uv, lodBias); }

// The built-in detail normal (tangent space of the lightmap texel): a smooth bump pattern whose
// exact value the tests recompute on the CPU (tests/judges/three_render_test.cpp, detail_normal). A
// real material passes its normal map's tangent-space normal here instead (see the guide).
vec3 ahd_detail_normal(vec2 uv) {
  const float TAU = 6.28318530718;
  return normalize(vec3(0.6 * sin(TAU * 3.0 * uv.x), 0.6 * cos(TAU * 2.0 * uv.y), 1.0));
}

void main() {
  vec3 iz = ahd_sample(izMap, vLmUv).rgb;
#ifdef AHD_PACKED
  vec4 dr = ahd_sample(dirratioMap, vLmUv);
  vec2 dir = dr.rg;
  vec3 ratio = dr.bbb;
#else
  vec2 dir = ahd_sample(dirMap, vLmUv).rg;
  #ifdef AHD_RATIO_RGB
  vec3 ratio = ahd_sample(ratioMap, vLmUv).rgb;
  #else
  vec3 ratio = ahd_sample(ratioMap, vLmUv).rrr;
  #endif
#endif
#ifndef AHD_DIRECTIONAL
  dir = vec2(0.5); ratio = vec3(1.0);
#endif
  vec3 n = useDetail == 1 ? ahd_detail_normal(vLmUv) : vec3(0.0, 0.0, 1.0);
  vec3 e = ahd_irradiance(iz, dir, ratio, n, dzMin);
  gl_FragColor = vec4(e * exposure, 1.0);
}`;

// A ShaderMaterial that lights with E(n) * exposure (linear, no tone mapping: render to a float
// target or add your own tone map and output transform).
export function ahdMaterial(lm, decodeGlsl, { exposure = 1.0, detail = false, uv1 = false, lod = -1 } = {}) {
  const m = lm.manifest, t = lm.textures;
  const defines = {};
  if (t.dirratio) defines.AHD_PACKED = '';
  if (m.decode.ratio_form === 'rgb') defines.AHD_RATIO_RGB = '';
  if (m.directional) defines.AHD_DIRECTIONAL = '';
  if (uv1) defines.AHD_UV1 = '';
  const uniforms = {
    izMap: { value: t.iz }, dzMin: { value: m.decode.dz_min }, exposure: { value: exposure },
    lodBias: { value: lod }, useDetail: { value: detail ? 1 : 0 },
  };
  if (t.dirratio) uniforms.dirratioMap = { value: t.dirratio };
  else {
    uniforms.dirMap = { value: t.dir || t.iz };
    uniforms.ratioMap = { value: t.ratio || t.iz };
  }
  return new THREE.ShaderMaterial({
    defines, uniforms, vertexShader: AHD_VERTEX,
    fragmentShader: decodeGlsl + '\n' + AHD_FRAGMENT_MAIN,
  });
}

// ---- Whole scenes: every plane as an array texture (layer p = atlas page p) ----------------------
// A scene's conversion (a Godot project, --mesh with --placement) is sampled per instance at its
// page, so every plane is bound as a sampler2DArray, a one-page atlas as a one-layer array. Files
// written with --zstd (KTX2 supercompression scheme 2) are inflated with the zstd decoder three
// ships (examples/jsm/libs/zstddec.module.js). Uncompressed formats become a DataArrayTexture of
// level 0 only (three r187 uploads no mip chain for DataArrayTexture); BC6H/BC4/BC5 a
// CompressedArrayTexture with every level (KTX2 keeps a level's layers one after the other, as
// three expects).
const KTX2_ZSTD = 2;
// vkFormat -> [three format, three type, typed array, compressed?]
const AHD_ARRAY_FORMATS = {
  97: [THREE.RGBAFormat, THREE.HalfFloatType, Uint16Array, false],        // R16G16B16A16_SFLOAT
  9: [THREE.RedFormat, THREE.UnsignedByteType, Uint8Array, false],        // R8_UNORM
  16: [THREE.RGFormat, THREE.UnsignedByteType, Uint8Array, false],        // R8G8_UNORM
  37: [THREE.RGBAFormat, THREE.UnsignedByteType, Uint8Array, false],      // R8G8B8A8_UNORM
  122: [THREE.RGBFormat, THREE.UnsignedInt101111Type, Uint32Array, false],  // B10G11R11_UFLOAT_PACK32
  123: [THREE.RGBFormat, THREE.UnsignedInt5999Type, Uint32Array, false],    // E5B9G9R9_UFLOAT_PACK32
  143: [THREE.RGB_BPTC_UNSIGNED_Format, THREE.UnsignedByteType, Uint8Array, true],  // BC6H_UFLOAT_BLOCK
  139: [THREE.RED_RGTC1_Format, THREE.UnsignedByteType, Uint8Array, true],         // BC4_UNORM_BLOCK
  141: [THREE.RED_GREEN_RGTC2_Format, THREE.UnsignedByteType, Uint8Array, true],   // BC5_UNORM_BLOCK
};
let ahdZstd = null;

// One plane file -> an array texture, whatever its layer count and supercompression.
export async function loadAhdPlaneArray(url) {
  const bytes = new Uint8Array(await (await fetch(url)).arrayBuffer());
  const c = readKtx2(bytes);
  const f = AHD_ARRAY_FORMATS[c.vkFormat];
  if (!f) throw new Error(url + ': vkFormat ' + c.vkFormat + ' is not an ahdpack plane format');
  if (c.supercompressionScheme !== 0 && c.supercompressionScheme !== KTX2_ZSTD)
    throw new Error(url + ': supercompression scheme ' + c.supercompressionScheme + ' (ahdpack writes none or zstd)');
  if (c.supercompressionScheme === KTX2_ZSTD && !ahdZstd) {
    ahdZstd = new ZSTDDecoder();
    await ahdZstd.init();
  }
  const layers = Math.max(1, c.layerCount);
  const levels = c.levels.map((lv, i) => {
    const raw = c.supercompressionScheme === KTX2_ZSTD ? ahdZstd.decode(lv.levelData, lv.uncompressedByteLength) : lv.levelData;
    const copy = raw.slice();  // aligned, owned
    return { data: new f[2](copy.buffer, 0, copy.byteLength / f[2].BYTES_PER_ELEMENT),
             width: Math.max(1, c.pixelWidth >> i), height: Math.max(1, c.pixelHeight >> i) };
  });
  let tex;
  if (f[3]) {
    tex = new THREE.CompressedArrayTexture(levels, c.pixelWidth, c.pixelHeight, layers, f[0], f[1]);
    setSampling(tex, levels.length);
  } else {
    tex = new THREE.DataArrayTexture(levels[0].data, c.pixelWidth, c.pixelHeight, layers);
    tex.format = f[0];
    tex.type = f[1];
    setSampling(tex, 1);
  }
  tex.levelsInFile = c.levels.length;
  return tex;
}

// The manifest and its planes as array textures: { manifest, textures, izScale, frame }.
export async function loadAhdLightmapArrays(manifestUrl) {
  const manifest = await (await fetch(manifestUrl)).json();
  if (manifest.format !== 'ahdpack-manifest' || manifest.version !== 1) throw new Error(manifestUrl + ': not an ahdpack manifest v1');
  if (manifest.container !== 'ktx2') throw new Error(manifestUrl + ': three.js loads the KTX2 container; convert with -o NAME.ktx2');
  const base = new URL(manifestUrl, document.baseURI);
  const textures = {};
  for (const p of manifest.planes) textures[p.name] = await loadAhdPlaneArray(new URL(p.file, base).href);
  // Stored I_z = iz_scale x E (docs/container-format.md): the decoder divides by it.
  return { manifest, textures, izScale: manifest.decode.iz_scale ?? 1.0, frame: manifest.decode.direction_frame };
}

// A lightmapped mesh of a scene: world position and normal, the lightmap UVs in atlas space in the
// second set (glTF TEXCOORD_1 = three's 'uv1', as `ahdpack scene` writes them), bound to the
// attribute ahdLmUv by ahdLightScene (three declares 'uv1' only for its own materials' maps).
export const AHD_SCENE_VERTEX = /* glsl */ `
in vec2 ahdLmUv;
out vec2 vLmUv;
out vec3 vWorldNormal;
void main() {
  vLmUv = ahdLmUv;
  vWorldNormal = normalize(mat3(modelMatrix) * normal);  // ahdpack scene: identity node transforms
  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

// Output: 0 = linear E (exposure applied), 1 = tone-mapped, sRGB-encoded display colour,
// 2 = (lightmap u, v, page, 1) for probes.
export const AHD_SCENE_FRAGMENT_MAIN = /* glsl */ `
precision highp sampler2DArray;
uniform sampler2DArray izMap;
#ifdef AHD_PACKED
uniform sampler2DArray dirratioMap;
#else
uniform sampler2DArray dirMap;
uniform sampler2DArray ratioMap;
#endif
uniform float page;
uniform float dzMin;
uniform float izScale;
uniform float exposure;
uniform int outputMode;
in vec2 vLmUv;
in vec3 vWorldNormal;

// ACES filmic fit (Narkowicz 2015) and the sRGB transfer function.
vec3 ahd_tonemap(vec3 x) { return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0); }
vec3 ahd_srgb(vec3 c) { return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c)); }

void main() {
  vec3 at = vec3(vLmUv, page);
  vec3 iz = texture(izMap, at).rgb;
#ifdef AHD_PACKED
  vec4 dr = texture(dirratioMap, at);
  vec2 dir = dr.rg;
  vec3 ratio = dr.bbb;
#else
  vec2 dir = texture(dirMap, at).rg;
  #ifdef AHD_RATIO_RGB
  vec3 ratio = texture(ratioMap, at).rgb;
  #else
  vec3 ratio = texture(ratioMap, at).rrr;
  #endif
#endif
#ifndef AHD_DIRECTIONAL
  dir = vec2(0.5); ratio = vec3(1.0);
#endif
  vec3 ng = normalize(vWorldNormal);
  vec3 nWorld = ng;  // the shading normal: a normal-mapped material passes its world normal here
#ifdef AHD_NORMAL_FRAME
  vec3 n = ahd_to_frame(ng, nWorld);  // the frame the bake's direction is stored in
#else
  vec3 n = vec3(0.0, 0.0, 1.0);        // tangent frame: a flat surface
#endif
  vec3 e = ahd_irradiance(iz, dir, ratio, n, dzMin) / izScale * exposure;
  if (outputMode == 2) gl_FragColor = vec4(vLmUv, page, 1.0);
  else if (outputMode == 1) gl_FragColor = vec4(ahd_srgb(ahd_tonemap(e)), 1.0);
  else gl_FragColor = vec4(e, 1.0);
}`;

// The material of a scene's instances on atlas page `page` (one material per page).
export function ahdSceneMaterial(lm, decodeGlsl, page, { exposure = 1.0, outputMode = 1 } = {}) {
  const m = lm.manifest, t = lm.textures;
  const defines = {};
  if (t.dirratio) defines.AHD_PACKED = '';
  if (m.decode.ratio_form === 'rgb') defines.AHD_RATIO_RGB = '';
  if (m.directional) defines.AHD_DIRECTIONAL = '';
  if (lm.frame === 'normal-frame') defines.AHD_NORMAL_FRAME = '';
  const uniforms = {
    izMap: { value: t.iz }, page: { value: page }, dzMin: { value: m.decode.dz_min }, izScale: { value: lm.izScale },
    exposure: { value: exposure }, outputMode: { value: outputMode },
  };
  if (t.dirratio) uniforms.dirratioMap = { value: t.dirratio };
  else {
    uniforms.dirMap = { value: t.dir || t.iz };
    uniforms.ratioMap = { value: t.ratio || t.iz };
  }
  return new THREE.ShaderMaterial({
    defines, uniforms, vertexShader: AHD_SCENE_VERTEX, fragmentShader: decodeGlsl + '\n' + AHD_SCENE_FRAGMENT_MAIN,
  });
}

// Lights every mesh under `root` (GLTFLoader's scene of `ahdpack scene`'s .glb): its page is the
// node's extras.ahd_page (GLTFLoader keeps node extras in userData). Returns the materials, one per
// page, to change `exposure` / `outputMode` on.
export function ahdLightScene(root, lm, decodeGlsl, opts = {}) {
  const materials = new Map();
  root.traverse((o) => {
    if (!o.isMesh) return;
    const page = o.userData.ahd_page ?? 0;
    const uv = o.geometry.getAttribute('uv1');
    if (!uv) throw new Error((o.name || 'a mesh') + ': no lightmap UVs (TEXCOORD_1)');
    o.geometry.setAttribute('ahdLmUv', uv);
    if (!materials.has(page)) materials.set(page, ahdSceneMaterial(lm, decodeGlsl, page, opts));
    o.material = materials.get(page);
  });
  return [...materials.values()];
}
