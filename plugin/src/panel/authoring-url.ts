/**
 * Where a dataset's authoring API is, from its manifest URL (the contract of `lanterna serve`):
 * `{server}/datasets/{name}/manifest.json` → `{server}/api/` and `{server}/api/datasets/{name}/presets`.
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
  return { name: decodeURIComponent(name), api: `${server}/api/`, presets: `${server}/api/datasets/${name}/presets` };
}

/** The one-line message of a failed save: the server's `{"error": …}`, else its status. */
export function saveErrorText(status: number, body: string): string {
  let message = '';
  try {
    const doc: unknown = JSON.parse(body);
    if (typeof doc === 'object' && doc !== null && 'error' in doc && typeof doc.error === 'string') {
      message = doc.error;
    }
  } catch {
    // not JSON: the status says it
  }
  const what: Readonly<Record<number, string>> = {
    401: 'the token was not accepted', 403: 'the server does not allow saving (no token configured, or another origin)',
    404: 'the server has no such dataset', 413: 'the library is too large',
  };
  const line = (message || what[status] || `HTTP ${status}`).split('\n')[0] ?? '';
  return `Not saved (${status}): ${line}`;
}
