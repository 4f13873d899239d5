/**
 * Patch file names `L_X_Y_W_H_O_INFO.png` (docs/annotations.md "Building") and the INFO slug the
 * server gives a new patch (ASCII letters, digits and `-`, at most 40 characters; "patch" if empty).
 * Pure: no DOM.
 */
import type { PatchFrame } from './patch-frame';

/** Longest INFO slug. */
export const SLUG_MAX = 40;

/** The INFO slug of a short text: accents dropped, other characters runs → `-`, trimmed, ≤ 40 chars. */
export function infoSlug(text: string): string {
  const ascii = text.normalize('NFKD').replace(/[\u0300-\u036f]/g, '');
  const slug = ascii.replace(/[^A-Za-z0-9]+/g, '-').replace(/^-+/, '').slice(0, SLUG_MAX).replace(/-+$/, '');
  return slug || 'patch';
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
