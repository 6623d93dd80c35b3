// ahdpack AHD decode (manifest version 1) — GLSL. The same math as src/fit/ahd_decode.cpp, the
// reference decoder; tests/gl renders this on Mesa and compares with it.
//
// Inputs are the SAMPLED (filtered) plane values:
//   iz        — the iz plane's RGB (HDR irradiance along the surface normal)
//   dir_uv01  — the dir plane's RG (hemi-octahedral, UNORM [0,1])  (packed profiles: dirratio.rg)
//   ratio     — the ratio plane (luminance form: .rrr; rgb form: .rgb) (packed profiles: dirratio.bbb)
//   n         — the unit shading normal in the texel's tangent frame (z = surface normal)
//   dz_min    — the manifest's decode.dz_min
// Returns irradiance E(n) (no 1/π; multiply by albedo/π for Lambertian outgoing radiance).
// A conversion whose manifest says "directional": false has no dir/ratio planes: pass
// dir_uv01 = vec2(0.5) and ratio = vec3(1.0) (d = z, pure ambient), or simply use iz.

vec3 ahd_hemi_oct_decode(vec2 uv01) {
  vec2 uv = uv01 * 2.0 - 1.0;
  vec2 p = vec2(uv.x + uv.y, uv.x - uv.y) * 0.5;
  return normalize(vec3(p, max(0.0, 1.0 - abs(p.x) - abs(p.y))));
}

vec3 ahd_irradiance(vec3 iz, vec2 dir_uv01, vec3 ratio, vec3 n, float dz_min) {
  vec3 d = ahd_hemi_oct_decode(dir_uv01);
  if (d.z < dz_min) {  // the horizon rule, exactly as the encoder applies it
    float rxy = length(d.xy);
    d = rxy > 1e-12 ? vec3(d.xy * (sqrt(1.0 - dz_min * dz_min) / rxy), dz_min) : vec3(0.0, 0.0, 1.0);
  }
  vec3 ca = ratio * iz;
  vec3 cd = (iz - ca) / d.z;
  return ca + max(0.0, dot(n, d)) * cd;
}

// World-space conversions (manifest decode.direction_frame == "normal-frame"): the stored direction
// is in this frame around the geometric normal ng (Duff et al. 2017); bring the shading normal
// into it with  n_local = ahd_to_frame(ng, n_world).
vec3 ahd_to_frame(vec3 ng, vec3 v) {
  float s = ng.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + ng.z);
  float b = ng.x * ng.y * a;
  vec3 t = vec3(1.0 + s * ng.x * ng.x * a, s * b, -s * ng.x);
  vec3 bt = vec3(b, s + ng.y * ng.y * a, -ng.y);
  return vec3(dot(t, v), dot(bt, v), dot(ng, v));
}
