/**
 * The colour of one PTM, HSH or SH pixel over the whole light hemisphere, as a disk (orthographic
 * projection of the light direction, as the light widget draws it), for the measurement mode
 * (docs/rendering.md, "Measurement mode"). Mirrors `tiler/render/measure.py`.
 *
 * Pure maths: no DOM, no GL.
 */
import { hshWeights } from './hsh-basis';
import { ptmWeights } from './ptm-basis';
import { shWeights } from './sh-basis';

/** Side of a disk (pixels). */
export const DISK_SIZE = 48;

/** An RGB colour. */
export type Rgb = readonly [number, number, number];

/**
 * The light at the centre of pixel (i, j) of a `size`² disk: `lu = 2(i + ½)/size − 1` (right),
 * `lv = 1 − 2(j + ½)/size` (up); `inside` false beyond the unit circle.
 */
export function diskLight(i: number, j: number, size: number): { lu: number; lv: number; inside: boolean } {
  const lu = (2 * (i + 0.5)) / size - 1;
  const lv = 1 - (2 * (j + 0.5)) / size;
  return { lu, lv, inside: lu * lu + lv * lv <= 1 };
}

/** The disk pixel (column, row) of the light (lu, lv) (the light marker). */
export function diskPixelOf(lu: number, lv: number, size: number): { x: number; y: number } {
  return { x: ((lu + 1) * size) / 2, y: ((1 - lv) * size) / 2 };
}

/** `size·size·3` values of `colorAt` at every disk pixel's light, rows top-down, 0 outside the disk. */
export function reflectanceDisk(size: number, colorAt: (lu: number, lv: number) => Rgb): Float32Array {
  const out = new Float32Array(size * size * 3);
  for (let j = 0; j < size; j++) {
    for (let i = 0; i < size; i++) {
      const { lu, lv, inside } = diskLight(i, j, size);
      if (inside) {
        out.set(colorAt(lu, lv), (j * size + i) * 3);
      }
    }
  }
  return out;
}

const dot = (values: Readonly<Record<string, number>>, names: readonly string[], w: ArrayLike<number>): number =>
  names.reduce((s, name, k) => s + (values[name] ?? 0) * (w[k] ?? 0), 0);
const range = (n: number, f: (k: number) => string): string[] => Array.from({ length: n }, (_, k) => f(k));

/**
 * The PTM colour mode's unclamped `c` (shader `lt_color`): lrgb `rgb·Σ L_k w_k·I`, rgb
 * `Σ a_{c,k} w_k·I`, from the pixel's dequantised channels by name (`L0…L5, R, G, B` or `R0…B5`).
 */
export function ptmColor(values: Readonly<Record<string, number>>, colorspace: 'lrgb' | 'rgb', lu: number, lv: number,
  intensity = 1): Rgb {
  const w = ptmWeights(lu, lv);
  if (colorspace === 'lrgb') {
    const l = dot(values, range(6, (k) => `L${k}`), w) * intensity;
    return [(values.R ?? 0) * l, (values.G ?? 0) * l, (values.B ?? 0) * l];
  }
  const [r, g, b] = ['R', 'G', 'B'].map((c) => dot(values, range(6, (k) => `${c}${k}`), w) * intensity);
  return [r ?? 0, g ?? 0, b ?? 0];
}

/** `c = Σ_k a_{c,k} w_k·I` from channels `R{k}, G{k}, B{k}` and the light's basis weights `w`. */
function termColor(values: Readonly<Record<string, number>>, w: ArrayLike<number>, terms: number,
  intensity: number): Rgb {
  const [r, g, b] = ['R', 'G', 'B'].map((c) => dot(values, range(terms, (k) => `${c}${k}`), w) * intensity);
  return [r ?? 0, g ?? 0, b ?? 0];
}

/** The HSH colour mode's unclamped `c = Σ_k a_{c,k} w_k·I`, from channels `R{k}, G{k}, B{k}`. */
export function hshColor(values: Readonly<Record<string, number>>, terms: number, lu: number, lv: number,
  intensity = 1): Rgb {
  return termColor(values, hshWeights(lu, lv, terms), terms, intensity);
}

/** The SH colour mode's unclamped `c = Σ_k a_{c,k} Y_k·I` (Relight's real SH), channels as HSH's. */
export function shColor(values: Readonly<Record<string, number>>, terms: number, lu: number, lv: number,
  intensity = 1): Rgb {
  return termColor(values, shWeights(lu, lv, terms), terms, intensity);
}
