/**
 * Shared vertex shader: a unit quad generated from `gl_VertexID` (draw 4 vertices as a triangle
 * strip, no buffers), placed by {@link U_MATRIX}; texture coordinates limited to the valid part of
 * the tile texture by {@link U_TEX_SCALE}.
 */
import { U_MATRIX, U_TEX_SCALE, V_UV } from '../uniforms';

/** GLSL ES 3.00 vertex shader source. */
export const QUAD_VERTEX_SHADER = /* glsl */ `#version 300 es
#define SHADER_NAME lanterna-quad-vertex
uniform mat3 ${U_MATRIX};
uniform vec2 ${U_TEX_SCALE};
out vec2 ${V_UV};
void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
  ${V_UV} = corner * ${U_TEX_SCALE};
  vec3 clip = ${U_MATRIX} * vec3(corner, 1.0);
  gl_Position = vec4(clip.xy, 0.0, 1.0);
}
`;
