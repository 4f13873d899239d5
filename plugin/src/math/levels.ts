/**
 * The viewer's current level of detail (`docs/annotations.md`, "Levels"). Pure maths.
 *
 * Levels count from the home view: at home the level is the home level (the overview; see
 * {@link homeLevelOf}), and each doubling of the zoom shows the next finer level, so a level keeps the paper's
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

/** A level whose image keeps at least this many pixels on its longer side is sharp on a screen at home. */
export const HOME_SIDE = 1024;

/**
 * The screen-sized level of an image: the coarsest level whose image is still at least
 * {@link HOME_SIDE} px on its longer side (0 for images smaller than that), at most `deepest`.
 * It depends on the image alone, never on the screen, so it never changes.
 */
export function screenLevelOf(width: number, height: number, deepest: number): number {
  const side = Math.max(width, height);
  if (!(side >= HOME_SIDE) || !(deepest > 0)) {
    return 0;
  }
  return Math.min(Math.floor(deepest), Math.floor(Math.log2(side / HOME_SIDE) + LEVEL_EPSILON));
}

/**
 * The level shown at home: the coarsest of the layer's overlay levels and its screen-sized level
 * ({@link screenLevelOf}), within its pyramid. The screen-sized level makes the home level of a layer
 * with no overlay, or only fine ones, the level an annotation drawn at home gets, so a first annotation
 * drawn at some zoom shows there (a patch is always drawn at the current level, never coarser than the
 * home level, so adding one never moves the home level).
 *
 * @param overlayLevels - the levels of the layer's overlay images (any order; may be empty)
 * @param scaleFactors - the layer pyramid's scale factors (powers of two)
 * @param width - the layer's full-resolution width (px)
 * @param height - the layer's full-resolution height (px)
 */
export function homeLevelOf(overlayLevels: readonly number[], scaleFactors: readonly number[],
  width: number, height: number): number {
  const deepest = maxLevelOf(scaleFactors);
  return Math.min(deepest, Math.max(screenLevelOf(width, height, deepest), ...overlayLevels));
}

/** The coarsest level of a pyramid whose scale factors are powers of two (`log2(max factor)`). */
export function maxLevelOf(scaleFactors: readonly number[]): number {
  return scaleFactors.length === 0 ? 0 : Math.round(Math.log2(Math.max(...scaleFactors)));
}
