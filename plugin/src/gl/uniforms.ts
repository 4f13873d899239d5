/**
 * GLSL uniform names shared by the TypeScript side and the shader sources.
 */

/** mat3: unit quad → clip space. */
export const U_MATRIX = 'u_matrix';
/** vec2: fraction of the tile texture holding valid data (`sourceBounds`). */
export const U_TEX_SCALE = 'u_texScale';
/** sampler2DArray: the plane groups of one tile, one layer per group. */
export const U_PLANES = 'u_planes';
/** vec3[K]: per-channel scale of each plane group. */
export const U_SCALE = 'u_scale';
/** vec3[K]: per-channel bias of each plane group. */
export const U_BIAS = 'u_bias';
/** vec3[2]: basis weights, terms 0–2 then 3–5. */
export const U_WEIGHTS = 'u_weights';
/** Vertex-to-fragment varying: texture coordinates. */
export const V_UV = 'v_uv';
/** Fragment output. */
export const OUT_COLOR = 'outColor';

/** Largest number of plane groups one layer may have (PTM rgb uses 6). */
export const MAX_PLANES = 6;
