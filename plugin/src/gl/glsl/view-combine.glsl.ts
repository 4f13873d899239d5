/**
 * The combine stage of `unsharpNormals` as one full-screen pass over what the quantity stage kept
 * for the view (`docs/rendering.md`, "What is kept while the light moves"): per device pixel the
 * filtered `(F(n·a), F(a))`, the normal `(n, a)` and the albedo `(ρ, a)` of the layer as its tiles
 * drew them. Only the light and the combine's parameters are read per frame, so a light drag costs
 * three texel fetches and a few operations a pixel, whatever the layer type.
 */
import { PARAM_NAMES } from '../../render/params';
import { OUT_COLOR, U_FILTERED, U_LIGHT, U_PARAM, U_VIEW_ALBEDO, U_VIEW_NORMAL } from '../uniforms';
import { COLOR_GLSL } from './color.glsl';

/** Fragment shader of the full-screen `unsharpNormals` combine (`GAMMA_ONE`: the post step for gamma 1). */
export function viewCombineFragmentShader(gammaOne: boolean): string {
  const params = PARAM_NAMES.map((n) => `uniform float ${U_PARAM[n]};`).join('\n');
  const P = U_PARAM;
  return /* glsl */ `#version 300 es
#define SHADER_NAME lanterna-unsharpNormals-view-combine
#define GAMMA_ONE ${gammaOne ? 1 : 0}
precision highp float;
precision highp int;
precision highp sampler2D;
uniform sampler2D ${U_FILTERED};
uniform sampler2D ${U_VIEW_NORMAL};
uniform sampler2D ${U_VIEW_ALBEDO};
uniform vec3 ${U_LIGHT};
${params}
layout(location = 0) out vec4 ${OUT_COLOR};
${COLOR_GLSL}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 n = texelFetch(${U_VIEW_NORMAL}, p, 0);
  if (n.a == 0.0) {
    discard; // no tile of the layer here
  }
  vec4 f = texelFetch(${U_FILTERED}, p, 0);
  vec3 q = n.xyz;
  vec3 qbar = f.a > 0.0 ? f.rgb / f.a : q;
  vec3 ne = normalize(q + ${P.umGain} * (q - qbar));
  vec3 rho = texelFetch(${U_VIEW_ALBEDO}, p, 0).rgb;
  vec3 c = rho * (${P.umKd} * clamp(dot(ne, ${U_LIGHT}), 0.0, 1.0) + ${P.umEnv}) / (${P.umKd} + ${P.umEnv})
    * ${P.lightIntensity};
  ${OUT_COLOR} = vec4(lanterna_post(c), 1.0);
}
`;
}
