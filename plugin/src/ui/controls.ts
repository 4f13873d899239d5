/**
 * The viewer page's control panel: layer switcher, mode menu (the active layer's modes only) and
 * sliders for the parameters the mode uses. Plain DOM, driven by the viewer's public API.
 */
import { LanternaError } from '../errors';
import { MODE_LABELS, type RenderMode } from '../render/modes';
import { PARAM_SPECS, relevantParams, type RenderParamName } from '../render/params';
import type { LanternaViewer } from '../viewer';
import { labelled } from './dom';

/** The panel's DOM. */
export interface Controls {
  readonly element: HTMLElement;
  destroy(): void;
}

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

  const layerSelect = document.createElement('select');
  layerSelect.name = 'layer';
  const modeSelect = document.createElement('select');
  modeSelect.name = 'mode';
  const sliders = document.createElement('div');
  sliders.className = 'lanterna-sliders';
  const reset = document.createElement('button');
  reset.type = 'button';
  reset.textContent = 'Reset';
  reset.title = 'Reset the parameters to their defaults';

  const layers = lanterna.getLayers();
  for (const l of layers) {
    layerSelect.add(new Option(`${l.label} (${l.layerType})`, l.id));
  }
  const layerRow = labelled('Layer', layerSelect);
  layerRow.hidden = layers.length < 2;
  panel.append(layerRow, labelled('Mode', modeSelect), sliders, reset);
  parent.appendChild(panel);

  const inputs = new Map<RenderParamName, { input: HTMLInputElement; value: HTMLOutputElement }>();
  let shownKey = '';

  const buildSliders = (names: RenderParamName[]): void => {
    sliders.replaceChildren();
    inputs.clear();
    for (const name of names) {
      const spec = PARAM_SPECS[name];
      const input = document.createElement('input');
      Object.assign(input, { type: 'range', name, min: String(spec.min), max: String(spec.max), step: String(spec.step) });
      const value = document.createElement('output');
      input.addEventListener('input', () => { lanterna.setRenderParams({ [name]: Number(input.value) }); });
      input.addEventListener('dblclick', () => { lanterna.setRenderParams({ [name]: spec.default }); });
      const row = labelled(spec.label, input);
      row.append(value);
      row.title = `${name}: ${spec.min}–${spec.max}, default ${spec.default} (double-click to reset)`;
      sliders.appendChild(row);
      inputs.set(name, { input, value });
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
    const names = relevantParams(mode, active.shading);
    const key = `${activeId}|${mode}`;
    if (key !== shownKey) {
      shownKey = key;
      modeSelect.replaceChildren(...active.modes.map((m) => new Option(MODE_LABELS[m], m)));
      buildSliders(names);
    }
    modeSelect.value = mode;
    const params = lanterna.getRenderParams();
    for (const [name, { input, value }] of inputs) {
      input.value = String(params[name]);
      value.textContent = params[name].toFixed(PARAM_SPECS[name].step < 1 ? 2 : 0);
    }
  };

  layerSelect.addEventListener('change', () => {
    lanterna.setActiveLayer(layerSelect.value).catch(onError);
  });
  modeSelect.addEventListener('change', () => {
    try {
      lanterna.setRenderMode(modeSelect.value as RenderMode);
    } catch (error) {
      onError(error instanceof LanternaError ? error : new LanternaError(String(error)));
    }
  });
  reset.addEventListener('click', () => { lanterna.resetRenderParams(); });
  const unsubscribe = lanterna.onChange(refresh);
  refresh();
  return {
    element: panel,
    destroy: () => {
      unsubscribe();
      panel.remove();
    },
  };
}
