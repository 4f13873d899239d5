/**
 * The viewer's current level of detail (`docs/annotations.md`, "Levels"). Pure maths.
 *
 * Levels count from the home view: at home the level is the overlay's coarsest level (the
 * overview), and each doubling of the zoom shows the next finer level, so a level keeps the paper's
 * meaning (level `L` drawn at `1/2^L` resolution, one octave of zoom per level) whatever the screen,
 * its pixel density or the size of the image.
 */

/** Slack added to `log2(zoom / homeZoom)` so that exact powers of two are not lost to rounding (4× → 2 levels finer). */
export const LEVEL_EPSILON = 1e-6;

/** What the current level depends on. */
export interface LevelView {
  /** The viewport zoom now (OpenSeadragon viewport zoom, any unit shared with `homeZoom`). */
  readonly zoom: number;
  /** The zoom of the home view (the whole object in view). */
  readonly homeZoom: number;
  /** The level shown at home and when zoomed out further: the coarsest level (≥ 0), see {@link homeLevelOf}. */
  readonly homeLevel: number;
}

/**
 * The current level: `clamp(homeLevel − floor(log2(zoom / homeZoom) + 1e-6), 0, homeLevel)`.
 *
 * @returns `homeLevel` at home (and zoomed out), one less at 2× the home zoom, … 0 at
 * `2^homeLevel`× and beyond; `homeLevel` when the zoom or the home zoom is not a positive number
 */
export function currentLevel(view: LevelView): number {
  const top = Number.isFinite(view.homeLevel) ? Math.max(0, Math.floor(view.homeLevel)) : 0;
  const ratio = view.zoom / view.homeZoom;
  if (Number.isNaN(ratio) || ratio <= 0 || !(view.homeZoom > 0)) {
    return top;
  }
  if (ratio === Infinity) {
    return 0;
  }
  const finer = Math.floor(Math.log2(ratio) + LEVEL_EPSILON);
  return Math.min(top, Math.max(0, top - finer));
}

/**
 * The level shown at home: the coarsest level that has an overlay image, or, for a layer without
 * an overlay, the coarsest level of its pyramid.
 *
 * @param overlayLevels - the levels of the layer's overlay images (any order; may be empty)
 * @param scaleFactors - the layer pyramid's scale factors (powers of two)
 */
export function homeLevelOf(overlayLevels: readonly number[], scaleFactors: readonly number[]): number {
  return overlayLevels.length > 0 ? Math.max(0, ...overlayLevels) : maxLevelOf(scaleFactors);
}

/** The coarsest level of a pyramid whose scale factors are powers of two (`log2(max factor)`). */
export function maxLevelOf(scaleFactors: readonly number[]): number {
  return scaleFactors.length === 0 ? 0 : Math.round(Math.log2(Math.max(...scaleFactors)));
}
