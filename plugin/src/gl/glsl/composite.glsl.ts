/**
 * Compositing shaders of the lens and the annotation overlays (`docs/annotations.md`, "Viewer"):
 * a circle mask in device pixels (`gl_FragCoord`, y up), anti-aliased over one pixel; the output is
 * premultiplied, blended with `ONE, ONE_MINUS_SRC_ALPHA` (source-over).
 */
import { OUT_COLOR, U_LENS_CIRCLE, U_MASK, U_OPACITY, U_PLANES, U_SMOOTH, U_SOURCE, U_TEX_SCALE, V_UV } from '../uniforms';

/** GLSL: `lens_inside()`, the fraction of this pixel inside the lens circle (x, y, r in device px). */
const LENS_MASK_GLSL = /* glsl */ `
uniform vec3 ${U_LENS_CIRCLE};
float lens_inside() {
  float d = length(gl_FragCoord.xy - ${U_LENS_CIRCLE}.xy);
  return clamp(${U_LENS_CIRCLE}.z - d + 0.5, 0.0, 1.0);
}
`;

/**
 * An overlay tile: the level image's RGBA (straight alpha, plane 0 of the tile's texture array),
 * premultiplied texel by texel and then filtered bilinearly ({@link U_SMOOTH} 1; 0: the nearest
 * texel), so a magnified drawing has smooth edges without dark fringes (filtering straight colour
 * would blend in the black of transparent texels). Taps are clamped to the valid part of the tile
 * ({@link U_TEX_SCALE}), like CLAMP_TO_EDGE. The result is times the mask
 * `u_mask.x + u_mask.y · inside` (everywhere (1, 0), inside the lens (0, 1), outside it (1, −1)).
 */
export const OVERLAY_FRAGMENT_SHADER = /* glsl */ `#version 300 es
#define SHADER_NAME lanterna-overlay
precision highp float;
precision highp sampler2DArray;
uniform sampler2DArray ${U_PLANES};
uniform vec2 ${U_MASK};
uniform vec2 ${U_TEX_SCALE};
uniform float ${U_SMOOTH};
in vec2 ${V_UV};
out vec4 ${OUT_COLOR};
${LENS_MASK_GLSL}
ivec2 g_last;
vec4 premultiplied(ivec2 p) {
  vec4 c = texelFetch(${U_PLANES}, ivec3(clamp(p, ivec2(0), g_last), 0), 0);
  return vec4(c.rgb * c.a, c.a);
}
void main() {
  vec2 size = vec2(textureSize(${U_PLANES}, 0).xy);
  g_last = max(ivec2(round(size * ${U_TEX_SCALE})) - 1, ivec2(0));
  vec2 t = ${V_UV} * size - 0.5;
  vec2 base = floor(t);
  vec2 f = ${U_SMOOTH} > 0.5 ? t - base : step(0.5, t - base);
  ivec2 p = ivec2(base);
  vec4 c = mix(mix(premultiplied(p), premultiplied(p + ivec2(1, 0)), f.x),
               mix(premultiplied(p + ivec2(0, 1)), premultiplied(p + ivec2(1, 1)), f.x), f.y);
  float m = ${U_MASK}.x + ${U_MASK}.y * lens_inside();
  ${OUT_COLOR} = c * m;
}
`;

/**
 * The lens layer, drawn beforehand into a canvas-sized RGBA8 target (premultiplied), composited
 * inside the circle with the lens opacity. Drawn on the full-screen triangle.
 */
export const LENS_FRAGMENT_SHADER = /* glsl */ `#version 300 es
#define SHADER_NAME lanterna-lens-composite
precision highp float;
precision highp sampler2D;
uniform sampler2D ${U_SOURCE};
uniform float ${U_OPACITY};
out vec4 ${OUT_COLOR};
${LENS_MASK_GLSL}
void main() {
  vec4 c = texelFetch(${U_SOURCE}, ivec2(gl_FragCoord.xy), 0);
  ${OUT_COLOR} = c * (lens_inside() * ${U_OPACITY});
}
`;
