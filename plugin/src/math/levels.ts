/**
 * The viewer's current level of detail (`docs/annotations.md`, "Levels"). Pure maths.
 */

/** Slack added to `log2(s)` so that exact powers of two are not lost to rounding (1:4 → level 2). */
export const LEVEL_EPSILON = 1e-6;

/**
 * The current level: `clamp(floor(log2(s) + 1e-6), 0, maxLevel)`.
 *
 * @param imagePxPerDevicePx - `s`, full-resolution image pixels per device pixel at the viewport centre
 * @param maxLevel - the coarsest level (≥ 0)
 * @returns 0 at 1:1 or closer, 1 at 1:2 and 1:3, 2 at 1:4, … (0 for non-finite or non-positive `s`)
 */
export function currentLevel(imagePxPerDevicePx: number, maxLevel: number): number {
  const top = Math.max(0, Math.floor(maxLevel));
  if (!Number.isFinite(imagePxPerDevicePx) || imagePxPerDevicePx <= 0) {
    return imagePxPerDevicePx === Infinity ? top : 0;
  }
  const level = Math.floor(Math.log2(imagePxPerDevicePx) + LEVEL_EPSILON);
  return Math.min(top, Math.max(0, level));
}

/**
 * `s` from OpenSeadragon's image zoom: `imageZoom` CSS px per image px (`TiledImage.viewportToImageZoom`)
 * and the device pixel ratio.
 */
export function imagePxPerDevicePx(imageZoom: number, pixelDensityRatio: number): number {
  return 1 / (imageZoom * pixelDensityRatio);
}

/** The coarsest level of a pyramid whose scale factors are powers of two (`log2(max factor)`). */
export function maxLevelOf(scaleFactors: readonly number[]): number {
  return scaleFactors.length === 0 ? 0 : Math.round(Math.log2(Math.max(...scaleFactors)));
}
