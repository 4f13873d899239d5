import { afterEach, describe, expect, it, vi } from 'vitest';
import { ImageInfoError, MismatchedPlanesError } from '../../../plugin/src/iiif/errors';
import { IMAGE3_CONTEXT, embeddedImage } from '../../../plugin/src/iiif/image-info';
import { loadLayer } from '../../../plugin/src/iiif/load';
import { parseManifest } from '../../../plugin/src/iiif/manifest';
import { parseRelightService } from '../../../plugin/src/iiif/relight-service';
import { info, manifest, manifestWithAnnotations, overlayAnnotation, overlayPage, relightBlock } from '../fixtures';

const BASE = 'http://127.0.0.1:8000/datasets/ushabti';
const TILES = [{ width: 256, height: 256, scaleFactors: [4, 1, 2] }];

/** The description the dataset writer embeds in a service (docs/dataset-format.md). */
function description(overrides: Record<string, unknown> = {}): Record<string, unknown> {
  return {
    profile: 'level0', width: 512, height: 1024, tiles: TILES,
    sizes: [{ width: 128, height: 256 }, { width: 256, height: 512 }, { width: 512, height: 1024 }],
    preferredFormats: ['png'], extraFormats: ['png'], ...overrides,
  };
}

/** The fixture's relight block, `embed(i)` added to plane i's service. */
function blockWith(embed: (i: number) => Record<string, unknown>): Record<string, unknown> {
  const block = relightBlock();
  const planes = block.planes as { service: Record<string, unknown> }[];
  block.planes = planes.map((p, i) => ({ ...p, service: { ...p.service, ...embed(i) } }));
  return block;
}

function stubFetch(): ReturnType<typeof vi.fn> {
  const fetch = vi.fn((url: string) => Promise.resolve(new Response(JSON.stringify(info({ id: url.replace('/info.json', '') })))));
  vi.stubGlobal('fetch', fetch);
  return fetch;
}

afterEach(() => {
  vi.unstubAllGlobals();
});

describe('embedded image descriptions', () => {
  it('reads a complete description as an info.json OpenSeadragon can use', () => {
    const layer = parseRelightService(blockWith(() => description()));
    const first = layer.planes[0]?.embedded;
    expect(first?.geometry).toEqual({ width: 512, height: 1024, tileWidth: 256, tileHeight: 256, scaleFactors: [1, 2, 4] });
    expect(first?.info).toMatchObject({
      '@context': IMAGE3_CONTEXT, protocol: 'http://iiif.io/api/image', id: `${BASE}/iiif/ptm_c0`,
      type: 'ImageService3', preferredFormats: ['png'], sizes: description().sizes,
    });
    expect(layer.planes.every((p) => p.embedded !== null)).toBe(true);
  });

  it('leaves a bare or incomplete reference to be fetched', () => {
    const bare = parseRelightService(relightBlock());
    expect(bare.planes.map((p) => p.embedded)).toEqual([null, null, null]);
    const partial = parseRelightService(blockWith((i) => [
      { width: 512, height: 1024 }, { tiles: TILES }, { ...description(), type: 'ImageService2' }][i] ?? {}));
    expect(partial.planes.map((p) => p.embedded)).toEqual([null, null, null]);
  });

  it.each([
    ['tiles without scaleFactors', { tiles: [{ width: 256 }] }, 'tiles[0] needs width and scaleFactors'],
    ['two tiles entries', { tiles: [...TILES, ...TILES] }, 'expected exactly one "tiles" entry'],
    ['a width that is not a number', { width: '512' }, 'width and height must be positive numbers'],
    ['a zero height', { height: 0 }, 'width and height must be positive numbers'],
  ])('refuses a malformed description (%s), naming its place in the manifest', (_what, bad, message) => {
    const block = blockWith((i) => (i === 1 ? description(bad) : description()));
    expect(() => parseRelightService(block)).toThrow(ImageInfoError);
    expect(() => parseRelightService(block)).toThrow(`manifest: ${BASE}/layers/ptm.json planes[1].service: ${message}`);
  });

  it('is null for a service that is not an ImageService3', () => {
    expect(embeddedImage({ id: 'x', type: 'ImageService2', ...description() }, 'here')).toBeNull();
  });
});

describe('loadLayer with embedded descriptions', () => {
  const layerOf = (block: Record<string, unknown>) => {
    const m = manifest();
    const image = ((((m.items as Record<string, unknown>[])[0]?.items as Record<string, unknown>[])[0]
      ?.items as Record<string, unknown>[])[0]?.body) as Record<string, unknown>;
    image.service = [{ id: `${BASE}/iiif/ptm_color`, type: 'ImageService3', profile: 'level0' }, block];
    const layer = parseManifest(m).layers[0];
    if (!layer) {
      throw new Error('no layer');
    }
    return layer;
  };

  it('fetches no info.json when every plane group embeds its description', async () => {
    const fetch = stubFetch();
    const loaded = await loadLayer(layerOf(blockWith(() => description())));
    expect(fetch).not.toHaveBeenCalled();
    expect(loaded.geometry.scaleFactors).toEqual([1, 2, 4]);
    expect(loaded.infos.map((i) => i.id)).toEqual([`${BASE}/iiif/ptm_c0`, `${BASE}/iiif/ptm_c1`, `${BASE}/iiif/ptm_color`]);
  });

  it('fetches the info.json of only the groups without one', async () => {
    const fetch = stubFetch();
    const loaded = await loadLayer(layerOf(blockWith((i) => (i === 2 ? {} : description()))));
    expect(fetch.mock.calls.map((c) => String(c[0]))).toEqual([`${BASE}/iiif/ptm_color/info.json`]);
    expect(loaded.infos[2]?.['@context']).toBe(IMAGE3_CONTEXT);
  });

  it('checks embedded groups against each other and names them by their place in the manifest', async () => {
    stubFetch();
    const layer = layerOf(blockWith((i) => description(i === 1 ? { tiles: [{ width: 512, scaleFactors: [1, 2, 4] }] } : {})));
    const error = await loadLayer(layer).catch((e: unknown) => e);
    expect(error).toBeInstanceOf(MismatchedPlanesError);
    expect((error as Error).message).toContain(`plane group 1 (manifest: ${BASE}/layers/ptm.json planes[1].service: 512×1024, tiles 512×512`);
  });
});

describe('overlay levels with embedded descriptions', () => {
  it('reads the level image service\'s description', () => {
    const anno = overlayAnnotation('ptm', 2, 'Whole', '');
    const body = (anno.body as Record<string, unknown>[])[0];
    const services = body.service as Record<string, unknown>[];
    services[0] = { ...services[0], ...description({ width: 128, height: 256, tiles: [{ width: 256, scaleFactors: [1] }] }) };
    const level = parseManifest(manifestWithAnnotations([overlayPage('ptm', [anno])])).layers[0]?.overlays[0];
    expect(level?.embedded?.geometry).toEqual({ width: 128, height: 256, tileWidth: 256, tileHeight: 256, scaleFactors: [1] });
  });

  it('refuses a malformed one, naming the annotation', () => {
    const anno = overlayAnnotation('ptm', 2, 'Whole', '');
    const body = (anno.body as Record<string, unknown>[])[0];
    const services = body.service as Record<string, unknown>[];
    services[0] = { ...services[0], width: 128, height: 256, tiles: 'all' };
    expect(() => parseManifest(manifestWithAnnotations([overlayPage('ptm', [anno])])))
      .toThrow(/^manifest: overlay annotation .*: the level image's service: expected exactly one "tiles" entry$/);
  });
});
