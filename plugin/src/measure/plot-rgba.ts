/**
 * A measurement's plot as display pixels (pure: no DOM): the slice tone-mapped
 * (`toneMapSlice`: Reinhard, then sRGB), the disk and the swatch clamped to 0–1 as the colour mode
 * shows them (they already are display values), transparent outside the disk.
 */
import { toneMapSlice } from '../math/brdf-slice';
import { diskLight } from '../math/reflectance-disk';
import type { MeasurementKind, MeasurementPlot } from './plot-of';

const clamp01 = (x: number): number => Math.min(1, Math.max(0, x));

/** RGBA bytes (`width·height·4`, rows top-down) of a plot. */
export function plotRgba(kind: MeasurementKind, plot: MeasurementPlot): Uint8ClampedArray<ArrayBuffer> {
  const { width, height, data } = plot;
  const out = new Uint8ClampedArray(width * height * 4);
  const display = kind === 'brdf-slice' ? toneMapSlice : clamp01;
  for (let j = 0; j < height; j++) {
    for (let i = 0; i < width; i++) {
      const p = j * width + i;
      for (let c = 0; c < 3; c++) {
        out[p * 4 + c] = Math.round(display(data[p * 3 + c] ?? 0) * 255);
      }
      out[p * 4 + 3] = kind === 'reflectance-disk' && !diskLight(i, j, width).inside ? 0 : 255;
    }
  }
  return out;
}
