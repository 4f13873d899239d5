/**
 * The viewer page's control panel: layer switcher, mode menu (the active layer's modes only) and
 * sliders for the parameters the mode uses. Plain DOM, driven by the viewer's public API.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { LanternaError } from '../errors';
import type { RenderMode } from '../render/modes';
import { PARAM_SPECS, relevantParams, type RenderParamName } from '../render/params';
import {
  labelled, layerOptions, modeOptions, mountSection, namedSelect, slider, type PanelSection, type Slider,
} from './panel-dom';

/** The panel's DOM. */
export type Controls = PanelSection;

/**
 * Build the panel into `parent` for a ready viewer.
 *
 * @param onError - called with errors from layer switching
 */
export function createControls(lanterna: LanternaViewer, parent: HTMLElement,
  onError: (error: unknown) => void = () => undefined): Controls {
  const panel = document.createElement('form');
  panel.className = 'lanterna-controls';
  panel.addEventListener('submit', (e) => { e.preventDefault(); });

  const layers = lanterna.getLayers();
  const layerSelect = namedSelect('layer', layerOptions(layers));
  const modeSelect = namedSelect('mode');
  const sliders = document.createElement('div');
  sliders.className = 'lanterna-sliders';
  const reset = document.createElement('button');
  reset.type = 'button';
  reset.textContent = 'Reset';
  reset.title = 'Reset the parameters to their defaults';
  const layerRow = labelled('Layer', layerSelect);
  layerRow.hidden = layers.length < 2;
  panel.append(layerRow, labelled('Mode', modeSelect), sliders, reset);

  const inputs = new Map<RenderParamName, Slider>();
  let shownKey = '';

  const buildSliders = (names: RenderParamName[]): void => {
    sliders.replaceChildren();
    inputs.clear();
    for (const name of names) {
      const spec = PARAM_SPECS[name];
      const s = slider(spec.label, { name, min: spec.min, max: spec.max, step: spec.step });
      s.input.addEventListener('input', () => { lanterna.setRenderParams({ [name]: Number(s.input.value) }); });
      s.input.addEventListener('dblclick', () => { lanterna.setRenderParams({ [name]: spec.default }); });
      s.row.title = `${name}: ${spec.min}–${spec.max}, default ${spec.default} (double-click to reset)`;
      sliders.appendChild(s.row);
      inputs.set(name, s);
    }
  };

  const refresh = (): void => {
    const activeId = lanterna.getActiveLayer();
    const active = layers.find((l) => l.id === activeId);
    if (!active) {
      return;
    }
    layerSelect.value = activeId;
    const mode = lanterna.getRenderMode();
    const key = `${activeId}|${mode}`;
    if (key !== shownKey) {
      shownKey = key;
      modeSelect.replaceChildren(...modeOptions(active.modes));
      buildSliders(relevantParams(mode, active.shading));
    }
    modeSelect.value = mode;
    const params = lanterna.getRenderParams();
    for (const [name, { input, value }] of inputs) {
      input.value = String(params[name]);
      value.textContent = params[name].toFixed(PARAM_SPECS[name].step < 1 ? 2 : 0);
    }
  };

  layerSelect.addEventListener('change', () => {
    lanterna.setActiveLayer(layerSelect.value).catch((error: unknown) => {
      refresh(); // back to the layer still shown
      onError(error);
    });
  });
  modeSelect.addEventListener('change', () => {
    try {
      lanterna.setRenderMode(modeSelect.value as RenderMode);
    } catch (error) {
      onError(error instanceof LanternaError ? error : new LanternaError(String(error)));
    }
  });
  reset.addEventListener('click', () => { lanterna.resetRenderParams(); });
  return mountSection(lanterna, parent, panel, refresh);
}
