/**
 * svbrdf layer functions (contract `layerType: "svbrdf"`, docs/rendering.md): Lambert + isotropic
 * Ward with E = π. Which maps exist is compiled in (`#define`s from `svbrdfDefines`): `SV_NORMALS`,
 * `SV_KD`, `SV_KS`, `SV_GLOSS` are the plane index of each map (-1 when absent), `SV_SRGB` is 1 when
 * kd/ks are sRGB-encoded, `SV_DISPLAY` is 1 when maps and shading are in display values (no decode,
 * no final encode: `inputColorSpace: "display"`, what `lanterna fit` writes by default). (Branching on uniforms instead costs as much as both sides on a CPU
 * rasteriser.) Without a normal map the layer is a flat image (kd, unshaded).
 */
import { U_GLOSS_LIMITS, U_HALF, U_LIGHT, U_PARAM } from '../../gl/uniforms';

const I = U_PARAM.lightIntensity;

/** Layer functions of an svbrdf program. */
export const SVBRDF_FRAGMENT_BODY = /* glsl */ `
uniform vec2 ${U_GLOSS_LIMITS};

vec3 sv_decode(vec3 v) {
#if SV_SRGB == 1
  return srgb_to_linear(v);
#else
  return v;
#endif
}

// the display value of a shaded (linear, or display when SV_DISPLAY) colour
vec3 sv_encode(vec3 v) {
#if SV_DISPLAY == 1
  return v;
#else
  return linear_to_srgb(v);
#endif
}

// linear kd, ks and alpha, with the contract's defaults for missing maps
void sv_material(out vec3 kd, out vec3 ks, out float alpha) {
#if SV_KD < 0
  kd = vec3(0.7);
  ks = vec3(0.15);
  alpha = 0.25;
#else
  kd = sv_decode(lanterna_plane(SV_KD));
#if SV_KS < 0
  ks = vec3(0.0);
  alpha = (${U_GLOSS_LIMITS}.x + ${U_GLOSS_LIMITS}.y) * 0.5;
#else
  ks = sv_decode(lanterna_plane(SV_KS));
#if SV_GLOSS < 0
  alpha = (${U_GLOSS_LIMITS}.x + ${U_GLOSS_LIMITS}.y) * 0.5;
#else
  alpha = ${U_GLOSS_LIMITS}.x + lanterna_plane(SV_GLOSS).r * (${U_GLOSS_LIMITS}.y - ${U_GLOSS_LIMITS}.x);
#endif
#endif
#endif
}

vec3 sv_kd() {
  vec3 kd, ks;
  float alpha;
  sv_material(kd, ks, alpha);
  return kd;
}

#if SV_NORMALS < 0
// no shape: a plain image (kd as stored when sRGB)
vec3 lt_normal() { return vec3(0.0, 0.0, 1.0); }
vec3 lt_color() {
#if SV_KD >= 0 && (SV_SRGB == 1 || SV_DISPLAY == 1)
  return lanterna_plane(SV_KD);
#else
  return linear_to_srgb(clamp01(sv_kd()));
#endif
}
vec3 lt_albedo() { return lt_color(); }
#else
vec3 lt_normal() { return normalize(lanterna_plane(SV_NORMALS)); }
vec3 lt_color() {
  vec3 kd, ks;
  float alpha;
  sv_material(kd, ks, alpha);
  vec3 n = lt_normal();
  float cosi = max(0.0, dot(n, ${U_LIGHT}));
  float cosr = max(n.z, 1e-4);
  float nh = max(dot(n, ${U_HALF}), 1e-4);
  float tan2 = (1.0 - nh * nh) / (nh * nh);
  float a2 = alpha * alpha;
  vec3 radiance = kd * cosi + ks * exp(-tan2 / a2) * sqrt(cosi / cosr) / (4.0 * a2);
  return sv_encode(clamp01(radiance * ${I}));
}
vec3 lt_albedo() { return sv_encode(sv_kd()); }
#endif

vec3 lt_diffuse() {
  return sv_encode(clamp01(sv_kd() * max(0.0, dot(lt_normal(), ${U_LIGHT})) * ${I}));
}
vec3 lt_achromatic() { return vec3(luma(lt_color())); }
vec3 lt_specular() {
  vec3 c = lt_color();
  float s = pow(clamp(dot(lt_normal(), ${U_HALF}), 0.0, 1.0), ${U_PARAM.specExponent});
  return c * ${U_PARAM.specKd} + mean3(c) * ${U_PARAM.specKs} * 2.0 * s;
}
`;
