/**
 * Render modes and where they apply (`docs/rendering.md`, "Modes and where they apply"). Pure.
 */
import type { RelightLayer } from '../iiif/relight-service';
import { svbrdfMapIndices } from '../iiif/relight-service';

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
export type ShadingClass = 'ptm-lrgb' | 'ptm-rgb' | 'hsh' | 'svbrdf' | 'flat';

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

/** The contract's applicability table: the shading classes each mode applies to. */
export const MODE_TABLE: Readonly<Record<RenderMode, readonly ShadingClass[]>> = {
  color: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf', 'flat'],
  normals: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf'],
  albedo: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf', 'flat'],
  diffuse: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf'],
  achromatic: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf', 'flat'],
  specular: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf'],
  diffuseGain: ['ptm-lrgb', 'ptm-rgb'],
  unsharpNormals: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf'],
  unsharpCoefficients: ['ptm-lrgb', 'ptm-rgb', 'hsh'],
  unsharpLuminance: ['ptm-lrgb'],
  unsharpImage: ['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf', 'flat'],
};

/** The shading class of a layer. */
export function shadingClass(layer: Pick<RelightLayer, 'layerType' | 'colorspace' | 'planes'>): ShadingClass {
  switch (layer.layerType) {
    case 'ptm':
      return layer.colorspace === 'lrgb' ? 'ptm-lrgb' : 'ptm-rgb';
    case 'hsh':
      return 'hsh';
    case 'svbrdf':
      return svbrdfMapIndices(layer).normals >= 0 ? 'svbrdf' : 'flat';
    default:
      return 'flat';
  }
}

/** Is `x` a render mode name? */
export function isRenderMode(x: unknown): x is RenderMode {
  return typeof x === 'string' && (RENDER_MODES as readonly string[]).includes(x);
}

/** The modes that apply to a layer, in menu order. */
export function applicableModes(layer: Pick<RelightLayer, 'layerType' | 'colorspace' | 'planes'>): RenderMode[] {
  const cls = shadingClass(layer);
  return RENDER_MODES.filter((m) => MODE_TABLE[m].includes(cls));
}

/** Is the mode one of the screen-space unsharp-masking modes? */
export function isUnsharpMode(mode: RenderMode): boolean {
  return mode.startsWith('unsharp');
}
