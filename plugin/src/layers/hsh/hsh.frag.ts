/**
 * HSH layer functions (contract `layerType: "hsh"`, docs/rendering.md): plane k holds term k's
 * R, G, B coefficients; `TERMS` (4, 9 or 16) is a compile-time define. The light's weights come in
 * as uniforms (`hshWeights` on the CPU); the basis is also evaluated per pixel, at the normal, for ρ.
 * {@link basisFragmentBody} is the same body for any basis of that layout (the `sh` kind's too).
 */
import { U_HALF, U_HSH_NORMAL_INV, U_HSH_NORMAL_WEIGHTS, U_PARAM, U_WEIGHTS } from '../../gl/uniforms';

const I = U_PARAM.lightIntensity;

/** Per-pixel HSH basis (same formulas as `hshWeights`), as the body's `lt_basis`. */
const HSH_BASIS = /* glsl */ `
void lt_basis(vec2 l, out float w[16]) {
  float r = length(l);
  float rc = min(r, 1.0);
  float lz = sqrt(max(0.0, 1.0 - rc * rc));
  float theta = min(acos(clamp(lz, 0.0, 1.0)), 1.5707963267948966 - 0.04);
  float x = cos(theta);
  float s = sqrt(max(x - x * x, 0.0));
  float cp = 1.0, sp = 0.0;
  if (r >= 1e-6) {
    cp = l.x / r;
    sp = l.y / r;
  }
  float c2 = cp * cp - sp * sp, s2 = 2.0 * sp * cp;
  float c3 = 4.0 * cp * cp * cp - 3.0 * cp, s3 = 3.0 * sp - 4.0 * sp * sp * sp;
  const float PI = 3.141592653589793;
  float xx = x * x - x, x2 = 2.0 * x - 1.0, s3p = s * s * s;
  float q5 = 1.0 - 5.0 * x + 5.0 * x * x;
  w[0] = 1.0 / sqrt(2.0 * PI);
  w[1] = sqrt(6.0 / PI) * cp * s;
  w[2] = sqrt(3.0 / (2.0 * PI)) * x2;
  w[3] = sqrt(6.0 / PI) * sp * s;
  w[4] = sqrt(30.0 / PI) * c2 * xx;
  w[5] = sqrt(30.0 / PI) * cp * x2 * s;
  w[6] = sqrt(5.0 / (2.0 * PI)) * (6.0 * x * x - 6.0 * x + 1.0);
  w[7] = sqrt(30.0 / PI) * sp * x2 * s;
  w[8] = sqrt(30.0 / PI) * s2 * xx;
  w[9] = 2.0 * sqrt(35.0 / PI) * c3 * s3p;
  w[10] = sqrt(210.0 / PI) * c2 * x2 * xx;
  w[11] = 2.0 * sqrt(21.0 / PI) * cp * s * q5;
  w[12] = sqrt(7.0 / (2.0 * PI)) * (20.0 * x * x * x - 30.0 * x * x + 12.0 * x - 1.0);
  w[13] = 2.0 * sqrt(21.0 / PI) * sp * s * q5;
  w[14] = sqrt(210.0 / PI) * s2 * x2 * xx;
  w[15] = 2.0 * sqrt(35.0 / PI) * s3 * s3p;
}
`;

/**
 * Layer functions of a program whose colour is `Σ_k plane_k · w_k(l)` over `TERMS` planes of R, G, B
 * coefficients, for a basis given as GLSL `void lt_basis(vec2 l, out float w[16])` (the weights of
 * the light projected at `l`, the first `TERMS` of them used): the light's weights in `u_weights`,
 * the normal from three fixed relights (`u_hshNormalWeights`, 16 per light), ρ relit along the normal.
 */
export const basisFragmentBody = (basis: string): string => /* glsl */ `
uniform float ${U_HSH_NORMAL_WEIGHTS}[48];
uniform mat3 ${U_HSH_NORMAL_INV};
${basis}
vec3 lt_raw() {
  vec3 c = vec3(0.0);
  for (int k = 0; k < TERMS; k++) {
    c += lanterna_plane(k) * ${U_WEIGHTS}[k];
  }
  return c;
}
vec3 lt_color() { return lt_raw() * ${I}; }
// Relight (unclamped) under three fixed lights, I_i = r + g + b, g = M⁻¹ I
vec3 lt_normal() {
  vec3 i3 = vec3(0.0);
  for (int k = 0; k < TERMS; k++) {
    vec3 p = lanterna_plane(k);
    vec3 wk = vec3(${U_HSH_NORMAL_WEIGHTS}[k], ${U_HSH_NORMAL_WEIGHTS}[16 + k], ${U_HSH_NORMAL_WEIGHTS}[32 + k]);
    i3 += (p.r + p.g + p.b) * wk;
  }
  vec3 g = ${U_HSH_NORMAL_INV} * i3;
  float len = length(g);
  return len < 1e-6 ? vec3(0.0, 0.0, 1.0) : g / len;
}
vec3 lt_albedo() {
  float w[16];
  lt_basis(lt_normal().xy, w);
  vec3 c = vec3(0.0);
  for (int k = 0; k < TERMS; k++) {
    c += lanterna_plane(k) * w[k];
  }
  return c;
}
vec3 lt_diffuse() { return lanterna_diffuse(lt_albedo(), lt_normal()); }
vec3 lt_achromatic() { return vec3(luma(lt_color())); }
vec3 lt_specular() {
  vec3 c = lt_color();
  float s = pow(clamp(dot(lt_normal(), ${U_HALF}), 0.0, 1.0), ${U_PARAM.specExponent} / 5.0);
  return c * ${U_PARAM.specKd} + mean3(c) * ${U_PARAM.specKs} * 4.0 * s;
}
vec3 lt_unsharp_q() { return lt_color(); }
vec3 lt_unsharp(vec3 q, vec3 qbar) { return q + ${U_PARAM.umGain} * (q - qbar); }
`;

/** Layer functions of an HSH program. */
export const HSH_FRAGMENT_BODY = basisFragmentBody(HSH_BASIS);
