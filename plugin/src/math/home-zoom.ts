/**
 * The home view's zoom (`docs/rendering.md`, "Home view"). Pure maths.
 *
 * OpenSeadragon's home view fits the image into the viewer, which blows a small image up many
 * times (a 64×43 image fills a 1280×720 viewer at 17×). The home zoom is capped so that an image
 * pixel covers at most {@link HOME_MAX_PIXEL_RATIO} CSS px: a small image shows small and centred,
 * and can still be zoomed into up to OpenSeadragon's `maxZoomPixelRatio`.
 */

/** Most CSS px per image px at the home view. */
export const HOME_MAX_PIXEL_RATIO = 2;

/** What the home zoom depends on. */
export interface HomeZoomView {
  /** The viewport zoom that fits the image into the viewer (OpenSeadragon's own home zoom). */
  readonly fitZoom: number;
  /** CSS px of one viewport unit at zoom 1: the width of the viewer's inner area. */
  readonly containerWidth: number;
  /** Image px per viewport unit (the image's width in px over its width in viewport units). */
  readonly imagePxPerUnit: number;
  /** Most CSS px per image px. @default HOME_MAX_PIXEL_RATIO */
  readonly maxPixelRatio?: number;
}

/**
 * The home zoom: `min(fitZoom, maxPixelRatio · imagePxPerUnit / containerWidth)` (at zoom `z` an
 * image pixel covers `z · containerWidth / imagePxPerUnit` CSS px). `fitZoom` when an input is not a
 * positive number.
 */
export function homeZoom(view: HomeZoomView): number {
  const ratio = view.maxPixelRatio ?? HOME_MAX_PIXEL_RATIO;
  const cap = (ratio * view.imagePxPerUnit) / view.containerWidth;
  return cap > 0 && Number.isFinite(cap) ? Math.min(view.fitZoom, cap) : view.fitZoom;
}
