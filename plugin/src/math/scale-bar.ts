/**
 * The scale bar's length: the largest round length (1, 2 or 5 × 10^k of a unit) whose bar fits in
 * a given number of screen pixels. Pure maths: no DOM.
 */

/** A length unit of the scale bar and its size in millimetres. */
interface BarUnit {
  readonly name: string;
  readonly mm: number;
}

/** Metric units, largest first: a length is shown in the largest unit it is at least 1 of. */
const METRIC: readonly BarUnit[] = [{ name: 'm', mm: 1000 }, { name: 'cm', mm: 10 }, { name: 'mm', mm: 1 }];
const INCH: readonly BarUnit[] = [{ name: 'in', mm: 25.4 }];

/** Millimetres per unit of the physdim service's `physicalUnits`. */
export const UNIT_MM: Readonly<Record<'mm' | 'cm' | 'in', number>> = { mm: 1, cm: 10, in: 25.4 };

/** A chosen scale bar. */
export interface ScaleBar {
  /** The bar's length in its unit (e.g. 5). */
  readonly value: number;
  readonly unit: string;
  /** What the bar says, e.g. `5 cm`. */
  readonly label: string;
  /** Its on-screen length, CSS px: `length / scale × (screen px per image px)`. */
  readonly px: number;
}

/** 1, 2, 5 × 10^k at most `x` (x > 0). */
export function roundDown125(x: number): number {
  const p = 10 ** Math.floor(Math.log10(x));
  const m = x / p;
  // 1e-9 absorbs log10's rounding (log10(1000) may be 2.9999…).
  return (m + 1e-9 >= 5 ? 5 : m + 1e-9 >= 2 ? 2 : 1) * p;
}

/** Print a length without floating-point noise (0.1 + 0.2 style). */
function printNumber(v: number): string {
  return String(Number(v.toPrecision(6)));
}

/**
 * The scale bar for a canvas whose pixel is `scale` `units` (the physdim service), shown at
 * `screenPerImage` CSS px per image pixel, at most `maxPx` CSS px long; null for bad input.
 * Inches are shown in inches (1/2/5 × 10^k in), millimetres and centimetres in mm, cm or m.
 */
export function chooseScaleBar(scale: number, units: 'mm' | 'cm' | 'in', screenPerImage: number,
  maxPx: number): ScaleBar | null {
  if (!(scale > 0) || !(screenPerImage > 0) || !(maxPx > 0) || !Number.isFinite(scale * screenPerImage * maxPx)) {
    return null;
  }
  const mmPerPx = (scale * UNIT_MM[units]) / screenPerImage; // millimetres per CSS px
  const maxMm = maxPx * mmPerPx;
  const family = units === 'in' ? INCH : METRIC;
  const smallest = family[family.length - 1] ?? { name: 'mm', mm: 1 };
  const lengthMm = roundDown125(maxMm / smallest.mm) * smallest.mm;
  const unit = family.find((u) => lengthMm >= u.mm * (1 - 1e-9)) ?? smallest;
  const value = Number((lengthMm / unit.mm).toPrecision(12));
  return { value, unit: unit.name, label: `${printNumber(value)} ${unit.name}`, px: lengthMm / mmPerPx };
}
