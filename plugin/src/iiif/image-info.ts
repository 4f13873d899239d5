/**
 * IIIF Image API 3 `info.json` checks for the plane groups of one layer. Pure: no network.
 */
import { ImageInfoError, MismatchedPlanesError } from './errors';

/** The tiling geometry of one IIIF image. */
export interface ImageGeometry {
  readonly width: number;
  readonly height: number;
  readonly tileWidth: number;
  readonly tileHeight: number;
  /** Scale factors, ascending. */
  readonly scaleFactors: readonly number[];
}

function isRecord(x: unknown): x is Record<string, unknown> {
  return typeof x === 'object' && x !== null && !Array.isArray(x);
}

/**
 * Read the tiling geometry of an `info.json` document.
 *
 * @throws {@link ImageInfoError} when width, height or a single `tiles` entry is missing
 */
export function imageGeometry(info: unknown, url = 'info.json'): ImageGeometry {
  if (!isRecord(info)) {
    throw new ImageInfoError(`${url}: not a JSON object`);
  }
  const { width, height, tiles } = info;
  if (typeof width !== 'number' || typeof height !== 'number' || width <= 0 || height <= 0) {
    throw new ImageInfoError(`${url}: width and height must be positive numbers`);
  }
  if (!Array.isArray(tiles) || tiles.length !== 1 || !isRecord(tiles[0])) {
    throw new ImageInfoError(`${url}: expected exactly one "tiles" entry`);
  }
  const t = tiles[0];
  const tileWidth = t.width;
  const tileHeight = t.height ?? t.width;
  const sf = t.scaleFactors;
  if (typeof tileWidth !== 'number' || typeof tileHeight !== 'number' || !Array.isArray(sf) || sf.length === 0
    || !sf.every((s) => typeof s === 'number' && s > 0)) {
    throw new ImageInfoError(`${url}: tiles[0] needs width and scaleFactors`);
  }
  const scaleFactors = (sf as number[]).slice().sort((a, b) => a - b);
  return { width, height, tileWidth, tileHeight, scaleFactors };
}

/**
 * Check that every plane group shares one geometry, and that it matches the layer's size.
 *
 * @param geometries - one per plane group, in plane order
 * @param layerSize - the relight block's width and height
 * @param names - what to call each plane group in messages (e.g. its info.json URL)
 * @returns the common geometry
 * @throws {@link MismatchedPlanesError} on any difference
 */
export function commonGeometry(
  geometries: readonly ImageGeometry[],
  layerSize?: { width: number; height: number },
  names: readonly string[] = [],
): ImageGeometry {
  const first = geometries[0];
  if (!first) {
    throw new MismatchedPlanesError('a layer needs at least one plane group');
  }
  const describe = (g: ImageGeometry, i: number): string => `plane group ${i} (${names[i] ? `${names[i]}: ` : ''}`
    + `${g.width}×${g.height}, tiles ${g.tileWidth}×${g.tileHeight}, scale factors ${g.scaleFactors.join(',')})`;
  geometries.forEach((g, i) => {
    const same = g.width === first.width && g.height === first.height && g.tileWidth === first.tileWidth
      && g.tileHeight === first.tileHeight && g.scaleFactors.length === first.scaleFactors.length
      && g.scaleFactors.every((s, k) => s === first.scaleFactors[k]);
    if (!same) {
      throw new MismatchedPlanesError(`${describe(g, i)} differs from ${describe(first, 0)}`);
    }
  });
  if (layerSize && (layerSize.width !== first.width || layerSize.height !== first.height)) {
    throw new MismatchedPlanesError(
      `plane images are ${first.width}×${first.height} but the relight service says ${layerSize.width}×${layerSize.height}`,
    );
  }
  return first;
}
