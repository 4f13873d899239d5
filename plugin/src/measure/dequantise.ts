/**
 * Plane values of one pixel from its tile's bytes, dequantised as the shader's `lanterna_plane` does
 * (pure: no DOM).
 */
import type { PlaneGroup } from '../iiif/relight-service';

/** `(t − bias)·scale` with t = byte/255, rounded to float32 at each step as the GPU computes it. */
export function dequantise(byte: number, scale: number, bias: number): number {
  const f = Math.fround;
  return f(f(f(byte / 255) - f(bias)) * f(scale));
}

/** The dequantised channels of one pixel of one plane group, from its tile's RGBA bytes. */
export function groupValues(group: Pick<PlaneGroup, 'channels' | 'scale' | 'bias'>, rgba: ArrayLike<number>,
  offset: number): Record<string, number> {
  const out: Record<string, number> = {};
  group.channels.forEach((name, k) => {
    // a single-band group decodes as grey: its value is in every channel
    out[name] = dequantise(rgba[offset + (group.channels.length === 1 ? 0 : k)] ?? 0, group.scale[k] ?? 1,
      group.bias[k] ?? 0);
  });
  return out;
}
