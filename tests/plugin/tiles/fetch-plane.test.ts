import { afterEach, describe, expect, it, vi } from 'vitest';
import { FetchError } from '../../../plugin/src/iiif/errors';
import { fetchPlane, isTransientStatus } from '../../../plugin/src/tiles/fetch-plane';

const URL_ = 'http://example.org/iiif/a/0,0,256,256/256,256/0/default.png';
const BITMAP = { width: 256, height: 256 };

function stub(...statuses: number[]): ReturnType<typeof vi.fn> {
  const fetch = vi.fn(() => {
    const status = statuses.shift() ?? 200;
    return status === 0 ? Promise.reject(new TypeError('Failed to fetch'))
      : Promise.resolve(new Response(status === 200 ? 'png' : 'error', { status }));
  });
  vi.stubGlobal('fetch', fetch);
  vi.stubGlobal('createImageBitmap', vi.fn(() => Promise.resolve(BITMAP)));
  return fetch;
}

const options = (signal = new AbortController().signal) => ({
  credentials: 'same-origin' as const, signal, retries: 2, retryDelayMs: 1,
});

afterEach(() => {
  vi.unstubAllGlobals();
});

describe('isTransientStatus', () => {
  it('retries network errors, timeouts, rate limits and server errors only', () => {
    expect([0, 408, 429, 500, 502, 503, 504].every(isTransientStatus)).toBe(true);
    expect([200, 400, 401, 403, 404, 410].some(isTransientStatus)).toBe(false);
  });
});

describe('fetchPlane', () => {
  it('retries a transient failure and returns the decoded plane', async () => {
    const fetch = stub(503, 0, 200);
    await expect(fetchPlane(URL_, options())).resolves.toBe(BITMAP);
    expect(fetch).toHaveBeenCalledTimes(3);
  });

  it('gives up after the last retry, naming the URL and the status', async () => {
    const fetch = stub(500, 500, 500, 200);
    await expect(fetchPlane(URL_, options())).rejects.toThrow(`HTTP 500 for ${URL_}`);
    expect(fetch).toHaveBeenCalledTimes(3);
  });

  it('does not retry a missing tile', async () => {
    const fetch = stub(404, 200);
    const error = await fetchPlane(URL_, options()).catch((e: unknown) => e);
    expect(error).toBeInstanceOf(FetchError);
    expect(error).toMatchObject({ status: 404, url: URL_ });
    expect(fetch).toHaveBeenCalledTimes(1);
  });

  it('stops at once when aborted, with the abort reason', async () => {
    stub(503, 503, 503);
    const controller = new AbortController();
    const pending = fetchPlane(URL_, { ...options(controller.signal), retryDelayMs: 10000 });
    const reason = new Error('dropped');
    setTimeout(() => { controller.abort(reason); }, 5);
    await expect(pending).rejects.toBe(reason);
  });

  it('says when an answer is not an image', async () => {
    stub(200);
    vi.stubGlobal('createImageBitmap', vi.fn(() => Promise.reject(new Error('decode'))));
    await expect(fetchPlane(URL_, options())).rejects.toThrow(/is not a decodable image/);
  });
});
