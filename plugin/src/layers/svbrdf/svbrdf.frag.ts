/**
 * svbrdf layer functions (contract `layerType: "svbrdf"`, docs/rendering.md): Lambert + isotropic
 * Ward with E = π. The plane index of each map comes in `u_maps` (normals, kd, ks, gloss; -1 when
 * absent). Without a normal map the layer is a flat image (kd, unshaded).
 */
import { U_GLOSS_LIMITS, U_HALF, U_LIGHT, U_MAPS, U_PARAM, U_SRGB_INPUT } from '../../gl/uniforms';

const I = U_PARAM.lightIntensity;

/** Layer functions of an svbrdf program. */
export const SVBRDF_FRAGMENT_BODY = /* glsl */ `
uniform ivec4 ${U_MAPS};
uniform vec2 ${U_GLOSS_LIMITS};
uniform int ${U_SRGB_INPUT};

vec3 sv_decode(vec3 v) { return ${U_SRGB_INPUT} == 1 ? srgb_to_linear(v) : v; }

// linear kd, ks and alpha, with the contract's defaults for missing maps
void sv_material(out vec3 kd, out vec3 ks, out float alpha) {
  float mid = (${U_GLOSS_LIMITS}.x + ${U_GLOSS_LIMITS}.y) * 0.5;
  if (${U_MAPS}.y < 0) {
    kd = vec3(0.7);
    ks = vec3(0.15);
    alpha = 0.25;
    return;
  }
  kd = sv_decode(lanterna_plane(${U_MAPS}.y));
  if (${U_MAPS}.z < 0) {
    ks = vec3(0.0);
    alpha = mid;
    return;
  }
  ks = sv_decode(lanterna_plane(${U_MAPS}.z));
  alpha = ${U_MAPS}.w < 0 ? mid
    : ${U_GLOSS_LIMITS}.x + lanterna_plane(${U_MAPS}.w).r * (${U_GLOSS_LIMITS}.y - ${U_GLOSS_LIMITS}.x);
}

vec3 sv_kd() {
  vec3 kd, ks;
  float alpha;
  sv_material(kd, ks, alpha);
  return kd;
}

vec3 lt_normal() { return normalize(lanterna_plane(${U_MAPS}.x)); }

vec3 lt_color() {
  if (${U_MAPS}.x < 0) {
    // no shape: a plain image (kd as stored when sRGB)
    if (${U_MAPS}.y >= 0 && ${U_SRGB_INPUT} == 1) {
      return lanterna_plane(${U_MAPS}.y);
    }
    return linear_to_srgb(clamp01(sv_kd()));
  }
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
  return linear_to_srgb(clamp01(radiance * ${I}));
}

vec3 lt_albedo() { return ${U_MAPS}.x < 0 ? lt_color() : linear_to_srgb(sv_kd()); }
vec3 lt_diffuse() {
  return linear_to_srgb(clamp01(sv_kd() * max(0.0, dot(lt_normal(), ${U_LIGHT})) * ${I}));
}
vec3 lt_achromatic() { return vec3(luma(lt_color())); }
vec3 lt_specular() {
  vec3 c = lt_color();
  float s = pow(clamp(dot(lt_normal(), ${U_HALF}), 0.0, 1.0), ${U_PARAM.specExponent});
  return c * ${U_PARAM.specKd} + mean3(c) * ${U_PARAM.specKs} * 2.0 * s;
}
`;
