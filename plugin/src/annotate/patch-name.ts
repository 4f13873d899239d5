/**
 * Patch file names `L_X_Y_W_H_O_INFO.png` (docs/annotations.md "Building") and the INFO slug the
 * server gives a new patch (ASCII letters, digits and `-`, at most 40 characters; "patch" if empty).
 * Pure: no DOM.
 */
import type { PatchFrame } from './patch-frame';

/** Longest INFO slug. */
export const SLUG_MAX = 40;

/**
 * The INFO slug of a short text, as the server makes it (`tiler/overlays/store.py` `slug`): other
 * than ASCII dropped, every run of characters other than letters, digits and `-` → `-`, dashes
 * trimmed at both ends, cut to 40 characters (and trimmed again).
 */
export function infoSlug(text: string): string {
  const trim = (t: string): string => t.replace(/^-+|-+$/g, '');
  // eslint-disable-next-line no-control-regex -- every character outside ASCII
  const ascii = text.replace(/[^\u0000-\u007f]/g, '');
  return trim(trim(ascii.replace(/[^A-Za-z0-9-]+/g, '-')).slice(0, SLUG_MAX)) || 'patch';
}

/** The patch's file name: `L_X_Y_W_H_O_INFO.png`. */
export function patchFileName(frame: Pick<PatchFrame, 'level' | 'x' | 'y' | 'w' | 'h'>, order: number,
  short: string): string {
  return `${[frame.level, frame.x, frame.y, frame.w, frame.h, order].join('_')}_${infoSlug(short)}.png`;
}

/** The order a new patch gets on top of patches with `orders`: 1 + the largest, 0 for the first. */
export function nextOrder(orders: Iterable<number>): number {
  let top: number | null = null;
  for (const o of orders) {
    top = top === null ? o : Math.max(top, o);
  }
  return top === null ? 0 : top + 1;
}
