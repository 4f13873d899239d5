/**
 * GLSL uniform names shared by the TypeScript side and the shader sources.
 */
import type { RenderParamName } from '../render/params';

/** mat3: unit quad → clip space. */
export const U_MATRIX = 'u_matrix';
/** vec2: fraction of the tile texture holding valid data (`sourceBounds`). */
export const U_TEX_SCALE = 'u_texScale';
/** sampler2DArray: the plane groups of one tile, one layer per group. */
export const U_PLANES = 'u_planes';
/** vec3[MAX_PLANES]: per-channel scale of each plane group (single-band groups repeat theirs). */
export const U_SCALE = 'u_scale';
/** vec3[MAX_PLANES]: per-channel bias of each plane group. */
export const U_BIAS = 'u_bias';
/** float[MAX_TERMS]: basis weights of the light (PTM: 6, HSH: 4/9/16). */
export const U_WEIGHTS = 'u_weights';
/** vec3: the unit light direction l. */
export const U_LIGHT = 'u_light';
/** vec3: the half vector h = normalize(l + v), v = (0, 0, 1). */
export const U_HALF = 'u_half';
/** float[48]: HSH weights of the three normal-estimate lights, 16 per light. */
export const U_HSH_NORMAL_WEIGHTS = 'u_hshNormalWeights';
/** mat3: inverse of the normal-estimate light matrix. */
export const U_HSH_NORMAL_INV = 'u_hshNormalInv';
/** vec3[PCA_SLOTS]: RGB plane weights W[p] of the light (PCA layers: `c = W[0] + Σ_q r_q·W[q + 1]`). */
export const U_PCA_WEIGHTS = 'u_pcaWeights';
/** vec3[PCA_SLOTS]: per plane, the r + g + b weights under the three normal-estimate lights. */
export const U_PCA_NORMAL_WEIGHTS = 'u_pcaNormalWeights';
/** vec3[PCA_SLOTS]: per plane, the sum of the three normal-estimate lights' RGB weights (albedo). */
export const U_PCA_ALBEDO_WEIGHTS = 'u_pcaAlbedoWeights';
/** vec2: svbrdf glossLimits. */
export const U_GLOSS_LIMITS = 'u_glossLimits';
/** sampler2D: the box-filtered (q·a, a) of the unsharp modes (combine stage). */
export const U_FILTERED = 'u_filtered';
/** sampler2D: the box-filtered second group of terms `(F(t₁·a), F(a))` (kinds with `UNSHARP_TERMS`). */
export const U_FILTERED_1 = 'u_filtered1';
/** Fragment output 1 of a quantity stage drawing two groups of terms. */
export const OUT_TERMS_1 = 'outTerms1';
/** sampler2D: `(n, a)` of the view, kept by the `unsharpNormals` quantity stage (output 1). */
export const U_VIEW_NORMAL = 'u_viewNormal';
/** sampler2D: `(ρ, a)` of the view, kept by the `unsharpNormals` quantity stage (output 2). */
export const U_VIEW_ALBEDO = 'u_viewAlbedo';
/** Fragment outputs 1 and 2 of the `unsharpNormals` quantity stage. */
export const OUT_VIEW_NORMAL = 'outViewNormal';
export const OUT_VIEW_ALBEDO = 'outViewAlbedo';
/** sampler2D: the input of a box pass. */
export const U_SOURCE = 'u_source';
/** ivec2: box pass direction, (1, 0) or (0, 1). */
export const U_STEP = 'u_step';
/** int: box pass radius. */
export const U_RADIUS = 'u_radius';
/** float: overlay filtering, 1 = bilinear on premultiplied colour, 0 = nearest texel. */
export const U_SMOOTH = 'u_smooth';
/** Vertex-to-fragment varying: texture coordinates. */
export const V_UV = 'v_uv';
/** Fragment output. */
export const OUT_COLOR = 'outColor';

/** float uniform of each render parameter, e.g. `u_gamma`. */
export const U_PARAM: Readonly<Record<RenderParamName, string>> = {
  lightIntensity: 'u_lightIntensity',
  gamma: 'u_gamma',
  brightness: 'u_brightness',
  specKd: 'u_specKd',
  specKs: 'u_specKs',
  specExponent: 'u_specExponent',
  diffuseGain: 'u_diffuseGain',
  umGain: 'u_umGain',
  umKd: 'u_umKd',
  umEnv: 'u_umEnv',
};

/** Largest number of plane groups one layer may have (HSH16). */
export const MAX_PLANES = 16;
/** Largest number of basis terms (HSH16). */
export const MAX_TERMS = 16;

/** vec3: the lens circle (x, y, radius) in device pixels, `gl_FragCoord` space (y up). */
export const U_LENS_CIRCLE = 'u_lensCircle';
/** vec2: overlay mask `m = u_mask.x + u_mask.y · inside` (everywhere (1, 0), inside (0, 1), outside (1, −1)). */
export const U_MASK = 'u_mask';
/** float: opacity of the lens layer over the base layer. */
export const U_OPACITY = 'u_opacity';
