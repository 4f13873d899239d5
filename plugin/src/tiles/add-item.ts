/**
 * Add a {@link BundleTileSource} TiledImage to a viewer (layers, lens layers, overlay levels).
 */
import OpenSeadragon from 'openseadragon';
import { LanternaError } from '../errors';
import type { ImageGeometry } from '../iiif/image-info';
import { BundleTileSource } from './bundle-tile-source';

/** Options of {@link addBundleItem}. */
export interface BundleItemOptions {
  /** The info.json documents, one per plane group. */
  readonly infos: readonly Record<string, unknown>[];
  readonly geometry: ImageGeometry;
  /** Tile format per plane group. */
  readonly formats: readonly string[];
  /** Preview plane (navigator, other drawers). @default 0 */
  readonly previewIndex?: number;
  /** Width in viewport units (layers are 1 wide at x = 0). @default 1 */
  readonly width?: number;
  /** Initial opacity (0 = nothing loads). */
  readonly opacity: number;
  /** What the item is, for error messages. */
  readonly what: string;
  /** OpenSeadragon's coverage cut-off level, when the tiling's own is wrong (whole levels). */
  readonly cutoffLevel?: number;
}

/** Add the item at (0, 0); resolves with the TiledImage once OpenSeadragon has opened it. */
export function addBundleItem(viewer: OpenSeadragon.Viewer, options: BundleItemOptions): Promise<OpenSeadragon.TiledImage> {
  const source = new BundleTileSource({
    infos: options.infos,
    geometry: options.geometry,
    formats: options.formats,
    previewIndex: options.previewIndex ?? 0,
    cutoffLevel: options.cutoffLevel,
  });
  return new Promise((resolve, reject) => {
    viewer.addTiledImage({
      tileSource: source as unknown as OpenSeadragon.TileSource,
      x: 0,
      y: 0,
      width: options.width ?? 1,
      opacity: options.opacity,
      success: (event: { item: OpenSeadragon.TiledImage }) => { resolve(event.item); },
      error: (event: { message?: string }) => {
        reject(new LanternaError(`cannot open ${options.what}: ${event.message ?? 'unknown error'}`));
      },
    } as unknown as Parameters<OpenSeadragon.Viewer['addTiledImage']>[0]);
  });
}
