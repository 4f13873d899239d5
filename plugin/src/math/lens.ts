/**
 * Lens geometry in CSS pixels of the viewer element. Pure maths: no DOM, no GL.
 */

/** A circle: centre (x, y) and radius, CSS px of the viewer element. */
export interface Circle {
  readonly x: number;
  readonly y: number;
  readonly radius: number;
}

/** Where a point lies relative to a lens. */
export type LensHit = 'inside' | 'border' | 'outside';

/** Half-width of the lens border band that resizes it (CSS px). */
export const LENS_BORDER_PX = 8;
/** Smallest and largest lens radius (CSS px). */
export const MIN_LENS_RADIUS = 16;
export const MAX_LENS_RADIUS = 4096;

/**
 * Classify a point: within ±`border` of the circle → `border`, closer to the centre → `inside`,
 * else `outside`.
 */
export function lensHit(lens: Circle, x: number, y: number, border = LENS_BORDER_PX): LensHit {
  const d = Math.hypot(x - lens.x, y - lens.y);
  if (Math.abs(d - lens.radius) <= border) {
    return 'border';
  }
  return d < lens.radius ? 'inside' : 'outside';
}

/** Clamp a radius to [MIN_LENS_RADIUS, MAX_LENS_RADIUS] (non-finite → the minimum). */
export function clampRadius(radius: number): number {
  return Number.isFinite(radius) ? Math.min(MAX_LENS_RADIUS, Math.max(MIN_LENS_RADIUS, radius)) : MIN_LENS_RADIUS;
}

/** The lens moved by (dx, dy). */
export function moveLens<T extends Circle>(lens: T, dx: number, dy: number): T {
  return { ...lens, x: lens.x + dx, y: lens.y + dy };
}

/** The lens resized so that its border passes through (x, y) (border drag). */
export function resizeLensTo<T extends Circle>(lens: T, x: number, y: number): T {
  return { ...lens, radius: clampRadius(Math.hypot(x - lens.x, y - lens.y)) };
}

/** The lens with its radius multiplied by `factor` (wheel, pinch). */
export function scaleLens<T extends Circle>(lens: T, factor: number): T {
  return { ...lens, radius: clampRadius(lens.radius * (Number.isFinite(factor) && factor > 0 ? factor : 1)) };
}

/** Radius factor of one wheel step (`scroll` = +1 per notch away from the user, as OpenSeadragon reports). */
export function wheelFactor(scroll: number): number {
  return Math.pow(1.1, Math.sign(scroll));
}

/**
 * A two-finger gesture applied to the lens: the centre follows the fingers' midpoint and the radius
 * scales with their distance.
 *
 * @param lens - the lens when the update's previous positions were taken
 * @param from - previous midpoint and distance of the two contacts
 * @param to - current midpoint and distance
 */
export function twoFingerLens<T extends Circle>(lens: T, from: { x: number; y: number; distance: number },
  to: { x: number; y: number; distance: number }): T {
  const factor = from.distance > 0 && to.distance > 0 ? to.distance / from.distance : 1;
  return scaleLens(moveLens(lens, to.x - from.x, to.y - from.y), factor);
}

/**
 * The lens kept inside a viewer of `width × height` CSS px: the radius at most half the short side
 * (and at least {@link MIN_LENS_RADIUS}), the centre moved the least so that the circle fits (centred
 * on an axis the viewer is too small for).
 */
export function clampLensInto<T extends Circle>(lens: T, width: number, height: number): T {
  const radius = clampRadius(Math.min(lens.radius, Math.min(width, height) / 2));
  const axis = (c: number, size: number): number =>
    size <= 2 * radius ? size / 2 : Math.min(size - radius, Math.max(radius, Number.isFinite(c) ? c : size / 2));
  return { ...lens, x: axis(lens.x, width), y: axis(lens.y, height), radius };
}

/**
 * The lens after the viewer was resized from `before` to `after` (CSS px). OpenSeadragon keeps the
 * view's centre and scale on a resize, so the lens keeps its offset from the viewer's centre (it stays
 * over the same part of the image), then is clamped into the new size ({@link clampLensInto}).
 */
export function lensAfterResize<T extends Circle>(lens: T, before: { readonly width: number; readonly height: number },
  after: { readonly width: number; readonly height: number }): T {
  const moved = moveLens(lens, (after.width - before.width) / 2, (after.height - before.height) / 2);
  return clampLensInto(moved, after.width, after.height);
}

/** The lens's bounding square `[x, y, w, h]` (CSS px). */
export function lensBounds(lens: Circle): [number, number, number, number] {
  return [lens.x - lens.radius, lens.y - lens.radius, 2 * lens.radius, 2 * lens.radius];
}

/**
 * The bounding box of points given as `[x, y]` pairs, `[x, y, w, h]`, grown by `margin` on every side
 * (e.g. the lens corners mapped to image pixels, plus one tile pixel for filtering).
 */
export function boundingBox(points: readonly (readonly [number, number])[], margin = 0): [number, number, number, number] {
  const xs = points.map((p) => p[0]);
  const ys = points.map((p) => p[1]);
  const x0 = Math.min(...xs) - margin;
  const y0 = Math.min(...ys) - margin;
  return [x0, y0, Math.max(...xs) + margin - x0, Math.max(...ys) + margin - y0];
}

/** The lens in device pixels with y up (what `gl_FragCoord` uses): centre and radius. */
export function lensInDevicePixels(lens: Circle, pixelDensityRatio: number, canvasHeight: number):
  { x: number; y: number; radius: number } {
  return {
    x: lens.x * pixelDensityRatio,
    y: canvasHeight - lens.y * pixelDensityRatio,
    radius: lens.radius * pixelDensityRatio,
  };
}
