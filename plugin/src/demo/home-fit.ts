/**
 * Home in the free part of the viewer: the area the toolbar and the panel leave uncovered, and the
 * image region that, fitted to the whole viewer, shows the whole object inside that area. Pure.
 */

/** A rectangle in CSS px of the viewer element: left, top, right, bottom edges. */
export interface Box {
  readonly left: number;
  readonly top: number;
  readonly right: number;
  readonly bottom: number;
}

/** Below this size (CSS px) a free area is not used: the whole viewer is. */
const MIN_FREE = 80;

const area = (b: Box): number => Math.max(0, b.right - b.left) * Math.max(0, b.bottom - b.top);

/**
 * The free area of a `width × height` viewer: below the `toolbar` (if any), and beside or above the
 * `panel` (if any), whichever leaves more room.
 */
export function freeArea(width: number, height: number, toolbar: Box | null, panel: Box | null): Box {
  let free: Box = { left: 0, top: 0, right: width, bottom: height };
  if (toolbar && toolbar.bottom < height - MIN_FREE) {
    free = { ...free, top: Math.max(0, toolbar.bottom) };
  }
  if (panel) {
    const candidates: Box[] = [
      { ...free, right: Math.min(free.right, panel.left) }, // left of the panel
      { ...free, bottom: Math.min(free.bottom, panel.top) }, // above the panel (a bottom sheet)
    ].filter((b) => b.right - b.left >= MIN_FREE && b.bottom - b.top >= MIN_FREE);
    const best = candidates.sort((a, b) => area(b) - area(a))[0];
    free = best ?? free;
  }
  return free;
}

/**
 * The region (x, y, w, h in image px) to fit to the whole `width × height` viewer so that the
 * `imageWidth × imageHeight` image fills `free` as far as it can, centred in it.
 */
export function homeRegion(width: number, height: number, free: Box, imageWidth: number,
  imageHeight: number): [number, number, number, number] {
  const fw = free.right - free.left;
  const fh = free.bottom - free.top;
  const s = Math.min(fw / imageWidth, fh / imageHeight); // CSS px per image px
  return [
    imageWidth / 2 - (free.left + fw / 2) / s,
    imageHeight / 2 - (free.top + fh / 2) / s,
    width / s,
    height / s,
  ];
}
