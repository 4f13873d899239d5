/**
 * What a measurement plots for a pixel's dequantised plane values (pure: no DOM): the material and
 * BRDF slice φd = 90° of a shape + material pixel, the colour over the light hemisphere of a PTM,
 * HSH or PCA (rbf, bilinear) pixel, the displayed colour of an image pixel (docs/rendering.md,
 * "Measurement mode").
 */
import { svbrdfMapIndices, type LayerType, type RelightLayer } from '../iiif/relight-service';
import { brdfSlice, linearToSrgb, SLICE_SIZE, srgbToLinear } from '../math/brdf-slice';
import type { Light } from '../math/light';
import { pcaWeights, reconstruct, type PcaBasis } from '../math/pca-weights';
import { DISK_SIZE, hshColor, ptmColor, reflectanceDisk, shColor, type Rgb } from '../math/reflectance-disk';

/** What a measurement plots. */
export type MeasurementKind = 'brdf-slice' | 'reflectance-disk' | 'swatch';

/** A plot: `width·height·3` values (RGB), rows top-down. */
export interface MeasurementPlot {
  readonly width: number;
  readonly height: number;
  readonly data: Float32Array;
}

/** The linear Lambert + Ward parameters a shape + material pixel is shaded with. */
export interface Material {
  readonly kd: Rgb;
  readonly ks: Rgb;
  readonly alpha: number;
  /** The unit normal (x right, y up, z to the viewer). */
  readonly normal: Rgb;
}

/** One measurement (see {@link measureAt}). */
export interface Measurement {
  /** The image pixel (integers, full resolution; y down). */
  readonly imageX: number;
  readonly imageY: number;
  /** The layer's id. */
  readonly layer: string;
  readonly kind: MeasurementKind;
  /** The pixel's dequantised channels, by name (exactly what the shader reads). */
  readonly values: Readonly<Record<string, number>>;
  /** shape + material with a normal map: the parameters of the slice. */
  readonly material: Material | null;
  /** The light when measured (the disk's marker). */
  readonly light: Light;
  /**
   * brdf-slice: `π·f(θh, θd)` (SLICE_SIZE², column θh, row θd); reflectance-disk: the colour mode's
   * unclamped value for each light (DISK_SIZE², 0 outside the disk); swatch: the displayed colour (1×1).
   */
  readonly plot: MeasurementPlot;
}

const GROUPS = { normals: ['NX', 'NY', 'NZ'], kd: ['KD_R', 'KD_G', 'KD_B'], ks: ['KS_R', 'KS_G', 'KS_B'] } as const;
const rgbOf = (v: Readonly<Record<string, number>>, names: readonly string[]): Rgb =>
  [v[names[0] ?? ''] ?? 0, v[names[1] ?? ''] ?? 0, v[names[2] ?? ''] ?? 0];
const mapRgb = (c: Rgb, f: (x: number) => number): Rgb => [f(c[0]), f(c[1]), f(c[2])];

/**
 * The material of a shape + material pixel as the shader's `sv_material` decodes it (sRGB maps
 * decoded, the contract's defaults for missing maps), or null without a normal map.
 */
export function materialOf(layer: RelightLayer, values: Readonly<Record<string, number>>): Material | null {
  const maps = svbrdfMapIndices(layer);
  if (maps.normals < 0) {
    return null;
  }
  const raw = rgbOf(values, GROUPS.normals);
  const len = Math.hypot(...raw);
  const normal = mapRgb(raw, (x) => (len > 0 ? x / len : 0));
  if (maps.kd < 0) {
    return { kd: [0.7, 0.7, 0.7], ks: [0.15, 0.15, 0.15], alpha: 0.25, normal };
  }
  const decode = (c: Rgb): Rgb => (layer.inputColorSpace === 'srgb' ? mapRgb(c, srgbToLinear) : c);
  const [lo, hi] = layer.glossLimits;
  const ks: Rgb = maps.ks < 0 ? [0, 0, 0] : decode(rgbOf(values, GROUPS.ks));
  // as sv_material: without a ks map the gloss map is not read
  const alpha = maps.ks < 0 || maps.gloss < 0 ? (lo + hi) / 2 : lo + (values.GLOSS ?? 0) * (hi - lo);
  return { kd: decode(rgbOf(values, GROUPS.kd)), ks, alpha, normal };
}

