/**
 * Shared fragment `main()`: picks the render mode's formula at compile time (`MODE`, `STAGE`) from
 * the functions a layer shader defines (`docs/rendering.md`, "Modes and where they apply").
 *
 * A layer shader defines, for the modes it supports: `lt_color()` (the colour-mode c, before post),
 * `lt_normal()`, `lt_albedo()`, `lt_diffuse()`, `lt_achromatic()`, `lt_specular()`,
 * `lt_diffuse_gain()`, and for `unsharpCoefficients`/`unsharpLuminance` `lt_unsharp_q()` (the
 * filtered quantity) and `lt_unsharp(q, qbar)`. A kind whose quantity is a weighted sum (by the
 * light) of two vec3 groups of terms defines `UNSHARP_TERMS 2`, `lt_unsharp_terms(t0, t1)` and
 * `lt_unsharp_from_terms(t0, t1)`: the terms are filtered instead, once per view
 * (`TERMS_QUANTITY`), and q̄ is the quantity of the filtered terms.
 *
 * Stages: `STAGE_DIRECT` draws the mode; for the unsharp modes `STAGE_QUANTITY` writes `(q, 1)` into
 * a float framebuffer (coverage a = 1 where drawn) and `STAGE_COMBINE` reads the box-filtered
 * `(F(q·a), F(a))` at the same device pixel and combines. `unsharpNormals` has no `STAGE_COMBINE`:
 * its quantity stage also writes `(n, 1)` and `(ρ, 1)` to outputs 1 and 2, kept for the view, and
 * a full-screen pass combines them with the light (`view-combine.glsl.ts`).
 */
import { RENDER_MODES } from '../../render/modes';
import { OUT_COLOR, OUT_TERMS_1, OUT_VIEW_ALBEDO, OUT_VIEW_NORMAL, U_FILTERED, U_FILTERED_1, U_PARAM } from '../uniforms';

/** Shader stages. */
export const STAGE = { direct: 0, quantity: 1, combine: 2 } as const;
/** A shader stage name. */
export type Stage = keyof typeof STAGE;

/** `#define MODE_<name> <index>` for every mode, and the stage constants. */
export const MODE_DEFINES: Readonly<Record<string, number>> = {
  ...Object.fromEntries(RENDER_MODES.map((m, i) => [`MODE_${m}`, i])),
  STAGE_DIRECT: STAGE.direct,
  STAGE_QUANTITY: STAGE.quantity,
  STAGE_COMBINE: STAGE.combine,
};

/** GLSL source of `main()`; needs the prelude, {@link COLOR_GLSL} and the layer's functions before it. */
export const MODES_MAIN_GLSL = /* glsl */ `
#if STAGE != STAGE_DIRECT
uniform sampler2D ${U_FILTERED};
#endif
#if STAGE != STAGE_DIRECT && defined(UNSHARP_TERMS) && (MODE == MODE_unsharpCoefficients || MODE == MODE_unsharpLuminance)
#define TERMS_QUANTITY 1
uniform sampler2D ${U_FILTERED_1};
#if STAGE == STAGE_QUANTITY
layout(location = 1) out vec4 ${OUT_TERMS_1};
#endif
#endif
#if STAGE == STAGE_QUANTITY && MODE == MODE_unsharpNormals
layout(location = 1) out vec4 ${OUT_VIEW_NORMAL};
layout(location = 2) out vec4 ${OUT_VIEW_ALBEDO};
#endif

#if STAGE != STAGE_DIRECT
vec3 quantity() {
#if MODE == MODE_unsharpNormals
  return lt_normal();
#elif MODE == MODE_unsharpImage
  return vec3(luma(clamp01(lt_color())), 0.0, 0.0);
#else
  return lt_unsharp_q();
#endif
}
#endif

vec3 shade() {
#if MODE == MODE_color
  return lt_color();
#elif MODE == MODE_normals
  return (lt_normal() + 1.0) * 0.5;
#elif MODE == MODE_albedo
  return lt_albedo();
#elif MODE == MODE_diffuse
  return lt_diffuse();
#elif MODE == MODE_achromatic
  return lt_achromatic();
#elif MODE == MODE_specular
  return lt_specular();
#elif MODE == MODE_diffuseGain
  return lt_diffuse_gain();
#elif STAGE == STAGE_COMBINE
  vec4 f = texelFetch(${U_FILTERED}, ivec2(gl_FragCoord.xy), 0);
  vec3 q = quantity();
#ifdef TERMS_QUANTITY
  vec4 f1 = texelFetch(${U_FILTERED_1}, ivec2(gl_FragCoord.xy), 0);
  vec3 qbar = f.a > 0.0 ? lt_unsharp_from_terms(f.rgb / f.a, f1.rgb / f1.a) : q;
#else
  vec3 qbar = f.a > 0.0 ? f.rgb / f.a : q;
#endif
#if MODE == MODE_unsharpImage
  vec3 c0 = clamp01(lt_color());
  return c0 + ${U_PARAM.umGain} * (q.x - qbar.x);
#elif MODE == MODE_unsharpNormals
#error unsharpNormals is combined by the full-screen pass of view-combine.glsl.ts
#else
  return lt_unsharp(q, qbar);
#endif
#else
  return vec3(0.0);
#endif
}

void main() {
#if STAGE == STAGE_QUANTITY && defined(TERMS_QUANTITY)
  vec3 t0, t1;
  lt_unsharp_terms(t0, t1);
  ${OUT_COLOR} = vec4(t0, 1.0);
  ${OUT_TERMS_1} = vec4(t1, 1.0);
#elif STAGE == STAGE_QUANTITY
  vec3 q = quantity();
  ${OUT_COLOR} = vec4(q, 1.0);
#if MODE == MODE_unsharpNormals
  ${OUT_VIEW_NORMAL} = vec4(q, 1.0);
  ${OUT_VIEW_ALBEDO} = vec4(lt_albedo(), 1.0);
#endif
#else
  ${OUT_COLOR} = vec4(lanterna_post(shade()), 1.0);
#endif
}
`;
