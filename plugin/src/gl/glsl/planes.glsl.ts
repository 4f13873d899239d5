/**
 * Shared fragment-shader prelude: version, defines, the plane texture array and dequantisation
 * `v = (t − bias) · scale` (t = texel / 255, as sampled from an RGBA8 texture), the light and the
 * render parameters.
 */
import { PARAM_NAMES } from '../../render/params';
import {
  MAX_PLANES, MAX_TERMS, OUT_COLOR, U_BIAS, U_HALF, U_LIGHT, U_PARAM, U_PLANES, U_SCALE, U_WEIGHTS, V_UV,
} from '../uniforms';

/**
 * Fragment shader header for a layer program: version, shader name, `#define`s, precision, inputs,
 * parameters and `lanterna_plane(k)` returning the dequantised channels of plane group `k` (a
 * single-band group decodes as grey, so all three channels hold its value).
 *
 * @param shaderName - value of `#define SHADER_NAME`, shown in GPU error messages
 * @param defines - extra `#define NAME VALUE` lines
 */
export function planesPrelude(shaderName: string, defines: Readonly<Record<string, string | number>> = {}): string {
  const lines = Object.entries(defines).map(([k, v]) => `#define ${k} ${v}`).join('\n');
  const params = PARAM_NAMES.map((n) => `uniform float ${U_PARAM[n]};`).join('\n');
  return /* glsl */ `#version 300 es
#define SHADER_NAME ${shaderName}
${lines}
precision highp float;
precision highp int;
precision highp sampler2DArray;
precision highp sampler2D;
uniform sampler2DArray ${U_PLANES};
uniform vec3 ${U_SCALE}[${MAX_PLANES}];
uniform vec3 ${U_BIAS}[${MAX_PLANES}];
uniform float ${U_WEIGHTS}[${MAX_TERMS}];
uniform vec3 ${U_LIGHT};
uniform vec3 ${U_HALF};
${params}
in vec2 ${V_UV};
layout(location = 0) out vec4 ${OUT_COLOR};

vec3 lanterna_plane(int k) {
  vec3 t = texture(${U_PLANES}, vec3(${V_UV}, float(k))).rgb;
  return (t - ${U_BIAS}[k]) * ${U_SCALE}[k];
}
`;
}
