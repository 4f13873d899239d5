/**
 * The overlay state at a level and the placement of level images. Pure: no DOM, no OpenSeadragon.
 */
import { levelRect } from '../annotations/draw-plan';
import type { ManifestLayer } from '../iiif/manifest';
import { overlayAt, type OverlayLevel } from '../iiif/overlays';
import { sanitizeHtml } from '../ui/sanitize-html';

/** What `getOverlayState()` returns. */
export interface OverlayState {
  /** The viewer's current level (docs/annotations.md formula). */
  readonly level: number;
  /** Whether the active layer has an overlay at that level. */
  readonly available: boolean;
  /** The level's short text ('' when unavailable). */
  readonly short: string;
  /** The level's long text, sanitised HTML ('' when unavailable). */
  readonly long: string;
}

/** The width in viewport units of a level image of `level.width` px when the canvas is `canvasWidth` px (= 1 unit). */
export function overlayItemWidth(level: OverlayLevel, canvasWidth: number): number {
  // Level pixel i covers full-resolution pixels [i·2^L, (i+1)·2^L): the last column may overhang.
  return levelRect(level, canvasWidth).width;
}

/** The overlay state for a layer at a level. */
export function overlayState(layer: ManifestLayer | null, level: number): OverlayState {
  const ov = layer ? overlayAt(layer.overlays, level) : null;
  return ov ? { level, available: true, short: ov.short, long: sanitizeHtml(ov.long) }
    : { level, available: false, short: '', long: '' };
}
