import { afterEach, describe, expect, it, vi } from 'vitest';
import { FetchError, ImageInfoError } from '../../../plugin/src/iiif/errors';
import { cachedInfo, fetchJson, type InfoCache } from '../../../plugin/src/iiif/load';

const URL_ = 'http://example.org/datasets/a/manifest.json';

/** Stub `fetch` with one answer per call (a Response, an error to throw, or 'hang'). */
function stubFetch(...answers: (Response | Error | 'hang')[]): ReturnType<typeof vi.fn> {
  const fetch = vi.fn((_url: string, init?: RequestInit) => {
    const answer = answers.shift() ?? new Error('no more answers');
    if (answer === 'hang') {
      return new Promise<Response>((_resolve, reject) => {
        init?.signal?.addEventListener('abort', () => { reject(init.signal?.reason as Error); });
      });
    }
    return answer instanceof Error ? Promise.reject(answer) : Promise.resolve(answer);
  });
  vi.stubGlobal('fetch', fetch);
  return fetch;
}

afterEach(() => {
  vi.unstubAllGlobals();
});

describe('fetchJson', () => {
  it('returns the parsed document', async () => {
    stubFetch(new Response('{"type": "Manifest"}'));
    await expect(fetchJson(URL_)).resolves.toEqual({ type: 'Manifest' });
  });

  it('names the URL and the status of an HTTP error', async () => {
    stubFetch(new Response('no', { status: 404, statusText: 'Not Found' }));
    const error = await fetchJson(URL_).catch((e: unknown) => e);
    expect(error).toBeInstanceOf(FetchError);
    expect(error).toMatchObject({ url: URL_, status: 404, message: `HTTP 404 Not Found fetching ${URL_}` });
  });

  it('says what a network error may be (CORS included)', async () => {
    stubFetch(new TypeError('Failed to fetch'));
    const error = await fetchJson(URL_).catch((e: unknown) => e);
    expect(error).toMatchObject({ status: 0 });
    expect((error as Error).message).toMatch(/^cannot fetch .*manifest\.json: .*\(CORS\)$/);
  });

  it('says why a document is not JSON', async () => {
    stubFetch(new Response('{"items": ['));
    const error = await fetchJson(URL_).catch((e: unknown) => e);
    expect(error).toBeInstanceOf(FetchError);
    expect((error as Error).message).toMatch(new RegExp(`^${URL_} is not valid JSON \\(.+\\)$`));
  });

  it('gives up on a server that does not answer in time', async () => {
    stubFetch('hang');
    const error = await fetchJson(URL_, undefined, 50).catch((e: unknown) => e);
    expect(error).toBeInstanceOf(FetchError);
    expect((error as Error).message).toBe(`no answer from ${URL_} within 0.05 s`);
  });
});

describe('cachedInfo', () => {
  const INFO = 'http://example.org/iiif/a/info.json';

  it('requests a document once', async () => {
    const fetch = stubFetch(new Response('{"width": 1}'));
    const cache: InfoCache = new Map();
    await cachedInfo(INFO, undefined, cache);
    await expect(cachedInfo(INFO, undefined, cache)).resolves.toEqual({ width: 1 });
    expect(fetch).toHaveBeenCalledTimes(1);
  });

  it('forgets a failed request, so that asking again tries again', async () => {
    const fetch = stubFetch(new Response('', { status: 503 }), new Response('{"width": 2}'));
    const cache: InfoCache = new Map();
    await expect(cachedInfo(INFO, undefined, cache)).rejects.toThrow(FetchError);
    await expect(cachedInfo(INFO, undefined, cache)).resolves.toEqual({ width: 2 });
    expect(fetch).toHaveBeenCalledTimes(2);
  });

  it('refuses JSON that is not an object', async () => {
    stubFetch(new Response('[1, 2]'));
    await expect(cachedInfo(INFO, undefined, new Map())).rejects.toThrow(ImageInfoError);
  });
});
