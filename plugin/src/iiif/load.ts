/**
 * Fetch a manifest and the image information of each plane group of its relight layers: the
 * description the manifest embeds, else the group's `info.json`.
 */
import { FetchError, ImageInfoError, MismatchedPlanesError } from './errors';
import { commonGeometry, imageGeometry, type EmbeddedImage, type ImageGeometry } from './image-info';
import { parseManifest, type ManifestInfo, type ManifestLayer } from './manifest';

/** A layer with its plane groups' image information, ready to build a tile source. */
export interface LoadedLayer extends ManifestLayer {
  /** The info.json documents (embedded in the manifest, or fetched), in plane order. */
  readonly infos: Record<string, unknown>[];
  /** Their common tiling geometry. */
  readonly geometry: ImageGeometry;
}

/** A manifest whose default layer is loaded. */
export interface LoadedManifest extends ManifestInfo {
  /** The default (first) layer, loaded. */
  readonly first: LoadedLayer;
}

/** Time limit of a JSON request (ms). */
export const FETCH_TIMEOUT_MS = 30000;

/**
 * GET a JSON document, within `timeoutMs`.
 *
 * @throws {@link FetchError} on a network error (CORS included), an HTTP error, no answer in time
 * or invalid JSON; its message names the URL and the problem
 */
export async function fetchJson(url: string, init?: RequestInit, timeoutMs = FETCH_TIMEOUT_MS): Promise<unknown> {
  const timeout = AbortSignal.timeout(timeoutMs);
  const signal = init?.signal ? AbortSignal.any([init.signal, timeout]) : timeout;
  const timedOut = (): FetchError => new FetchError(url, 0, `no answer from ${url} within ${timeoutMs / 1000} s`);
  let response: Response;
  try {
    response = await fetch(url, { mode: 'cors', ...init, signal });
  } catch (error) {
    if (timeout.aborted) {
      throw timedOut();
    }
    throw new FetchError(url, 0, `cannot fetch ${url}: the server cannot be reached, or it does not allow `
      + `requests from this page (CORS)`, { cause: error });
  }
  if (!response.ok) {
    const reason = response.statusText ? ` ${response.statusText}` : '';
    throw new FetchError(url, response.status, `HTTP ${response.status}${reason} fetching ${url}`);
  }
  let text: string;
  try {
    text = await response.text();
  } catch (error) {
    throw timeout.aborted ? timedOut() : new FetchError(url, response.status, `cannot read ${url}: ${String(error)}`,
      { cause: error });
  }
  try {
    return JSON.parse(text) as unknown;
  } catch (error) {
    const why = error instanceof SyntaxError ? error.message : String(error);
    throw new FetchError(url, response.status, `${url} is not valid JSON (${why})`, { cause: error });
  }
}

/** info.json documents already requested, by URL (layers sharing an image fetch it once). */
export type InfoCache = Map<string, Promise<Record<string, unknown>>>;

/**
 * The info.json document at `url` (a JSON object), requested once per cache; a failed request is
 * dropped from the cache, so that asking again tries again.
 *
 * @throws {@link FetchError} or {@link ImageInfoError}
 */
export function cachedInfo(url: string, init: RequestInit | undefined, cache: InfoCache): Promise<Record<string, unknown>> {
  let pending = cache.get(url);
  if (!pending) {
    const request = fetchJson(url, init).then((info) => {
      if (typeof info !== 'object' || info === null || Array.isArray(info)) {
        throw new ImageInfoError(`${url}: not a JSON object`);
      }
      return info as Record<string, unknown>;
    });
    request.catch(() => {
      if (cache.get(url) === request) {
        cache.delete(url);
      }
    });
    cache.set(url, request);
    pending = request;
  }
  return pending;
}

/**
 * One image's information: the description its service embeds in the manifest (`embedded`), else
 * its `{serviceId}/info.json`, fetched through `cache`; `where` names it in messages.
 *
 * @throws {@link FetchError} or {@link ImageInfoError}
 */
export async function imageInfo(serviceId: string, embedded: EmbeddedImage | null, init: RequestInit | undefined,
  cache: InfoCache): Promise<EmbeddedImage> {
  if (embedded) {
    return embedded;
  }
  const url = `${serviceId}/info.json`;
  const info = await cachedInfo(url, init, cache);
  return { info, geometry: imageGeometry(info, url), where: url };
}

/**
 * The image information of every plane group of a layer ({@link imageInfo}), checked that the
 * groups share one geometry matching the relight block.
 */
export async function loadLayer(layer: ManifestLayer, init?: RequestInit, cache: InfoCache = new Map()):
  Promise<LoadedLayer> {
  const images = await Promise.all(layer.layer.planes.map((plane) => imageInfo(plane.serviceId, plane.embedded,
    init, cache)));
  const infos = images.map((image) => image.info);
  let geometry: ImageGeometry;
  try {
    geometry = commonGeometry(images.map((image) => image.geometry), layer.layer, images.map((image) => image.where));
  } catch (error) {
    if (error instanceof MismatchedPlanesError) {
      throw new MismatchedPlanesError(`layer ${layer.id}: ${error.message}`, { cause: error });
    }
    throw error;
  }
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
