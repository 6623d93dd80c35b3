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
  if (c.supercompressionScheme !== 0) throw new Error(url + ': supercompressed KTX2 is not written by ahdpack');
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
// exact value the tests recompute on the CPU (tests/unit/three_render_test.cpp, detail_normal). A
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
