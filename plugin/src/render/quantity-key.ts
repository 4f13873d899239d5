/**
 * When the filtered quantity of an unsharp mode can be kept while the light moves, and the key of
 * what it was computed from (`docs/rendering.md`, "Screen-space filters", "What is kept while the
 * light moves"). Pure: the drawer turns GL objects into numbers before asking.
 */
import type { BoxFilter } from './filter-plan';
import type { RenderMode } from './modes';

/**
 * Whether an unsharp mode's quantity (the `quantity()` of the shaders, what the box passes filter)
 * reads the light: `always`, `lit` (only on layers the light changes) or `never`. The light here
 * includes `lightIntensity`, which the relit quantities multiply in. No quantity reads any other
 * parameter: `umGain`, `umKd` and `umEnv` are read by the combine stage only.
 */
const QUANTITY_READS_LIGHT: Readonly<Partial<Record<RenderMode, 'always' | 'lit' | 'never'>>> = {
  unsharpNormals: 'never', // n
  unsharpCoefficients: 'always', // the relit L (PTM lrgb) or the unclamped relit c
  unsharpLuminance: 'always', // the relit L
  unsharpImage: 'lit', // Y = luma(clamp01(c)): the colour mode's c, unlit on image layers
};

/**
 * Can the filtered quantity of `mode` on a layer (`lit`: the light changes it) be kept while the
 * light moves? False for the modes without a screen filter.
 */
export function quantityKeepsUnderLight(mode: RenderMode, lit: boolean): boolean {
  const reads = QUANTITY_READS_LIGHT[mode];
  return reads === 'never' || (reads === 'lit' && !lit);
}

/** One drawn tile as the quantity saw it: its texture's id, its placement and the valid part of its texture. */
export interface QuantityTile {
  readonly texture: number;
  readonly matrix: readonly number[];
  readonly texScale: readonly [number, number];
}

/** Everything the filtered quantity of one layer draw depends on, besides the light. */
export interface QuantityInputs {
  /** Id of the quantity program: the layer's kind and compile-time facts, the mode, the gamma variant. */
  readonly program: number;
  /** Id of the layer (its scale, bias and kind uniforms). */
  readonly layer: number;
  readonly filter: BoxFilter;
  /** The drawing buffer's size in device px. */
  readonly width: number;
  readonly height: number;
  /** Id of the planes' sampler (smoothing on or off). */
  readonly sampler: number;
  /** The tiles drawn, in drawing order (coarse level first). */
  readonly tiles: readonly QuantityTile[];
}

/**
 * The key of a filtered quantity: equal keys mean equal filtered textures. Numbers are written
 * exactly (shortest round-trip form), so any change of a matrix entry changes the key.
 */
export function quantityKey(q: QuantityInputs): string {
  const head = `p${q.program} l${q.layer} f${q.filter.radius}x${q.filter.repeats} ${q.width}x${q.height} s${q.sampler}`;
  const tiles = q.tiles.map((t) => `t${t.texture}[${t.matrix.join(',')}](${t.texScale[0]},${t.texScale[1]})`);
  return [head, ...tiles].join(' ');
}

/**
 * Is the mode combined by one full-screen pass over what its quantity stage kept for the view (the
 * normal and the albedo of each pixel, besides the filtered quantity), instead of by drawing the
 * tiles again? Only for a quantity that is always kept: `unsharpNormals`.
 */
export function combinesFromView(mode: RenderMode): boolean {
  return mode === 'unsharpNormals';
}

/** The extra outputs of a mode's quantity stage, kept for the view: `(n, 1)` and `(ρ, 1)` for {@link combinesFromView}. */
export function quantityExtras(mode: RenderMode): number {
  return combinesFromView(mode) ? 2 : 0;
}
