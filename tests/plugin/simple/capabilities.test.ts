import { describe, expect, it } from 'vitest';
import type { LayerInfo, PresetLibrary } from '../../../plugin/src/index';
import { simpleControls } from '../../../plugin/src/simple/capabilities';

const layer = (id: string, layerType: LayerInfo['layerType']): LayerInfo => ({
  id, label: id, layerType, shading: 'flat', modes: ['color'],
});
const LAYERS = [layer('ptm', 'ptm'), layer('ir', 'image'), layer('uv', 'image'), layer('sv', 'svbrdf')];

function library(base: [string, string][], lens: [string, string][]): PresetLibrary {
  const presets: Record<string, PresetLibrary['presets'][string]> = {};
  for (const [id, layerId] of [...base, ...lens]) {
    presets[id] = { label: id, layer: layerId, mode: 'color', params: {} };
  }
  return {
    type: 'LanternaPresets', version: 1, presets,
    base: base.map(([id]) => ({ label: id, preset: id })), lens: lens.map(([id]) => ({ label: id, preset: id })),
  };
}

describe('simpleControls', () => {
  it('shows both menus and both toggles for a full library', () => {
    expect(simpleControls(library([['raking', 'ptm']], [['infrared', 'ir']]), LAYERS)).toEqual({
      baseMenu: true, lensMenu: true, lensToggle: true, measureToggle: true, noPresets: false,
    });
  });

  it('hides the lens toggle when the library has no lens entries', () => {
    const c = simpleControls(library([['raking', 'ptm']], []), LAYERS);
    expect(c).toMatchObject({ lensMenu: false, lensToggle: false, baseMenu: true });
  });

  it('hides the measurement toggle when no used layer is shape+material, PTM or HSH', () => {
    expect(simpleControls(library([['ir', 'ir']], [['uv', 'uv']]), LAYERS).measureToggle).toBe(false);
    expect(simpleControls(library([['ir', 'ir']], [['sv', 'sv']]), LAYERS).measureToggle).toBe(true);
  });

  it('uses an entry\'s own layer over its preset\'s', () => {
    const lib = library([['ir', 'ir']], []);
    const entries = { ...lib, base: [{ label: 'PTM view', preset: 'ir', layer: 'ptm' }] };
    expect(simpleControls(entries, LAYERS).measureToggle).toBe(true);
  });

  it('without presets: the lens toggle only, and the note', () => {
    expect(simpleControls(library([], []), LAYERS)).toEqual({
      baseMenu: false, lensMenu: false, lensToggle: true, measureToggle: false, noPresets: true,
    });
  });
});
