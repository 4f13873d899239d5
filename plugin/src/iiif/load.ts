/**
 * Fetch a manifest and the `info.json` of each plane group of its relight layer.
 */
import { FetchError, ImageInfoError } from './errors';
import { commonGeometry, imageGeometry, type ImageGeometry } from './image-info';
import { parseManifest, type ManifestInfo } from './manifest';

/** A manifest with its plane groups' image information, ready to build a tile source. */
export interface LoadedLayer extends ManifestInfo {
  /** The info.json documents, in plane order. */
  readonly infos: Record<string, unknown>[];
  /** Their common tiling geometry. */
  readonly geometry: ImageGeometry;
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

/**
 * Load a manifest and the info.json of every plane group (`{service.id}/info.json`), and check
 * that the groups share one geometry matching the relight block.
 */
export async function loadRelightManifest(manifestUrl: string, init?: RequestInit): Promise<LoadedLayer> {
  const manifest = parseManifest(await fetchJson(manifestUrl, init));
  const infos = await Promise.all(manifest.layer.planes.map(async (plane) => {
    const url = `${plane.serviceId}/info.json`;
    const info = await fetchJson(url, init);
    if (typeof info !== 'object' || info === null || Array.isArray(info)) {
      throw new ImageInfoError(`${url}: not a JSON object`);
    }
    return info as Record<string, unknown>;
  }));
  const geometries = infos.map((info, i) => imageGeometry(info, manifest.layer.planes[i]?.serviceId));
  const geometry = commonGeometry(geometries, manifest.layer);
  return { ...manifest, infos, geometry };
}
