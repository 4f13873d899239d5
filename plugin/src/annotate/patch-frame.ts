/**
 * The patch an annotation is drawn on: from the image region in view and the level displayed at this
 * zoom, the patch's full-resolution rectangle and its pixel size at that level, following the
 * destination rule of docs/annotations.md "Building" (`x0 = floor(X/2^L)`, `x1 = ceil((X+W)/2^L)`),
 * so that the server composites the drawing without resampling. Pure: no DOM.
 */

/** A patch: its level, its rectangle in full-resolution canvas pixels and its size at the level. */
export interface PatchFrame {
  /** The level `L` (0 = full resolution). */
  readonly level: number;
  /** The rectangle `X, Y, W, H` in full-resolution canvas pixels (inside the canvas). */
  readonly x: number;
  readonly y: number;
  readonly w: number;
  readonly h: number;
  /** The destination's first level pixel, `floor(X/2^L)`, `floor(Y/2^L)`. */
  readonly x0: number;
  readonly y0: number;
  /** The drawing's size in level pixels: `x1 − x0`, `y1 − y0`. */
  readonly width: number;
  readonly height: number;
}

/** A rectangle x, y, w, h (full-resolution image pixels). */
export type Rect = readonly [number, number, number, number];

/** The level-`level` destination `[x0, y0, x1, y1]` of the full-resolution rectangle `(x, y, w, h)`. */
export function destination(level: number, x: number, y: number, w: number, h: number): [number, number, number, number] {
  const s = 2 ** level;
  return [Math.floor(x / s), Math.floor(y / s), Math.ceil((x + w) / s), Math.ceil((y + h) / s)];
}

/**
 * The patch at `level` covering `region` (the part of the canvas in view), for a canvas of
 * `canvasWidth × canvasHeight` px, or null when the region misses the canvas.
 *
 * The rectangle is grown outward to whole level pixels (`X` a multiple of `2^L`, `X + W` too, or the
 * canvas edge) and clipped to the canvas: so level pixel `i` of the drawing covers exactly the
 * full-resolution pixels `[(x0 + i)·2^L, (x0 + i + 1)·2^L)`, where the viewer draws level pixels.
 */
export function patchFrame(region: Rect, level: number, canvasWidth: number, canvasHeight: number): PatchFrame | null {
  if (!Number.isInteger(level) || level < 0) {
    throw new RangeError(`the level must be a whole number ≥ 0, not ${level}`);
  }
  const s = 2 ** level;
  const [rx, ry, rw, rh] = region;
  const x = Math.max(0, Math.floor(rx / s) * s);
  const y = Math.max(0, Math.floor(ry / s) * s);
  const xEnd = Math.min(canvasWidth, Math.ceil((rx + rw) / s) * s);
  const yEnd = Math.min(canvasHeight, Math.ceil((ry + rh) / s) * s);
  if (!(xEnd > x && yEnd > y)) {
    return null;
  }
  const [x0, y0, x1, y1] = destination(level, x, y, xEnd - x, yEnd - y);
  return { level, x, y, w: xEnd - x, h: yEnd - y, x0, y0, width: x1 - x0, height: y1 - y0 };
}

/**
 * Where the drawing lies in full-resolution pixels: its level pixels times `2^L` (at the canvas's
 * right or bottom edge this overhangs the canvas by under `2^L` px, as the viewer's level images do).
 */
export function frameImageRect(frame: PatchFrame): Rect {
  const s = 2 ** frame.level;
  return [frame.x0 * s, frame.y0 * s, frame.width * s, frame.height * s];
}

/**
 * `rect` (full-resolution image px) in CSS px of a viewer element `elementWidth × elementHeight`
 * whose whole area shows the image region `view` (unrotated).
 */
export function rectOnScreen(rect: Rect, view: Rect, elementWidth: number, elementHeight: number): Rect {
  const sx = elementWidth / view[2];
  const sy = elementHeight / view[3];
  return [(rect[0] - view[0]) * sx, (rect[1] - view[1]) * sy, rect[2] * sx, rect[3] * sy];
}

/** The point (x, y) in CSS px of an element showing `frame`'s drawing at `rect` (CSS px) in drawing pixels. */
export function toDrawing(frame: PatchFrame, rect: Rect, x: number, y: number): [number, number] {
  return [((x - rect[0]) / rect[2]) * frame.width, ((y - rect[1]) / rect[3]) * frame.height];
}
