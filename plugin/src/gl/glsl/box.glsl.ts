/**
 * Screen-space box pass (`docs/rendering.md`, "Screen-space filters"): the mean of 2r+1 texels
 * along one axis, taps clamped to the canvas edge, on a full-screen triangle.
 */
import { OUT_COLOR, U_RADIUS, U_SOURCE, U_STEP } from '../uniforms';

/** Full-screen triangle from `gl_VertexID` (draw 3 vertices, no buffers). */
export const FULLSCREEN_VERTEX_SHADER = /* glsl */ `#version 300 es
#define SHADER_NAME lanterna-fullscreen-vertex
void main() {
  vec2 p = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
  gl_Position = vec4(p, 0.0, 1.0);
}
`;

/** One box pass over an RGBA float texture. */
export const BOX_FRAGMENT_SHADER = /* glsl */ `#version 300 es
#define SHADER_NAME lanterna-box-pass
precision highp float;
precision highp int;
precision highp sampler2D;
uniform sampler2D ${U_SOURCE};
uniform ivec2 ${U_STEP};
uniform int ${U_RADIUS};
out vec4 ${OUT_COLOR};
void main() {
  ivec2 size = textureSize(${U_SOURCE}, 0);
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 sum = vec4(0.0);
  for (int d = -${U_RADIUS}; d <= ${U_RADIUS}; d++) {
    sum += texelFetch(${U_SOURCE}, clamp(p + d * ${U_STEP}, ivec2(0), size - 1), 0);
  }
  ${OUT_COLOR} = sum / float(2 * ${U_RADIUS} + 1);
}
`;
