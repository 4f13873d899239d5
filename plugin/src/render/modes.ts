/**
 * Render modes: their names, menu order and labels (`docs/rendering.md`, "Modes and where they
 * apply"; which layers each applies to is in the layer kinds, `layers/layer-kinds.ts`). Pure.
 */

/** Every render mode, in menu order. */
export const RENDER_MODES = [
  'color', 'normals', 'albedo', 'diffuse', 'achromatic', 'specular', 'diffuseGain',
  'unsharpNormals', 'unsharpCoefficients', 'unsharpLuminance', 'unsharpImage',
] as const;
/** A render mode. */
export type RenderMode = (typeof RENDER_MODES)[number];

/** The default render mode. */
export const DEFAULT_RENDER_MODE: RenderMode = 'color';

/**
 * How a layer shades, i.e. which column of the contract's table applies: `flat` is an image layer
 * or an svbrdf layer without a normal map.
 */
export type ShadingClass = 'ptm-lrgb' | 'ptm-rgb' | 'hsh' | 'sh' | 'rbf' | 'bilinear' | 'svbrdf' | 'flat';

/** Human-readable mode names for menus. */
export const MODE_LABELS: Readonly<Record<RenderMode, string>> = {
  color: 'Colour',
  normals: 'Normals',
  albedo: 'Albedo',
  diffuse: 'Diffuse',
  achromatic: 'Achromatic',
  specular: 'Specular enhancement',
  diffuseGain: 'Diffuse gain',
  unsharpNormals: 'Unsharp normals',
  unsharpCoefficients: 'Unsharp coefficients',
  unsharpLuminance: 'Unsharp luminance',
  unsharpImage: 'Unsharp image',
};

/** Is `x` a render mode name? */
export function isRenderMode(x: unknown): x is RenderMode {
  return typeof x === 'string' && (RENDER_MODES as readonly string[]).includes(x);
}

/** Is the mode one of the screen-space unsharp-masking modes? */
export function isUnsharpMode(mode: RenderMode): boolean {
  return mode.startsWith('unsharp');
}
