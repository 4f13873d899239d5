/**
 * Whole-level loading of small images: each pyramid level fetched as one whole image per plane group
 * (`full/w,h`, the level's `sizes` entry; `full/max` for full resolution) instead of its tiles.
 * Pure: no network.
 *
 * A 1024² image in 256² tiles is 16 + 4 + 1 = 21 requests per plane group (189 for an HSH9 layer,
 * 32 rounds of the 6 connections an HTTP/1.1 browser opens per host); whole levels make it at most
 * 3. The bytes and the texture memory of a level in view are the same either way; the cost is that
 * a zoomed-in view loads its whole level rather than the visible tiles, which the size limit bounds
 * ({@link DEFAULT_WHOLE_LEVEL_MAX_SIDE}).
 */
import type { ImageGeometry } from './image-info';

/**
 * Longest side (px) up to which an image loads by whole levels, by default. A 1024² level of an
 * HSH16 layer is 16 × 4 MiB = 64 MiB of RGBA textures, what a view of the whole image at full
 * resolution holds with tiles too; at 2048² a zoomed-in phone would hold 256 MiB for a corner.
 */
export const DEFAULT_WHOLE_LEVEL_MAX_SIDE = 1024;

function listsSize(info: Record<string, unknown>, width: number, height: number): boolean {
  const sizes = info.sizes;
  return Array.isArray(sizes) && sizes.some((s: unknown) => typeof s === 'object' && s !== null
    && (s as Record<string, unknown>).width === width && (s as Record<string, unknown>).height === height);
}

/** Whether `factors` are 1, 2, 4, … 2ⁿ (the levels OpenSeadragon computes from the largest). */
function powersOfTwo(factors: readonly number[]): boolean {
  return factors.every((f, k) => f === 2 ** k);
}

/** An image's plane groups tiled one tile per level. */
export interface WholeLevels {
  /** The info.json documents, each with one tile as large as the image. */
  readonly infos: Record<string, unknown>[];
  readonly geometry: ImageGeometry;
  /**
   * OpenSeadragon's coverage cut-off level (its `getClosestLevel`, by default the finest level that
   * fits one tile). OpenSeadragon loads the levels from the one the view needs down to the cut-off,
   * and loads the cut-off too when nothing covers the view yet; with one tile per level its own
   * answer would be the full resolution, loaded even for a view that needs a coarser level. With
   * a `view`, the cut-off is the level that view needs ({@link viewLevel}): the item opens with that
   * one level, one request per plane group (nothing shows until it arrives); zooming in then loads
   * only the finer level, zooming out the coarser ones. Without, it is the original tiling's
   * cut-off: the same levels as with tiles, one request each.
   */
  readonly cutoffLevel: number;
}

/** The view an item opens at: its width on screen (CSS px) and OpenSeadragon's `minPixelRatio`. */
export interface WholeLevelView {
  readonly displayWidth: number;
  readonly minPixelRatio: number;
}

/**
 * The level a view needs, numbered as OpenSeadragon does (0 = coarsest, `maxLevel` = full
 * resolution): the finest whose pixels are each at least `minPixelRatio` CSS px wide on screen
 * (OpenSeadragon's choice), else 0.
 *
 * @param displayWidth - the image's width on screen, CSS px
 * @param width - its full-resolution width, px
 */
export function viewLevel(displayWidth: number, width: number, maxLevel: number, minPixelRatio: number): number {
  for (let k = maxLevel; k > 0; k--) {
    if (displayWidth / Math.ceil(width / 2 ** (maxLevel - k)) >= minPixelRatio) {
      return k;
    }
  }
  return 0;
}

/**
 * The infos and geometry of `geometry`'s image tiled one tile per level (so OpenSeadragon asks for
 * each level as one whole image), or null when the image does not qualify: longest side over
 * `maxSide`, already one tile per level, scale factors not 1, 2, 4, …, a reduced `full/max`
 * (`maxWidth`/`maxHeight`), or a level missing from some plane group's `sizes` (its whole image
 * may not exist on a level-0 server).
 *
 * @param infos - the plane groups' info.json documents (fetched or embedded), in plane order
 * @param geometry - their common geometry
 * @param maxSide - the longest side allowed; 0 turns whole levels off
 * @param view - the view the item opens at, if known (see {@link WholeLevels.cutoffLevel})
 */
export function wholeLevelTiling(infos: readonly Record<string, unknown>[], geometry: ImageGeometry, maxSide: number,
  view?: WholeLevelView): WholeLevels | null {
  const { width, height, scaleFactors } = geometry;
  const side = Math.max(width, height);
  if (side > maxSide || (geometry.tileWidth >= width && geometry.tileHeight >= height) || !powersOfTwo(scaleFactors)) {
    return null;
  }
  const levels = scaleFactors.slice(1).map((f) => [Math.ceil(width / f), Math.ceil(height / f)] as const);
  const usable = infos.every((info) => (info.maxWidth === undefined || info.maxWidth === width)
    && (info.maxHeight === undefined || info.maxHeight === height)
    && levels.every(([w, h]) => listsSize(info, w, h)));
  if (!usable) {
    return null;
  }
  const tiles = [{ width: side, height: side, scaleFactors: [...scaleFactors] }];
  // OpenSeadragon's level k (0 = coarsest) is scale factor 2^(maxLevel − k)
  const maxLevel = scaleFactors.length - 1;
  const fits = (k: number): boolean => Math.ceil(width / 2 ** (maxLevel - k)) <= geometry.tileWidth
    && Math.ceil(height / 2 ** (maxLevel - k)) <= geometry.tileHeight;
  let cutoffLevel = 0;
  while (cutoffLevel < maxLevel && fits(cutoffLevel + 1)) {
    cutoffLevel += 1;
  }
  if (view) {
    cutoffLevel = viewLevel(view.displayWidth, width, maxLevel, view.minPixelRatio);
  }
  return {
    infos: infos.map((info) => ({ ...info, tiles })),
    geometry: { ...geometry, tileWidth: side, tileHeight: side },
    cutoffLevel,
  };
}
