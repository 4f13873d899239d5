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

/** The Image API 3 context: OpenSeadragon builds Image API 3 URLs only for a document that has it. */
export const IMAGE3_CONTEXT = 'http://iiif.io/api/image/3/context.json';

/** An image whose description the manifest embeds: what its info.json would give, without a request. */
export interface EmbeddedImage {
  /** The description, completed as an info.json document (`@context`, `protocol`, `id`). */
  readonly info: Record<string, unknown>;
  readonly geometry: ImageGeometry;
  /** Where it is in the manifest, for messages. */
  readonly where: string;
}

/**
 * The description a manifest's `ImageService3` reference embeds (`docs/dataset-format.md`), or null
 * when it has none to use: not an `ImageService3`, or `width`, `height` or `tiles` absent (the
 * viewer then fetches the image's info.json). A description that is there is checked as strictly as
 * a fetched info.json.
 *
 * @param service - the service object (with a string `id`)
 * @param where - its place in the manifest, naming it in errors
 * @throws {@link ImageInfoError} a malformed description (e.g. `tiles` without `scaleFactors`)
 */
export function embeddedImage(service: Record<string, unknown>, where: string): EmbeddedImage | null {
  if (service.type !== 'ImageService3' || service.width === undefined || service.height === undefined
    || service.tiles === undefined) {
    return null;
  }
  const geometry = imageGeometry(service, where);
  const id = String(service.id).replace(/\/+$/, '');
  return {
    info: { ...service, '@context': IMAGE3_CONTEXT, protocol: 'http://iiif.io/api/image', id }, geometry, where,
  };
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
