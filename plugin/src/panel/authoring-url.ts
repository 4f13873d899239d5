/**
 * Where a dataset's authoring API is, from its manifest URL (the contract of `lanterna serve`):
 * `{server}/datasets/{name}/manifest.json` → `{server}/api/`, `{server}/api/datasets/{name}/presets` and
 * a layer's annotation endpoints `{server}/api/datasets/{name}/layers/{layer}/…` (docs/serving.md).
 * Pure: no DOM, no network.
 */

/** The authoring endpoints of a dataset. */
export interface AuthoringUrls {
  /** The dataset's name. */
  readonly name: string;
  /** `GET` → `{"authoring": true|false}`. */
  readonly api: string;
  /** `GET` / `PUT` the dataset's preset library. */
  readonly presets: string;
  /** `{server}/api/datasets/{name}`: the dataset's endpoints start here. */
  readonly dataset: string;
}

/** The annotation endpoints of one layer of a dataset. */
export interface LayerAuthoringUrls {
  /** `GET` the layer's patches, `POST` a new one (multipart `meta` + `image`). */
  readonly patches: string;
  /** `GET` the rebuild status. */
  readonly status: string;
  /** `PUT` the texts of level `level`. */
  level(level: number): string;
  /** `GET` / `PUT` / `DELETE` a patch. */
  patch(id: string): string;
}

const DATASET_MANIFEST = /^(.*)\/datasets\/([^/?#]+)\/manifest\.json(?:[?#].*)?$/;

/** The authoring endpoints for `manifestUrl` (absolute), or null if it is not a served dataset's manifest. */
export function authoringUrls(manifestUrl: string): AuthoringUrls | null {
  const m = DATASET_MANIFEST.exec(manifestUrl);
  if (!m) {
    return null;
  }
  const server = m[1] ?? '';
  const name = m[2] ?? '';
  const dataset = `${server}/api/datasets/${name}`;
  return { name: decodeURIComponent(name), api: `${server}/api/`, presets: `${dataset}/presets`, dataset };
}

/** The annotation endpoints of layer `layer` (an id) of the dataset at `urls`. */
export function layerUrls(urls: AuthoringUrls, layer: string): LayerAuthoringUrls {
  const base = `${urls.dataset}/layers/${encodeURIComponent(layer)}`;
  return {
    patches: `${base}/patches`, status: `${base}/status`,
    level: (level) => `${base}/levels/${level}`,
    patch: (id) => `${base}/patches/${encodeURIComponent(id)}`,
  };
}

/** The server's one-line `{"error": …}` of a failed request, else '' (not JSON, or no error). */
export function serverError(body: string): string {
  try {
    const doc: unknown = JSON.parse(body);
    if (typeof doc === 'object' && doc !== null && 'error' in doc && typeof doc.error === 'string') {
      return doc.error.split('\n')[0] ?? '';
    }
  } catch {
    // not JSON: the status says it
  }
  return '';
}

/** The one-line message of a failed save: the server's `{"error": …}`, else its status. */
export function saveErrorText(status: number, body: string): string {
  const what: Readonly<Record<number, string>> = {
    401: 'the token was not accepted', 403: 'the server does not allow saving (no token configured, or another origin)',
    404: 'the server has no such dataset', 413: 'the library is too large',
  };
  const line = (serverError(body) || what[status] || `HTTP ${status}`).split('\n')[0] ?? '';
  return `Not saved (${status}): ${line}`;
}
