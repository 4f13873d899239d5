/**
 * Compositing shaders of the lens and the annotation overlays (`docs/annotations.md`, "Viewer"):
 * a circle mask in device pixels (`gl_FragCoord`, y up), anti-aliased over one pixel; the output is
 * premultiplied, blended with `ONE, ONE_MINUS_SRC_ALPHA` (source-over).
 */
import { OUT_COLOR, U_LENS_CIRCLE, U_MASK, U_OPACITY, U_PLANES, U_SOURCE, V_UV } from '../uniforms';

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
 * premultiplied, times the mask `u_mask.x + u_mask.y · inside` (everywhere (1, 0), inside the lens
 * (0, 1), outside it (1, −1)).
 */
export const OVERLAY_FRAGMENT_SHADER = /* glsl */ `#version 300 es
#define SHADER_NAME lanterna-overlay
precision highp float;
precision highp sampler2DArray;
uniform sampler2DArray ${U_PLANES};
uniform vec2 ${U_MASK};
in vec2 ${V_UV};
out vec4 ${OUT_COLOR};
${LENS_MASK_GLSL}
void main() {
  vec4 c = texture(${U_PLANES}, vec3(${V_UV}, 0.0));
  float m = ${U_MASK}.x + ${U_MASK}.y * lens_inside();
  ${OUT_COLOR} = vec4(c.rgb * c.a, c.a) * m;
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
