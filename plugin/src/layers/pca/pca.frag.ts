/**
 * PCA layer functions (contract `layerType` `rbf` and `bilinear`, colour spaces mrgb and mycc,
 * docs/rendering.md), shared by both kinds: the light's sample weights, the basis and the colour
 * space are folded on the CPU (`pcaPlaneWeights`) into RGB weights per plane, so the shader only
 * sums `c = W[0] + Σ_q r_q·W[q + 1]` over the coefficients — one texture fetch per plane group
 * (`PCA_GROUPS` = ⌈N/3⌉; group g holds planes 3g, 3g + 1, 3g + 2, padding channels read 0).
 *
 * Normal and albedo come from the same coefficients relit under HSH's three normal-estimate lights
 * (fixed per layer: `U_PCA_NORMAL_WEIGHTS`, `U_PCA_ALBEDO_WEIGHTS`), in the same single pass over
 * the planes. Arrays hold `PCA_SLOTS` = 3·PCA_GROUPS + 1 vec3s (≤ 49 each for N ≤ 48).
 */
import {
  U_HALF, U_HSH_NORMAL_INV, U_PARAM, U_PCA_ALBEDO_WEIGHTS, U_PCA_NORMAL_WEIGHTS, U_PCA_WEIGHTS,
} from '../../gl/uniforms';

const I = U_PARAM.lightIntensity;

/** Most plane groups of a PCA layer (48 planes). */
const MAX_GROUPS = 16;

/**
 * `step(g)` for every plane group the layer has, unrolled at compile time (`#if PCA_GROUPS > g`):
 * constant texture layers and uniform indices (measured faster than a loop in SwiftShader).
 */
const unrolled = (step: (g: number) => string): string => Array.from({ length: MAX_GROUPS },
  (_, g) => `#if PCA_GROUPS > ${g}\n  ${step(g)}\n#endif`).join('\n');

/** Layer functions of a PCA program (needs `PCA_GROUPS` and `PCA_SLOTS`). */
export const PCA_FRAGMENT_BODY = /* glsl */ `
uniform vec3 ${U_PCA_WEIGHTS}[PCA_SLOTS];
uniform vec3 ${U_PCA_NORMAL_WEIGHTS}[PCA_SLOTS];
uniform vec3 ${U_PCA_ALBEDO_WEIGHTS}[PCA_SLOTS];
uniform mat3 ${U_HSH_NORMAL_INV};

// Σ over the coefficients of weights w: w[0] + Σ_q r_q·w[q + 1], for group g's r
#define PCA_ADD(acc, w, r, g) acc += r.x * w[3 * g + 1] + r.y * w[3 * g + 2] + r.z * w[3 * g + 3]
#define PCA_COLOR_STEP(g) { vec3 r = lanterna_plane(g); PCA_ADD(c, ${U_PCA_WEIGHTS}, r, g); }
#define PCA_SUMS_STEP(g) { vec3 r = lanterna_plane(g); PCA_ADD(c, ${U_PCA_WEIGHTS}, r, g); \\
  PCA_ADD(i3, ${U_PCA_NORMAL_WEIGHTS}, r, g); PCA_ADD(a, ${U_PCA_ALBEDO_WEIGHTS}, r, g); }

// the colour under the light (intensity 1)
vec3 pca_color() {
  vec3 c = ${U_PCA_WEIGHTS}[0];
${unrolled((g) => `PCA_COLOR_STEP(${g})`)}
  return c;
}

// one pass over the planes: the colour c, the normal lights' r + g + b (i3) and their colour sum (a)
void pca_sums(out vec3 c, out vec3 i3, out vec3 a) {
  c = ${U_PCA_WEIGHTS}[0];
  i3 = ${U_PCA_NORMAL_WEIGHTS}[0];
  a = ${U_PCA_ALBEDO_WEIGHTS}[0];
${unrolled((g) => `PCA_SUMS_STEP(${g})`)}
}

// g = M⁻¹ I, n = g/‖g‖, (0, 0, 1) when ‖g‖ < 1e-6
vec3 pca_normal_of(vec3 i3) {
  vec3 g = ${U_HSH_NORMAL_INV} * i3;
  float len = length(g);
  return len < 1e-6 ? vec3(0.0, 0.0, 1.0) : g / len;
}

// Lambertian albedo: ρ = Σ_i c(l_i) / max(Σ_i l_i·n, 0.1), Σ_i l_i = (0, 0, 3·cos 45°)
vec3 pca_albedo_of(vec3 a, vec3 n) { return a / max(2.1213203435596424 * n.z, 0.1); }

vec3 lt_color() { return pca_color() * ${I}; }
vec3 lt_normal() {
  vec3 c, i3, a;
  pca_sums(c, i3, a);
  return pca_normal_of(i3);
}
vec3 lt_albedo() {
  vec3 c, i3, a;
  pca_sums(c, i3, a);
  return pca_albedo_of(a, pca_normal_of(i3));
}
vec3 lt_diffuse() {
  vec3 c, i3, a;
  pca_sums(c, i3, a);
  vec3 n = pca_normal_of(i3);
  return lanterna_diffuse(pca_albedo_of(a, n), n);
}
vec3 lt_achromatic() { return vec3(luma(lt_color())); }
vec3 lt_specular() {
  vec3 c, i3, a;
  pca_sums(c, i3, a);
  c *= ${I};
  float s = pow(clamp(dot(pca_normal_of(i3), ${U_HALF}), 0.0, 1.0), ${U_PARAM.specExponent} / 5.0);
  return c * ${U_PARAM.specKd} + mean3(c) * ${U_PARAM.specKs} * 4.0 * s;
}
vec3 lt_unsharp_q() { return lt_color(); }
vec3 lt_unsharp(vec3 q, vec3 qbar) { return q + ${U_PARAM.umGain} * (q - qbar); }
`;
