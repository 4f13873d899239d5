/**
 * Mirador's viewport ↔ the Lanterna view. Pure.
 *
 * Mirador keeps `viewers[windowId] = {x, y, zoom}` in canvas pixels: the centre of the view, and
 * zoom = 1 / (the view's width in canvas pixels) (its OpenSeadragon world is the canvas). Lanterna's
 * view is the image rectangle (x, y, w, h in image pixels) the viewer shows, not clipped to the image.
 * The image covers the canvas, so a canvas pixel is (image width / canvas width) image pixels across.
 */
import type { MiradorViewport } from './types';

/** A width and height in pixels. */
export interface Size {
  readonly width: number;
  readonly height: number;
}

/** An image rectangle: x, y, width, height in image pixels. */
export type ImageRect = readonly [number, number, number, number];

/** Whether a Mirador viewport has a usable centre and zoom (not yet set, or NaN from a zoom of nothing). */
export function isViewport(v: Partial<MiradorViewport> | null | undefined): v is MiradorViewport {
  return !!v && Number.isFinite(v.x) && Number.isFinite(v.y) && typeof v.zoom === 'number'
    && Number.isFinite(v.zoom) && v.zoom > 0;
}

/**
 * The image rectangle Lanterna shows for a Mirador viewport, in a viewer of this aspect ratio
 * (width / height of its element).
 */
export function viewportToImageRect(v: MiradorViewport, canvas: Size, image: Size, aspect: number): ImageRect {
  const sx = image.width / canvas.width;
  const sy = image.height / canvas.height;
  const w = 1 / v.zoom;
  const h = w / aspect;
  return [(v.x - w / 2) * sx, (v.y - h / 2) * sy, w * sx, h * sy];
}

/** The Mirador viewport of the image rectangle the Lanterna viewer shows (its whole element). */
export function imageRectToViewport(rect: ImageRect, canvas: Size, image: Size): MiradorViewport {
  const sx = image.width / canvas.width;
  const sy = image.height / canvas.height;
  const [x, y, w, h] = rect;
  return { x: (x + w / 2) / sx, y: (y + h / 2) / sy, zoom: sx / w };
}

/**
 * Whether two viewports show the same view to within `tolerance` of the view's width (centre) and
 * of the zoom (relative): the test that stops a change from echoing back and forth.
 */
export function sameViewport(a: MiradorViewport, b: MiradorViewport, tolerance = 1e-3): boolean {
  const width = 1 / Math.max(a.zoom, b.zoom);
  return Math.abs(a.x - b.x) <= tolerance * width && Math.abs(a.y - b.y) <= tolerance * width
    && Math.abs(a.zoom - b.zoom) <= tolerance * Math.max(a.zoom, b.zoom);
}
