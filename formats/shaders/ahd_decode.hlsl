// ahdpack AHD decode (manifest version 1) — HLSL. The same math as src/fit/ahd_decode.cpp and
// formats/shaders/ahd_decode.glsl (see there for the inputs; without dir/ratio planes, i.e.
// "directional": false in the manifest, the irradiance is iz for every normal).

float3 ahd_hemi_oct_decode(float2 uv01) {
  float2 uv = uv01 * 2.0 - 1.0;
  float2 p = float2(uv.x + uv.y, uv.x - uv.y) * 0.5;
  return normalize(float3(p, max(0.0, 1.0 - abs(p.x) - abs(p.y))));
}

float3 ahd_irradiance(float3 iz, float2 dir_uv01, float3 ratio, float3 n, float dz_min) {
  float3 d = ahd_hemi_oct_decode(dir_uv01);
  if (d.z < dz_min) {  // the horizon rule, exactly as the encoder applies it
    float rxy = length(d.xy);
    d = rxy > 1e-12 ? float3(d.xy * (sqrt(1.0 - dz_min * dz_min) / rxy), dz_min) : float3(0.0, 0.0, 1.0);
  }
  float3 ca = ratio * iz;
  float3 cd = (iz - ca) / d.z;
  return ca + max(0.0, dot(n, d)) * cd;
}

// World-space conversions (manifest decode.direction_frame == "normal-frame"), as in the GLSL file.
float3 ahd_to_frame(float3 ng, float3 v) {
  float s = ng.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + ng.z);
  float b = ng.x * ng.y * a;
  float3 t = float3(1.0 + s * ng.x * ng.x * a, s * b, -s * ng.x);
  float3 bt = float3(b, s + ng.y * ng.y * a, -ng.y);
  return float3(dot(t, v), dot(bt, v), dot(ng, v));
}
