/**
 * PTM layer functions (contract `layerType: "ptm"`, docs/rendering.md): basis weights
 * `[lu², lv², lu·lv, lu, lv, 1]` come in as uniforms, computed on the CPU by `ptmWeights`.
 * `PTM_LRGB` selects the lrgb layout (planes 0–1: L0…L5, plane 2: R,G,B); otherwise planes 2c and
 * 2c+1 hold channel c's six coefficients.
 */
import { U_HALF, U_PARAM, U_WEIGHTS } from '../../gl/uniforms';

const I = U_PARAM.lightIntensity;

/** Shared PTM helpers: evaluation, the Malzbender normal and the diffuse-gain transform. */
const PTM_COMMON = /* glsl */ `
vec3 ptm_w012() { return vec3(${U_WEIGHTS}[0], ${U_WEIGHTS}[1], ${U_WEIGHTS}[2]); }
vec3 ptm_w345() { return vec3(${U_WEIGHTS}[3], ${U_WEIGHTS}[4], ${U_WEIGHTS}[5]); }

// Σ a_k w_k for the light
float ptm_eval(vec3 a012, vec3 a345) { return dot(a012, ptm_w012()) + dot(a345, ptm_w345()); }

// Σ a_k w_k(u, v)
float ptm_eval_at(vec3 a012, vec3 a345, vec2 uv) {
  return dot(a012, vec3(uv.x * uv.x, uv.y * uv.y, uv.x * uv.y)) + dot(a345, vec3(uv, 1.0));
}

// Malzbender 2001: the polynomial's maximum, (0, 0, 1) when it has none
vec3 ptm_normal(vec3 p, vec3 q) {
  float a0 = p.x, a1 = p.y, a2 = p.z, a3 = q.x, a4 = q.y;
  float d = 4.0 * a0 * a1 - a2 * a2;
  if (d > 0.0 && a0 < 0.0) {
    vec2 l0 = vec2(a2 * a4 - 2.0 * a1 * a3, a2 * a3 - 2.0 * a0 * a4) / d;
    float r = length(l0);
    if (r > 1.0) {
      l0 /= r;
    }
    return vec3(l0, sqrt(max(0.0, 1.0 - l0.x * l0.x - l0.y * l0.y)));
  }
  return vec3(0.0, 0.0, 1.0);
}

// Malzbender 2001 diffuse gain: transformed coefficients a' for gain g at normal (nu, nv)
void ptm_gain(vec3 p, vec3 q, vec2 n, float g, out vec3 p2, out vec3 q2) {
  float a0 = p.x, a1 = p.y, a2 = p.z, a3 = q.x, a4 = q.y, a5 = q.z;
  float nu = n.x, nv = n.y;
  p2 = g * p;
  float b3 = (1.0 - g) * (2.0 * a0 * nu + a2 * nv) + a3;
  float b4 = (1.0 - g) * (2.0 * a1 * nv + a2 * nu) + a4;
  float b5 = (1.0 - g) * (a0 * nu * nu + a1 * nv * nv + a2 * nu * nv) + (a3 - b3) * nu + (a4 - b4) * nv + a5;
  q2 = vec3(b3, b4, b5);
}

float ptm_spec(vec3 n, float exponent) { return pow(clamp(dot(n, ${U_HALF}), 0.0, 1.0), exponent); }
`;

