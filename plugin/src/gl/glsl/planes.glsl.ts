/**
 * Shared fragment-shader prelude: the plane texture array and dequantisation
 * `v = (t − bias) · scale` (t = texel / 255, as sampled from an RGBA8 texture).
 */
import { MAX_PLANES, OUT_COLOR, U_BIAS, U_PLANES, U_SCALE, V_UV } from '../uniforms';

/**
 * Fragment shader header for a layer program: version, shader name, precision, inputs and the
 * `lanterna_plane(k)` function returning the dequantised channels of plane group `k`.
 *
 * @param shaderName - value of `#define SHADER_NAME`, shown in GPU error messages
 */
export function planesPrelude(shaderName: string): string {
  return /* glsl */ `#version 300 es
#define SHADER_NAME ${shaderName}
precision highp float;
precision highp int;
precision highp sampler2DArray;
uniform sampler2DArray ${U_PLANES};
uniform vec3 ${U_SCALE}[${MAX_PLANES}];
uniform vec3 ${U_BIAS}[${MAX_PLANES}];
in vec2 ${V_UV};
out vec4 ${OUT_COLOR};

vec3 lanterna_plane(int k) {
  vec3 t = texture(${U_PLANES}, vec3(${V_UV}, float(k))).rgb;
  return (t - ${U_BIAS}[k]) * ${U_SCALE}[k];
}
`;
}
