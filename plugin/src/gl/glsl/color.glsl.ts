/**
 * Shared GLSL colour helpers (`docs/rendering.md`): clamp01, luma, mean, sRGB transfer functions,
 * the post step (gamma then brightness) and the generic diffuse term.
 */
import { U_LIGHT, U_PARAM } from '../uniforms';

/** GLSL source; needs {@link planesPrelude} before it. */
export const COLOR_GLSL = /* glsl */ `
vec3 clamp01(vec3 c) { return clamp(c, 0.0, 1.0); }
float luma(vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }
float mean3(vec3 c) { return (c.r + c.g + c.b) / 3.0; }

vec3 linear_to_srgb(vec3 x) {
  vec3 lo = 12.92 * x;
  vec3 hi = 1.055 * pow(max(x, vec3(0.0031308)), vec3(1.0 / 2.4)) - 0.055;
  return mix(hi, lo, vec3(lessThanEqual(x, vec3(0.0031308))));
}

vec3 srgb_to_linear(vec3 x) {
  vec3 lo = x / 12.92;
  vec3 hi = pow(max((x + 0.055) / 1.055, vec3(0.0)), vec3(2.4));
  return mix(hi, lo, vec3(lessThanEqual(x, vec3(0.04045))));
}

// post: out = clamp01(clamp01(c)^(1/gamma) + brightness). GAMMA_ONE (compile time) skips the pow
// when gamma = 1: a CPU rasteriser runs both sides of a branch on a uniform.
vec3 lanterna_post(vec3 c) {
  c = clamp01(c);
#if !GAMMA_ONE
  c = pow(c, vec3(1.0 / ${U_PARAM.gamma}));
#endif
  return clamp01(c + ${U_PARAM.brightness});
}

// diffuse: rho · max(0, n·l) · lightIntensity
vec3 lanterna_diffuse(vec3 rho, vec3 n) {
  return rho * max(0.0, dot(n, ${U_LIGHT})) * ${U_PARAM.lightIntensity};
}
`;
