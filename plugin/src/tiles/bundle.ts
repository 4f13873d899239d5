/**
 * The `lanternaBundle` data type: all plane images of one tile, decoded, in plane order.
 */
import OpenSeadragon from 'openseadragon';

/** OpenSeadragon data-type name of a {@link PlaneBundle}. */
export const BUNDLE_DATA_TYPE = 'lanternaBundle';

/** The decoded plane images of one tile, all the same size. */
export interface PlaneBundle {
  /** One bitmap per plane group, in the relight block's plane order. */
  readonly bitmaps: readonly ImageBitmap[];
  /** Index of the bitmap that looks like the image (for previews), e.g. the colour group. */
  readonly previewIndex: number;
  readonly width: number;
  readonly height: number;
}

let registered = false;

/**
 * Register the bundle data type with OpenSeadragon's converter (idempotent): an immutable copy
 * edge, a preview edge to `context2d` (navigator, other drawers) and a destructor closing the bitmaps.
 */
export function registerBundleType(): void {
  if (registered) {
    return;
  }
  registered = true;
  const converter = OpenSeadragon.converter;
  // Bundles are never modified in place, so a "copy" can share the bitmaps.
  converter.learn(BUNDLE_DATA_TYPE, BUNDLE_DATA_TYPE, (_tile: unknown, bundle: PlaneBundle) => bundle, 0, 1);
  converter.learn(BUNDLE_DATA_TYPE, 'context2d', (_tile: unknown, bundle: PlaneBundle) => {
    const canvas = document.createElement('canvas');
    canvas.width = bundle.width;
    canvas.height = bundle.height;
    const ctx = canvas.getContext('2d');
    const preview = bundle.bitmaps[bundle.previewIndex] ?? bundle.bitmaps[0];
    if (ctx && preview) {
      ctx.drawImage(preview, 0, 0);
    }
    return ctx;
  }, 1, 3);
  converter.learnDestroy(BUNDLE_DATA_TYPE, (bundle: PlaneBundle) => {
    for (const b of bundle.bitmaps) {
      b.close();
    }
  });
}
