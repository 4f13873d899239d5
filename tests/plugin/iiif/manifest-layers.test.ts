import { describe, expect, it } from 'vitest';
import { ManifestError, MissingRelightServiceError, RelightServiceError } from '../../../plugin/src/iiif/errors';
import { idFromUrl, parseManifest } from '../../../plugin/src/iiif/manifest';
import { parseRelightService, svbrdfMapIndices } from '../../../plugin/src/iiif/relight-service';
import { manifest, relightBlock } from '../fixtures';

const BASE = 'http://127.0.0.1:8000/datasets/obj';

function plane(image: string, channels: string[], scale?: number[], bias?: number[]): Record<string, unknown> {
  return {
    service: { id: `${BASE}/iiif/${image}`, type: 'ImageService3', profile: 'level0' }, format: 'png', channels,
    scale: scale ?? channels.map(() => 1), bias: bias ?? channels.map(() => 0),
  };
}

function block(id: string, fields: Record<string, unknown>): Record<string, unknown> {
  return {
    id: `${BASE}/layers/${id}.json`, type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', width: 512,
    height: 1024, ...fields,
  };
}

function item(label: string, service: Record<string, unknown> | null): Record<string, unknown> {
  return {
    id: `${BASE}/iiif/${label}/full/max/0/default.jpg`, type: 'Image', label: { en: [label] },
    service: [{ id: `${BASE}/iiif/${label}`, type: 'ImageService3', profile: 'level0' }, ...(service ? [service] : [])],
  };
}

const hsh9 = block('hsh', {
  layerType: 'hsh', terms: 9,
  planes: Array.from({ length: 9 }, (_, k) => plane(`hsh_t${k}`, [`R${k}`, `G${k}`, `B${k}`], [0.5, 0.5, 0.5], [0.2, 0.2, 0.2])),
});
const shape = block('shape', {
  layerType: 'svbrdf', glossLimits: [0.02, 0.4], inputColorSpace: 'srgb',
  planes: [plane('normals', ['NX', 'NY', 'NZ'], [2, 2, 2], [0.5, 0.5, 0.5]), plane('kd', ['KD_R', 'KD_G', 'KD_B']),
    plane('gloss', ['GLOSS']), plane('depth', ['DEPTH'], [0.3], [0.1])],
});
const mono = block('band7', { layerType: 'image', planes: [plane('band7', ['Y'])] });

describe('multi-layer manifests', () => {
  const choice = {
    type: 'Choice',
    items: [item('ptm', relightBlock()), item('HSH', hsh9), item('plain', null), item('Shape', shape), item('Band 7', mono)],
  };
  const m = parseManifest(manifest(choice));

  it('parses every Choice item with a relight service, in order', () => {
    expect(m.layers.map((l) => l.id)).toEqual(['ptm', 'hsh', 'shape', 'band7']);
    expect(m.layers.map((l) => l.label)).toEqual(['ptm', 'HSH', 'Shape', 'Band 7']);
    expect(m.layers.map((l) => l.layer.layerType)).toEqual(['ptm', 'hsh', 'svbrdf', 'image']);
    expect(m.layer).toBe(m.layers[0]?.layer);
    expect(m.imageId).toBe(`${BASE}/iiif/ptm/full/max/0/default.jpg`);
  });

  it('reads HSH terms and svbrdf fields', () => {
    const h = m.layers[1]?.layer;
    expect(h?.terms).toBe(9);
    expect(h?.planes).toHaveLength(9);
    const s = m.layers[2]?.layer;
    expect(s?.glossLimits).toEqual([0.02, 0.4]);
    expect(s?.inputColorSpace).toBe('srgb');
    expect(s && svbrdfMapIndices(s)).toEqual({ normals: 0, kd: 1, ks: -1, gloss: 2, depth: 3 });
  });

  it('keeps single-channel groups as one channel', () => {
    const s = m.layers[2]?.layer;
    expect(s?.planes[3]).toMatchObject({ channels: ['DEPTH'], scale: [0.3], bias: [0.1] });
    expect(m.layers[3]?.layer.planes[0]?.channels).toEqual(['Y']);
  });

  it('defaults svbrdf fields', () => {
    const l = parseRelightService(block('n', { layerType: 'svbrdf', planes: [plane('n', ['NX', 'NY', 'NZ'])] }));
    expect(l.glossLimits).toEqual([0.01, 0.5]);
    expect(l.inputColorSpace).toBe('linear');
  });

  it('rejects two layers with the same id, or no relight service at all', () => {
    const twice = { type: 'Choice', items: [item('a', hsh9), item('b', hsh9)] };
    expect(() => parseManifest(manifest(twice))).toThrow(ManifestError);
    const none = { type: 'Choice', items: [item('a', null), item('b', null)] };
    expect(() => parseManifest(manifest(none))).toThrow(MissingRelightServiceError);
  });

  it('names layers after the service document, else the image', () => {
    expect(idFromUrl('http://h/d/layers/ptm.json')).toBe('ptm');
    expect(idFromUrl('http://h/d/layers/ptm.json?x=1#y')).toBe('ptm');
    expect(idFromUrl('http://h/d/iiif/img/')).toBe('img');
    const noId = { ...hsh9, id: undefined };
    expect(parseManifest(manifest(item('x', noId))).layers[0]?.id).toBe('x');
  });
});

