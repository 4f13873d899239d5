/**
 * The one-line caption of a measurement (pure: no DOM), e.g. `kd 0.62 0.41 0.30 · ks 0.20 · α 0.15`.
 */
import type { Measurement } from './plot-of';

const n2 = (x: number): string => x.toFixed(2);

/** Three values, or one when they are equal to two decimals (a grey). */
function triple(c: readonly number[]): string {
  const parts = c.map(n2);
  return parts.every((p) => p === parts[0]) ? parts[0] ?? '' : parts.join(' ');
}

/** The caption of a measurement. */
export function measurementCaption(m: Measurement): string {
  const where = `(${m.imageX}, ${m.imageY})`;
  if (m.kind === 'brdf-slice' && m.material) {
    const { kd, ks, alpha } = m.material;
    return `kd ${triple(kd)} · ks ${triple(ks)} · α ${n2(alpha)} ${where}`;
  }
  if (m.kind === 'reflectance-disk') {
    return `light ${n2(m.light.lu)} ${n2(m.light.lv)} ${where}`;
  }
  const names = Object.keys(m.values);
  return `${names.map((k) => `${k} ${n2(m.values[k] ?? 0)}`).join(' ')} ${where}`;
}