/** The displayed colour of an image pixel, or of a shape + material pixel without a normal map. */
export function swatchOf(layer: RelightLayer, values: Readonly<Record<string, number>>): Rgb {
  if (layer.layerType === 'image') {
    return values.Y === undefined ? rgbOf(values, ['R', 'G', 'B']) : [values.Y, values.Y, values.Y];
  }
  if (svbrdfMapIndices(layer).kd < 0) {
    return mapRgb([0.7, 0.7, 0.7], linearToSrgb);
  }
  const kd = rgbOf(values, GROUPS.kd);
  return layer.inputColorSpace === 'linear' ? mapRgb(kd, linearToSrgb) : kd;
}

/** The PCA plane weights of each light of the disk, computed once per basis (the disk's lights are fixed). */
const DISK_WEIGHTS = new WeakMap<PcaBasis, Map<string, Float64Array>>();

function diskWeights(basis: PcaBasis, lu: number, lv: number): Float64Array {
  let byLight = DISK_WEIGHTS.get(basis);
  if (!byLight) {
    byLight = new Map();
    DISK_WEIGHTS.set(basis, byLight);
  }
  const key = `${lu},${lv}`;
  let w = byLight.get(key);
  if (!w) {
    w = pcaWeights(basis, lu, lv);
    byLight.set(key, w);
  }
  return w;
}

/** A pixel's colour under a light of the reflectance disk (the colour mode's unclamped `c`). */
type DiskColor = (layer: RelightLayer, values: Readonly<Record<string, number>>, intensity: number) =>
  (lu: number, lv: number) => Rgb;

/** The PCA colour mode's unclamped `c` (shader `lt_color`) from the pixel's channels `P0…`. */
const pcaColor: DiskColor = (layer, values, intensity) => {
  const basis = layer.pca;
  if (!basis) {
    throw new Error(`a ${layer.layerType} layer without its basis`); // parsePcaBlock always sets it
  }
  const r = Array.from({ length: basis.nplanes }, (_, q) => values[`P${q}`] ?? 0);
  return (lu, lv) => {
    const c = reconstruct(r, diskWeights(basis, lu, lv));
    return [c[0] * intensity, c[1] * intensity, c[2] * intensity];
  };
};

/** The layer types a measurement plots as a reflectance disk, and their colour under a light. */
const DISK_COLORS: Partial<Record<LayerType, DiskColor>> = {
  ptm: (layer, values, intensity) => (lu, lv) => ptmColor(values, layer.colorspace, lu, lv, intensity),
  hsh: (layer, values, intensity) => (lu, lv) => hshColor(values, layer.terms, lu, lv, intensity),
  sh: (layer, values, intensity) => (lu, lv) => shColor(values, layer.terms, lu, lv, intensity),
  rbf: pcaColor,
  bilinear: pcaColor,
};

/** The plot and material of a pixel's values (pure; `intensity` is `lightIntensity`). */
export function plotOf(layer: RelightLayer, values: Readonly<Record<string, number>>, intensity: number):
  { kind: MeasurementKind; plot: MeasurementPlot; material: Material | null } {
  const diskColor = DISK_COLORS[layer.layerType];
  if (diskColor) {
    return { kind: 'reflectance-disk', material: null,
      plot: { width: DISK_SIZE, height: DISK_SIZE, data: reflectanceDisk(DISK_SIZE, diskColor(layer, values, intensity)) } };
  }
  const material = layer.layerType === 'svbrdf' ? materialOf(layer, values) : null;
  if (material) {
    return { kind: 'brdf-slice', material,
      plot: { width: SLICE_SIZE, height: SLICE_SIZE, data: brdfSlice(material.kd, material.ks, material.alpha) } };
  }
  return { kind: 'swatch', material: null, plot: { width: 1, height: 1, data: Float32Array.from(swatchOf(layer, values)) } };
}
