/**
 * Fetching and decoding one plane image of a bundle tile, retrying the failures that may pass
 * (network errors, HTTP 408, 429 and 5xx) a few times, with a readable error otherwise.
 */
import { FetchError } from '../iiif/errors';

/** Options of {@link fetchPlane}. */
export interface FetchPlaneOptions {
  readonly credentials: RequestCredentials;
  /** Aborts the request and any wait between attempts (the tile was dropped or timed out). */
  readonly signal: AbortSignal;
  /** Further attempts after a transient failure. */
  readonly retries: number;
  /** Wait before the first retry, doubled for each next one (ms). */
  readonly retryDelayMs: number;
}

/** True for HTTP statuses worth retrying: the same request may succeed later. */
export function isTransientStatus(status: number): boolean {
  return status === 0 || status === 408 || status === 429 || status >= 500;
}

/** Resolve after `ms`, or reject with the signal's reason as soon as it aborts. */
function wait(ms: number, signal: AbortSignal): Promise<void> {
  return new Promise((resolve, reject) => {
    const done = (): void => {
      clearTimeout(timer);
      reject(signal.reason as Error);
    };
    const timer = setTimeout(() => {
      signal.removeEventListener('abort', done);
      resolve();
    }, ms);
    signal.addEventListener('abort', done, { once: true });
  });
}

/** One attempt: the response's bytes decoded, unchanged (no premultiplication, no colour conversion). */
async function attempt(url: string, options: FetchPlaneOptions): Promise<ImageBitmap> {
  let response: Response;
  try {
    response = await fetch(url, { mode: 'cors', credentials: options.credentials, signal: options.signal });
  } catch (error) {
    if (options.signal.aborted) {
      throw options.signal.reason as Error;
    }
    throw new FetchError(url, 0, `network error for ${url} (offline, or cross-origin requests are not allowed)`,
      { cause: error });
  }
  if (!response.ok) {
    throw new FetchError(url, response.status, `HTTP ${response.status} for ${url}`);
  }
  const blob = await response.blob();
  try {
    return await createImageBitmap(blob, { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
  } catch (error) {
    // Permanent: the status is a success one, so it is not retried.
    throw new FetchError(url, response.status,
      `${url} is not a decodable image (${blob.type || 'no type'}, ${blob.size} bytes)`, { cause: error });
  }
}

/**
 * Fetch and decode one plane image.
 *
 * @throws {@link FetchError} after the last attempt, or the signal's reason once it aborts
 */
export async function fetchPlane(url: string, options: FetchPlaneOptions): Promise<ImageBitmap> {
  for (let tries = 0; ; tries++) {
    try {
      return await attempt(url, options);
    } catch (error) {
      const transient = error instanceof FetchError && isTransientStatus(error.status);
      if (options.signal.aborted || !transient || tries >= options.retries) {
        throw error;
      }
      await wait(options.retryDelayMs * 2 ** tries, options.signal);
    }
  }
}
