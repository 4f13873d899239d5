/**
 * How the quantity of an unsharp mode is drawn, whether it can be kept while the light moves, and
 * the key of what it was computed from (`docs/rendering.md`, "Screen-space filters", "What is kept while the
 * light moves"). Pure: the drawer turns GL objects into numbers before asking.
 */
import type { BoxFilter } from './filter-plan';
import type { RenderMode } from './modes';

/** What a layer's kind says about its unsharp quantities. */
export interface QuantityFacts {
  /** Whether the light changes the layer's picture (`LayerKind.lit`). */
  readonly lit: boolean;
  /**
   * How many vec3 groups of light-independent terms the relit quantity of `unsharpCoefficients`
   * and `unsharpLuminance` is a weighted sum of (PTM lrgb: 2, the six luminance coefficients), 0
   * when the kind has none to offer.
   */
  readonly unsharpTerms: number;
}

/**
 * How an unsharp mode's quantity is drawn, filtered and combined: `kept` while the light moves
 * (it reads neither the light nor any parameter), into `filtered` targets that are box-filtered
 * and `extras` kept as drawn, and combined by drawing the tiles again or, `fromView`, by one
 * full-screen pass over what was kept.
 */
export interface QuantityPlan {
  readonly kept: boolean;
  readonly filtered: number;
  readonly extras: number;
  readonly fromView: boolean;
}

const RELIT: QuantityPlan = { kept: false, filtered: 1, extras: 0, fromView: false };

/**
 * The plan of each unsharp mode's quantity (the `quantity()` of the shaders). No quantity reads a
 * parameter other than `lightIntensity` (`umGain`, `umKd`, `umEnv` are read by the combine only);
 * the relit ones read the light and `lightIntensity` and are filtered again every frame.
 */
const PLANS: Readonly<Partial<Record<RenderMode, (facts: QuantityFacts) => QuantityPlan>>> = {
  // n; the combine's per-pixel inputs n and ρ are kept too
  unsharpNormals: () => ({ kept: true, filtered: 1, extras: 2, fromView: true }),
  // the relit L or c; by linearity F(Σ wₖaₖ) = Σ wₖF(aₖ), so the kind's terms can be filtered instead
  unsharpCoefficients: termsPlan,
  unsharpLuminance: termsPlan,
  // Y = luma(clamp01(c)), c the colour mode's: unlit on image layers
  unsharpImage: ({ lit }) => (lit ? RELIT : { ...RELIT, kept: true }),
};

function termsPlan({ unsharpTerms }: QuantityFacts): QuantityPlan {
  return unsharpTerms > 0 ? { kept: true, filtered: unsharpTerms, extras: 0, fromView: false } : RELIT;
}

/** The plan of `mode`'s quantity on a layer with `facts`, or null for a mode without a screen filter. */
export function quantityPlan(mode: RenderMode, facts: QuantityFacts): QuantityPlan | null {
  return PLANS[mode]?.(facts) ?? null;
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

