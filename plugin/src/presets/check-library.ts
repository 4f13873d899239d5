/**
 * The rules of a preset library that need the dataset (`docs/presets.md`): layers exist, modes apply,
 * views fit the image, entries name presets that exist. Pure: no DOM, no GL.
 */
import type { RenderMode } from '../render/modes';
import type { PresetDataset, PresetLayerFacts, PresetLibrary } from './library';
import { describe, join, type Reader } from './reader';

/** The rules that need the dataset: layers exist, modes apply, lights and views fit. */
export function checkAgainst(r: Reader, library: PresetLibrary, dataset: PresetDataset): void {
  const ids = dataset.layers.map((l) => l.id);
  const layerAt = (id: string, path: string): PresetLayerFacts => {
    const layer = dataset.layers.find((l) => l.id === id);
    if (!layer) {
      r.fail(path, `no layer ${describe(id)} in the dataset (layers: ${ids.join(', ')})`);
    }
    return layer;
  };
  const modeApplies = (mode: RenderMode, layer: PresetLayerFacts, path: string): void => {
    if (!layer.modes.includes(mode)) {
      r.fail(path, `mode ${mode} does not apply to layer ${layer.id}; it supports ${layer.modes.join(', ')}`);
    }
  };
  for (const [id, preset] of Object.entries(library.presets)) {
    const path = join('presets', id);
    modeApplies(preset.mode, layerAt(preset.layer, join(path, 'layer')), join(path, 'mode'));
    if (preset.view) {
      const [x, y, w, h] = preset.view;
      if (x < 0 || y < 0 || x + w > dataset.width || y + h > dataset.height) {
        r.fail(join(path, 'view'), `the region ${describe(preset.view)} is not within the image `
          + `(${dataset.width} × ${dataset.height})`);
      }
    }
  }
  for (const target of ['base', 'lens'] as const) {
    library[target].forEach((entry, k) => {
      const path = join(target, k);
      const preset = library.presets[entry.preset];
      if (!preset) {
        r.fail(join(path, 'preset'), `no preset ${describe(entry.preset)} in the library`);
      }
      if (entry.layer !== undefined) {
        modeApplies(preset.mode, layerAt(entry.layer, join(path, 'layer')), join(path, 'layer'));
      }
    });
  }
}

