/**
 * The brush width under a pointer: a pen's pressure scales it (0.5, the Pointer Events default for a
 * pressed button, gives the chosen size); mouse and touch draw at the chosen size (their `pressure`
 * is the 0.5 default, or a constant). Pure: no DOM.
 */

/** Thinnest and widest stroke of a pen, as fractions of the chosen size. */
export const PEN_RANGE: readonly [number, number] = [0.2, 2];

/** The width (drawing px) for a brush of `size` px under a pointer of `pointerType` at `pressure` (0–1). */
export function brushWidth(size: number, pointerType: string, pressure: number): number {
  if (pointerType !== 'pen' || !Number.isFinite(pressure) || pressure <= 0) {
    return size;
  }
  const f = Math.min(PEN_RANGE[1], Math.max(PEN_RANGE[0], 2 * Math.min(1, pressure)));
  return size * f;
}
