/**
 * `measureAt`: what the measurement mode shows for the pixel under a point of the viewer
 * (docs/rendering.md, "Measurement mode"): the pixel's dequantised plane values, read back from the
 * planes, and a plot computed from them: the BRDF slice φd = 90° of a shape + material pixel, the
 * colour over the light hemisphere of a PTM or HSH pixel, the displayed colour of an image pixel.
 */
import OpenSeadragon from 'openseadragon';
import type { LanternaViewer } from '../api/viewer-api';
import type { LoadedLayer } from '../iiif/load';
import { PlanePixels } from './plane-pixels';
import { plotOf, type Measurement } from './plot-of';

/** The full-resolution image pixel under (x, y) CSS px of the viewer element, or null outside the image. */
export function imagePixelAt(lanterna: LanternaViewer, layer: LoadedLayer, x: number, y: number):
  { x: number; y: number } | null {
  // Layers are 1 wide at x = 0 in viewport units (tiles/add-item.ts).
  const p = lanterna.viewer.viewport.viewerElementToViewportCoordinates(new OpenSeadragon.Point(x, y));
  const ix = Math.floor(p.x * layer.geometry.width);
  const iy = Math.floor(p.y * layer.geometry.width);
  const inside = ix >= 0 && iy >= 0 && ix < layer.geometry.width && iy < layer.geometry.height;
  return inside ? { x: ix, y: iy } : null;
}

let sharedPixels: PlanePixels | null = null;

/**
 * Measure the active layer at (x, y) CSS px of the viewer element; null outside the image or
 * before the viewer is ready.
 *
 * @example
 * ```ts
 * const m = await measureAt(lanterna, 200, 150);
 * console.log(m?.values, m?.plot.width);
 * ```
 * @param pixels - the plane reader, whose decoded tiles are kept between measurements
 *   @default one reader shared by every call without one
 * @throws a `FetchError` when a plane tile cannot be fetched or decoded
 */
export async function measureAt(lanterna: LanternaViewer, x: number, y: number,
  pixels: PlanePixels = (sharedPixels ??= new PlanePixels())): Promise<Measurement | null> {
  const layer = lanterna.layer;
  const at = layer ? imagePixelAt(lanterna, layer, x, y) : null;
  if (!layer || !at) {
    return null;
  }
  const light = lanterna.getLight();
  const values = await pixels.valuesAt(layer, at.x, at.y);
  const { kind, plot, material } = plotOf(layer.layer, values, lanterna.getRenderParams().lightIntensity);
  return { imageX: at.x, imageY: at.y, layer: layer.id, kind, values, material, light, plot };
}
