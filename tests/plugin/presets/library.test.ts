import { describe, expect, it } from 'vitest';
import {
  addPreset, emptyLibrary, entryLayer, libraryLayers, presetId, serializeLibrary, type PresetDataset,
} from '../../../plugin/src/presets/library';
import { parsePresetLibrary } from '../../../plugin/src/presets/read-library';

const DATASET: PresetDataset = {
  layers: [
    { id: 'ptm', modes: ['color', 'normals', 'specular', 'diffuseGain'] },
    { id: 'band_ir', modes: ['color', 'albedo', 'achromatic', 'unsharpImage'] },
  ],
  width: 1536,
  height: 1152,
};

const valid = (): Record<string, unknown> => ({
  type: 'LanternaPresets',
  version: 1,
  presets: {
    raking: { label: 'Raking', layer: 'ptm', mode: 'color', params: { lightIntensity: 1.5 }, light: [-0.95, 0.1],
      view: [100, 200, 400, 300] },
    ir: { label: 'IR', layer: 'band_ir', mode: 'achromatic' },
  },
  base: [{ label: 'Raking light', preset: 'raking' }],
  lens: [{ label: 'Infrared', preset: 'ir', opacity: 0.8 }],
});

/** A library document as the tests edit it. */
interface Doc {
  [key: string]: unknown;
  presets: Record<string, Record<string, unknown> & { params: Record<string, unknown> }>;
  base: Record<string, unknown>[];
  lens: Record<string, unknown>[];
}

/** The library `valid()` with `edit` applied to it. */
function broken(edit: (doc: Doc) => void): Doc {
  const doc = valid() as Doc;
  edit(doc);
  return doc;
}

describe('parsePresetLibrary', () => {
  it('reads a valid library, with the service block fields of a manifest', () => {
    const lib = parsePresetLibrary({ id: 'https://x/presets.json', profile: 'urn:lanterna:presets:1', ...valid() },
      'm.json', DATASET);
    expect(lib.presets.raking?.light).toEqual([-0.95, 0.1]);
    expect(lib.lens[0]?.opacity).toBe(0.8);
    expect(libraryLayers(lib)).toEqual(['ptm', 'band_ir']);
    expect(entryLayer(lib, lib.base[0])).toBe('ptm');
  });

  it.each([
    ['base[0].preset', (d: Doc) => { d.base[0].preset = 'nope'; }],
    ['base[0].layer', (d: Doc) => { d.base[0].layer = 'band_ir'; }], // raking is colour: fine
    ['presets.raking.layer', (d: Doc) => { d.presets.raking.layer = 'x'; }],
    ['presets.ir.mode', (d: Doc) => { d.presets.ir.mode = 'specular'; }],
    ['presets.raking.mode', (d: Doc) => { d.presets.raking.mode = 'glow'; }],
    ['presets.raking.params.gamma', (d: Doc) => { d.presets.raking.params.gamma = 9; }],
    ['presets.raking.params.shine', (d: Doc) => { d.presets.raking.params.shine = 1; }],
    ['presets.raking.light', (d: Doc) => { d.presets.raking.light = [0.9, 0.9]; }],
    ['presets.raking.view', (d: Doc) => { d.presets.raking.view = [1400, 0, 400, 10]; }],
    ['lens[0].opacity', (d: Doc) => { d.lens[0].opacity = 2; }],
    ['base[0].opacity', (d: Doc) => { d.base[0].opacity = 0.5; }],
    ['presets.bad id', (d: Doc) => { d.presets['bad id'] = d.presets.ir!; }],
    ['version', (d: Doc) => { d.version = 2; }],
    ['lens', (d: Doc) => { delete (d as Record<string, unknown>).lens; }],
  ])('names %s', (path, edit) => {
    const doc = broken(edit);
    if (path === 'base[0].layer') {
      // a colour preset applies to the IR layer too; an entry pointing at a missing layer does not
      expect(() => parsePresetLibrary(doc, 'p.json', DATASET)).not.toThrow();
      doc.base[0].layer = 'missing';
    }
    expect(() => parsePresetLibrary(doc, 'p.json', DATASET)).toThrow(`p.json: ${path}: `);
  });

  it('checks only the schema rules without a dataset', () => {
    expect(() => parsePresetLibrary(broken((d) => { d.presets.raking.layer = 'x'; }), 'p.json')).not.toThrow();
  });
});

describe('editing a library', () => {
  it('adds presets under unique ids and writes a document that reads back equal', () => {
    let lib = emptyLibrary();
    const preset = { label: 'Raking light', layer: 'ptm', mode: 'color' as const, params: { gamma: 1.2 } };
    const first = addPreset(lib, preset, 'base');
    const second = addPreset(first.library, preset, 'lens', 0.5);
    lib = second.library;
    expect([first.id, second.id]).toEqual(['raking-light', 'raking-light-2']);
    expect(lib.lens).toEqual([{ label: 'Raking light', preset: 'raking-light-2', opacity: 0.5 }]);
    expect(parsePresetLibrary(JSON.parse(serializeLibrary(lib)), 'x', DATASET)).toEqual(lib);
    expect(presetId('***', [])).toBe('preset');
  });
});