/** lrgb: `L = Σ L_k w_k`, `c = rgb·L·lightIntensity`. */
const PTM_LRGB = /* glsl */ `
float lt_lum() { return ptm_eval(lanterna_plane(0), lanterna_plane(1)); }
vec3 lt_color() { return lanterna_plane(2) * lt_lum() * ${I}; }
vec3 lt_normal() { return ptm_normal(lanterna_plane(0), lanterna_plane(1)); }
vec3 lt_albedo() { return lanterna_plane(2); }
vec3 lt_diffuse() { return lanterna_diffuse(lt_albedo(), lt_normal()); }
vec3 lt_achromatic() { return vec3(lt_lum() * ${I}); }
vec3 lt_specular() {
  float s = ptm_spec(lt_normal(), ${U_PARAM.specExponent});
  return (lanterna_plane(2) * ${U_PARAM.specKd} + ${U_PARAM.specKs} * s) * lt_lum() * ${I};
}
vec3 lt_diffuse_gain() {
  vec3 p = lanterna_plane(0), q = lanterna_plane(1), p2, q2;
  ptm_gain(p, q, ptm_normal(p, q).xy, ${U_PARAM.diffuseGain}, p2, q2);
  return lanterna_plane(2) * ptm_eval(p2, q2) * ${I};
}
vec3 lt_unsharp_q() { return vec3(lt_lum(), 0.0, 0.0); }
// the quantity's light-independent terms (filtered once per view) and the quantity from them
void lt_unsharp_terms(out vec3 t0, out vec3 t1) { t0 = lanterna_plane(0); t1 = lanterna_plane(1); }
vec3 lt_unsharp_from_terms(vec3 t0, vec3 t1) { return vec3(ptm_eval(t0, t1), 0.0, 0.0); }
vec3 lt_unsharp(vec3 q, vec3 qbar) {
  float l2 = q.x + ${U_PARAM.umGain} * (q.x - qbar.x);
  return lanterna_plane(2) * l2 * ${I};
}
`;

/** rgb: `c_ch = Σ a_{ch,k} w_k · lightIntensity`; the normal is the normalised mean of the channels'. */
const PTM_RGB = /* glsl */ `
vec3 lt_raw() {
  return vec3(ptm_eval(lanterna_plane(0), lanterna_plane(1)), ptm_eval(lanterna_plane(2), lanterna_plane(3)),
    ptm_eval(lanterna_plane(4), lanterna_plane(5)));
}
vec3 lt_color() { return lt_raw() * ${I}; }
vec3 lt_normal() {
  vec3 s = ptm_normal(lanterna_plane(0), lanterna_plane(1)) + ptm_normal(lanterna_plane(2), lanterna_plane(3))
    + ptm_normal(lanterna_plane(4), lanterna_plane(5));
  vec3 m = s / 3.0;
  float len = length(m);
  return len > 0.0 ? m / len : vec3(0.0, 0.0, 1.0);
}
vec3 lt_albedo() {
  vec2 n = lt_normal().xy;
  return vec3(ptm_eval_at(lanterna_plane(0), lanterna_plane(1), n), ptm_eval_at(lanterna_plane(2), lanterna_plane(3), n),
    ptm_eval_at(lanterna_plane(4), lanterna_plane(5), n));
}
vec3 lt_diffuse() { return lanterna_diffuse(lt_albedo(), lt_normal()); }
vec3 lt_achromatic() { return vec3(luma(lt_color())); }
vec3 lt_specular() {
  vec3 c = lt_color();
  float s = ptm_spec(lt_normal(), ${U_PARAM.specExponent});
  return c * ${U_PARAM.specKd} + mean3(c) * ${U_PARAM.specKs} * 2.0 * s;
}
vec3 lt_diffuse_gain() {
  vec2 n = lt_normal().xy;
  float g = ${U_PARAM.diffuseGain};
  vec3 c;
  for (int ch = 0; ch < 3; ch++) {
    vec3 p2, q2;
    ptm_gain(lanterna_plane(2 * ch), lanterna_plane(2 * ch + 1), n, g, p2, q2);
    c[ch] = ptm_eval(p2, q2);
  }
  return c * ${I};
}
vec3 lt_unsharp_q() { return lt_color(); }
vec3 lt_unsharp(vec3 q, vec3 qbar) { return q + ${U_PARAM.umGain} * (q - qbar); }
`;

/** Layer functions of a PTM program (lrgb or rgb). */
export function ptmFragmentBody(colorspace: 'lrgb' | 'rgb'): string {
  return PTM_COMMON + (colorspace === 'lrgb' ? PTM_LRGB : PTM_RGB);
}

