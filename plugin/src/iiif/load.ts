/**
 * Fetch a manifest and the `info.json` of each plane group of its relight layers.
 */
import { FetchError, ImageInfoError } from './errors';
import { commonGeometry, imageGeometry, type ImageGeometry } from './image-info';
import { parseManifest, type ManifestInfo, type ManifestLayer } from './manifest';

/** A layer with its plane groups' image information, ready to build a tile source. */
export interface LoadedLayer extends ManifestLayer {
  /** The info.json documents, in plane order. */
  readonly infos: Record<string, unknown>[];
  /** Their common tiling geometry. */
  readonly geometry: ImageGeometry;
}

/** A manifest whose default layer is loaded. */
export interface LoadedManifest extends ManifestInfo {
  /** The default (first) layer, loaded. */
  readonly first: LoadedLayer;
}

/**
 * GET a JSON document.
 *
 * @throws {@link FetchError} on a network error, an HTTP error or invalid JSON
 */
export async function fetchJson(url: string, init?: RequestInit): Promise<unknown> {
  let response: Response;
  try {
    response = await fetch(url, { mode: 'cors', ...init });
  } catch (error) {
    throw new FetchError(url, 0, `cannot fetch ${url}: ${String(error)}`, { cause: error });
  }
  if (!response.ok) {
    throw new FetchError(url, response.status, `HTTP ${response.status} fetching ${url}`);
  }
  try {
    return await response.json();
  } catch (error) {
    throw new FetchError(url, response.status, `${url} is not valid JSON`, { cause: error });
  }
}

/** info.json documents already requested, by URL (layers sharing an image fetch it once). */
export type InfoCache = Map<string, Promise<Record<string, unknown>>>;

/**
 * Load the info.json of every plane group of a layer (`{service.id}/info.json`) and check that the
 * groups share one geometry matching the relight block.
 */
export async function loadLayer(layer: ManifestLayer, init?: RequestInit, cache: InfoCache = new Map()):
  Promise<LoadedLayer> {
  const infos = await Promise.all(layer.layer.planes.map((plane) => {
    const url = `${plane.serviceId}/info.json`;
    let pending = cache.get(url);
    if (!pending) {
      pending = fetchJson(url, init).then((info) => {
        if (typeof info !== 'object' || info === null || Array.isArray(info)) {
          throw new ImageInfoError(`${url}: not a JSON object`);
        }
        return info as Record<string, unknown>;
      });
      cache.set(url, pending);
    }
    return pending;
  }));
  const geometries = infos.map((info, i) => imageGeometry(info, layer.layer.planes[i]?.serviceId));
  const geometry = commonGeometry(geometries, layer.layer);
  return { ...layer, infos, geometry };
}

/**
 * Load a manifest and its default layer's plane information (other layers load on demand with
 * {@link loadLayer}).
 */
export async function loadRelightManifest(manifestUrl: string, init?: RequestInit, cache?: InfoCache):
  Promise<LoadedManifest> {
  const manifest = parseManifest(await fetchJson(manifestUrl, init));
  const first = await loadLayer(manifest.layers[0], init, cache);
  return { ...manifest, first };
}
