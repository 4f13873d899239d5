/**
 * Screen-space filters of the unsharp modes (`docs/rendering.md`, "Screen-space filters"). Pure.
 */
import type { RenderMode } from './modes';

/** One separable box pass: a (2·radius + 1)-tap mean along one axis, taps clamped to the canvas. */
export interface BoxPass {
  readonly axis: 'x' | 'y';
  readonly radius: number;
}

/** A filter: `B_radius` applied `repeats` times. */
export interface BoxFilter {
  readonly radius: number;
  readonly repeats: number;
}

/** `F3 = (B_1)²`. */
export const F3: BoxFilter = { radius: 1, repeats: 2 };
/** `F5 = (B_2)⁵`. */
export const F5: BoxFilter = { radius: 2, repeats: 5 };

/** The filter an unsharp mode uses, or null for the other modes. */
export function modeFilter(mode: RenderMode): BoxFilter | null {
  switch (mode) {
    case 'unsharpCoefficients':
      return F3;
    case 'unsharpNormals':
    case 'unsharpLuminance':
    case 'unsharpImage':
      return F5;
    default:
      return null;
  }
}

/** The passes of a filter, in order: for each repeat, horizontal then vertical. */
export function boxPasses(filter: BoxFilter): BoxPass[] {
  const out: BoxPass[] = [];
  for (let i = 0; i < filter.repeats; i++) {
    out.push({ axis: 'x', radius: filter.radius }, { axis: 'y', radius: filter.radius });
  }
  return out;
}

/**
 * CPU reference of one box pass on a single-channel image (row-major, `width × height`), for tests
 * and documentation: mean over `2r+1` taps along `axis`, clamping taps to the edge.
 */
export function boxPassReference(src: Float32Array, width: number, height: number, pass: BoxPass): Float32Array {
  const out = new Float32Array(src.length);
  const n = 2 * pass.radius + 1;
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) {
      let sum = 0;
      for (let d = -pass.radius; d <= pass.radius; d++) {
        const xx = pass.axis === 'x' ? Math.min(width - 1, Math.max(0, x + d)) : x;
        const yy = pass.axis === 'y' ? Math.min(height - 1, Math.max(0, y + d)) : y;
        sum += src[yy * width + xx] ?? 0;
      }
      out[y * width + x] = sum / n;
    }
  }
  return out;
}
