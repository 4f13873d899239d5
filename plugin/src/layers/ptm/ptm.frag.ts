/**
 * PTM fragment shaders (contract `layerType: "ptm"`): basis weights come in as two vec3 uniforms
 * (`[lu², lv², lu·lv]`, `[lu, lv, 1]`), computed on the CPU by `ptmWeights`.
 */
import { planesPrelude } from '../../gl/glsl/planes.glsl';
import { OUT_COLOR, U_WEIGHTS } from '../../gl/uniforms';

/** lrgb: planes 0–1 hold L0…L5, plane 2 holds R,G,B; output `clamp(RGB · Σ L_k w_k)`. */
export const PTM_LRGB_FRAGMENT_SHADER = `${planesPrelude('lanterna-ptm-lrgb')}
uniform vec3 ${U_WEIGHTS}[2];
void main() {
  float lum = dot(lanterna_plane(0), ${U_WEIGHTS}[0]) + dot(lanterna_plane(1), ${U_WEIGHTS}[1]);
  vec3 rgb = clamp(lanterna_plane(2) * lum, 0.0, 1.0);
  ${OUT_COLOR} = vec4(rgb, 1.0);
}
`;

/** rgb: planes 2c and 2c+1 hold channel c's six coefficients; output `clamp(Σ c_k w_k)`. */
export const PTM_RGB_FRAGMENT_SHADER = `${planesPrelude('lanterna-ptm-rgb')}
uniform vec3 ${U_WEIGHTS}[2];
float channel(int c) {
  return dot(lanterna_plane(2 * c), ${U_WEIGHTS}[0]) + dot(lanterna_plane(2 * c + 1), ${U_WEIGHTS}[1]);
}
void main() {
  vec3 rgb = clamp(vec3(channel(0), channel(1), channel(2)), 0.0, 1.0);
  ${OUT_COLOR} = vec4(rgb, 1.0);
}
`;
