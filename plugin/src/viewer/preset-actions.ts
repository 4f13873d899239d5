/**
 * Presets on a running viewer: apply an entry of a library's `base` or `lens` list, and capture the
 * current base or lens as a preset (`docs/presets.md`). Uses only the viewer's public API, so what a
 * preset does is exactly what the same calls made by hand do.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { LanternaError } from '../errors';
import { entryLayer, type Preset, type PresetLibrary, type PresetTarget } from '../presets/library';
import { DEFAULT_RENDER_PARAMS, relevantParams, type RenderParamName } from '../render/params';

/** An entry index that is not in the list. */
export class PresetIndexError extends LanternaError {}

/**
 * Apply entry `index` of `library`'s `target` list. Base: the entry's layer becomes the active layer,
 * then its mode, its parameters (the others back to their defaults), its light and its view, if it has
 * them. Lens: the lens is switched on showing the entry's layer in the preset's mode and parameters,
 * at the entry's opacity (default 1); the preset's light and view are not used (one light for both).
 */
export async function applyPresetEntry(lanterna: LanternaViewer, library: PresetLibrary, target: PresetTarget,
  index: number): Promise<void> {
  const entry = library[target][index];
  const preset = entry ? library.presets[entry.preset] : undefined;
  if (!entry || !preset) {
    throw new PresetIndexError(`no ${target} preset at index ${index} (the list has ${library[target].length})`);
  }
  const layer = entryLayer(library, entry);
  const params = { ...DEFAULT_RENDER_PARAMS, ...preset.params };
  if (target === 'lens') {
    const opacity = 'opacity' in entry && typeof entry.opacity === 'number' ? entry.opacity : 1;
    await lanterna.setLens({ enabled: true, layer, mode: preset.mode, params, opacity });
    return;
  }
  if (lanterna.getActiveLayer() !== layer) {
    await lanterna.setActiveLayer(layer);
  }
  lanterna.setRenderMode(preset.mode);
  lanterna.resetRenderParams();
  lanterna.setRenderParams(params);
  if (preset.light) {
    lanterna.setLight(preset.light[0], preset.light[1]);
  }
  if (preset.view) {
    const [x, y, w, h] = preset.view;
    lanterna.showImageRegion(x, y, w, h);
  }
}

/** Round to 4 decimals (what a slider can set), so saved files stay readable. */
const round = (v: number): number => Math.round(v * 1e4) / 1e4;

/**
 * The current base (layer, mode, the parameters the mode uses, light and, if `withView`, the region in
 * view) or lens (its layer, mode and parameters) as a preset named `label`.
 */
export function capturePreset(lanterna: LanternaViewer, target: PresetTarget, label: string,
  withView = false): Preset {
  const lens = lanterna.getLens();
  const layerId = target === 'lens' ? lens.layer : lanterna.getActiveLayer();
  const info = lanterna.getLayers().find((l) => l.id === layerId);
  if (!info) {
    throw new PresetIndexError(`no layer ${JSON.stringify(layerId)} is shown`);
  }
  const mode = target === 'lens' ? lens.mode : lanterna.getRenderMode();
  const all = target === 'lens' ? lens.params : lanterna.getRenderParams();
  const params: Partial<Record<RenderParamName, number>> = {};
  for (const name of relevantParams(mode, info.shading)) {
    params[name] = round(all[name]);
  }
  if (target === 'lens') {
    return { label, layer: layerId, mode, params };
  }
  const { lu, lv } = lanterna.getLight();
  const light: [number, number] = [round(lu), round(lv)];
  if (light[0] * light[0] + light[1] * light[1] > 1) {
    const n = Math.hypot(light[0], light[1]);
    light[0] = Math.trunc((lu / n) * 1e4) / 1e4;
    light[1] = Math.trunc((lv / n) * 1e4) / 1e4;
  }
  const preset: Preset = { label, layer: layerId, mode, params, light };
  if (!withView) {
    return preset;
  }
  const region = lanterna.getImageRegion();
  return region ? { ...preset, view: region } : preset;
}
