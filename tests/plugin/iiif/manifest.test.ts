import { describe, expect, it } from 'vitest';
import {
  ManifestError, MismatchedPlanesError, MissingRelightServiceError, RelightServiceError, ImageInfoError,
} from '../../../plugin/src/iiif/errors';
import { commonGeometry, imageGeometry } from '../../../plugin/src/iiif/image-info';
import { labelText, parseManifest } from '../../../plugin/src/iiif/manifest';
import { expectedChannels, parseRelightService } from '../../../plugin/src/iiif/relight-service';
import { info, manifest, relightBlock } from '../fixtures';

describe('parseManifest', () => {
  it('finds the relight layer of the painting image', () => {
    const m = parseManifest(manifest());
    expect(m.label).toBe('Ushabti');
    expect(m.layer.layerType).toBe('ptm');
    expect(m.layer.colorspace).toBe('lrgb');
    expect(m.layer.width).toBe(512);
    expect(m.layer.height).toBe(1024);
    expect(m.layer.planes.map((p) => p.serviceId)).toEqual([
      'http://127.0.0.1:8000/datasets/ushabti/iiif/ptm_c0',
      'http://127.0.0.1:8000/datasets/ushabti/iiif/ptm_c1',
      'http://127.0.0.1:8000/datasets/ushabti/iiif/ptm_color',
    ]);
    expect(m.layer.planes[1]?.scale).toEqual([2, 2, 0]);
    expect(m.layer.planes[0]?.bias).toEqual([0.627, 0.627, 0.627]);
  });

  it('takes the first Image of a Choice', () => {
    const image = (manifest().items as { items: { items: { body: unknown }[] }[] }[])[0]?.items[0]?.items[0]?.body;
    const choice = { type: 'Choice', items: [image, { type: 'Image', id: 'other', service: [] }] };
    expect(parseManifest(manifest(choice)).layer.planes).toHaveLength(3);
  });

  it('rejects an image without a relight service', () => {
    const body = { id: 'x', type: 'Image', service: [{ id: 'y', type: 'ImageService3' }] };
    expect(() => parseManifest(manifest(body))).toThrow(MissingRelightServiceError);
  });

  it('rejects documents that are not manifests or have no painting image', () => {
    expect(() => parseManifest({ type: 'Collection' })).toThrow(ManifestError);
    expect(() => parseManifest({ type: 'Manifest', items: [] })).toThrow(ManifestError);
    expect(() => parseManifest(manifest({ type: 'Video', id: 'v' }))).toThrow(ManifestError);
  });

  it('reads label language maps', () => {
    expect(labelText({ none: ['X'] })).toBe('X');
    expect(labelText({ fr: ['Y'] })).toBe('Y');
    expect(labelText(undefined)).toBe('');
  });
});

describe('parseRelightService', () => {
  it('rejects a wrong plane count, channel order, basis or profile', () => {
    const fewer = { ...relightBlock(), planes: (relightBlock().planes as unknown[]).slice(0, 2) };
    expect(() => parseRelightService(fewer)).toThrow(/needs 3 plane groups/);
    const swapped = relightBlock();
    const planes = swapped.planes as Record<string, unknown>[];
    planes[0] = { ...planes[0], channels: ['L1', 'L0', 'L2'] };
    expect(() => parseRelightService(swapped)).toThrow(RelightServiceError);
    expect(() => parseRelightService({ ...relightBlock(), basis: ['1', 'lu', 'lv', 'lu2', 'lv2', 'lulv'] }))
      .toThrow(/basis/);
    expect(() => parseRelightService({ ...relightBlock(), profile: 'urn:other' })).toThrow(RelightServiceError);
    expect(() => parseRelightService({ ...relightBlock(), layerType: 'rti' })).toThrow(/layerType/);
    expect(() => parseRelightService({ ...relightBlock(), width: 0 })).toThrow(/width/);
  });

  it('rejects a non-numeric scale or bias', () => {
    const b = relightBlock();
    const planes = b.planes as Record<string, unknown>[];
    planes[2] = { ...planes[2], scale: [1, 1] };
    expect(() => parseRelightService(b)).toThrow(/scale/);
  });

  it('knows the rgb channel layout', () => {
    expect(expectedChannels('ptm', 'rgb')).toEqual([
      ['R0', 'R1', 'R2'], ['R3', 'R4', 'R5'], ['G0', 'G1', 'G2'], ['G3', 'G4', 'G5'],
      ['B0', 'B1', 'B2'], ['B3', 'B4', 'B5'],
    ]);
    expect(expectedChannels('image', 'rgb')).toEqual([['R', 'G', 'B']]);
  });

  it('accepts an image layer', () => {
    const layer = parseRelightService({
      type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType: 'image', colorspace: 'rgb',
      width: 10, height: 20,
      planes: [{ service: { id: 'http://h/iiif/img/' }, channels: ['R', 'G', 'B'], scale: [1, 1, 1], bias: [0, 0, 0] }],
    });
    expect(layer.planes[0]?.serviceId).toBe('http://h/iiif/img');
    expect(layer.planes[0]?.format).toBe('png');
  });
});

describe('plane geometry', () => {
  it('reads info.json tiling', () => {
    const g = imageGeometry(info({ tiles: [{ width: 256, scaleFactors: [4, 1, 2] }] }));
    expect(g).toEqual({ width: 512, height: 1024, tileWidth: 256, tileHeight: 256, scaleFactors: [1, 2, 4] });
    expect(() => imageGeometry(info({ tiles: undefined }))).toThrow(ImageInfoError);
  });

  it('accepts identical groups and returns their geometry', () => {
    const g = commonGeometry([imageGeometry(info()), imageGeometry(info())], { width: 512, height: 1024 });
    expect(g.tileWidth).toBe(256);
  });

  it('rejects groups that differ in size, tiles or scale factors', () => {
    const a = imageGeometry(info());
    expect(() => commonGeometry([a, imageGeometry(info({ width: 511 }))])).toThrow(MismatchedPlanesError);
    expect(() => commonGeometry([a, imageGeometry(info({ tiles: [{ width: 512, scaleFactors: [1, 2, 4] }] }))]))
      .toThrow(MismatchedPlanesError);
    expect(() => commonGeometry([a, imageGeometry(info({ tiles: [{ width: 256, scaleFactors: [1, 2] }] }))]))
      .toThrow(/scale factors/);
    expect(() => commonGeometry([a], { width: 512, height: 1000 })).toThrow(MismatchedPlanesError);
  });
});