describe('relight service errors for the new types', () => {
  it('rejects bad HSH blocks', () => {
    expect(() => parseRelightService({ ...hsh9, terms: 6 })).toThrow(/terms/);
    expect(() => parseRelightService({ ...hsh9, terms: 16 })).toThrow(/16 plane groups/);
    const swapped = { ...hsh9, planes: [...(hsh9.planes as unknown[])].reverse() };
    expect(() => parseRelightService(swapped)).toThrow(/channels must be/);
    expect(() => parseRelightService({ ...hsh9, colorspace: 'lrgb' })).toThrow(/colorspace/);
  });

  it('rejects bad svbrdf blocks', () => {
    const with_ = (planes: unknown[], extra = {}) => block('s', { layerType: 'svbrdf', planes, ...extra });
    expect(() => parseRelightService(with_([]))).toThrow(/at least one map/);
    expect(() => parseRelightService(with_([plane('x', ['KD_G', 'KD_R', 'KD_B'])]))).toThrow(/not an svbrdf map/);
    expect(() => parseRelightService(with_([plane('g', ['GLOSS']), plane('h', ['GLOSS'])]))).toThrow(/twice/);
    expect(() => parseRelightService(with_([plane('g', ['GLOSS'])], { glossLimits: [0.5, 0.1] }))).toThrow(/glossLimits/);
    expect(() => parseRelightService(with_([plane('g', ['GLOSS'])], { glossLimits: [0, 0.1] }))).toThrow(/glossLimits/);
    expect(() => parseRelightService(with_([plane('g', ['GLOSS'])], { inputColorSpace: 'rec709' })))
      .toThrow(RelightServiceError);
    const display = parseRelightService(with_([plane('g', ['GLOSS'])], { inputColorSpace: 'display' }));
    expect(display.inputColorSpace).toBe('display');
  });

  it('rejects scale/bias that do not match the channel count, and 2-channel groups', () => {
    expect(() => parseRelightService(block('m', { layerType: 'image', planes: [plane('m', ['Y'], [1, 1, 1], [0])] })))
      .toThrow(/scale must be an array of 1 finite number/);
    expect(() => parseRelightService(block('m', { layerType: 'image', planes: [plane('m', ['Y', 'A'])] })))
      .toThrow(/1 or 3 names/);
    expect(() => parseRelightService(block('m', { layerType: 'image', planes: [plane('m', ['GLOSS'])] })))
      .toThrow(/channels must be/);
  });
});
