/**
 * The viewer page's control panel: layer switcher, mode menu (the active layer's modes only) and
 * sliders for every parameter the mode uses (light intensity included). Plain DOM, driven by the viewer's public API.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { LanternaError } from '../errors';
import type { RenderMode } from '../render/modes';
import { labelled, layerOptions, modeOptions, mountSection, namedSelect, type PanelSection } from './panel-dom';
import { createParamSliders } from './param-sliders';

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
  const sliders = createParamSliders('', (params) => { lanterna.setRenderParams(params); });
  const reset = document.createElement('button');
  reset.type = 'button';
  reset.textContent = 'Reset';
  reset.title = 'Reset the parameters to their defaults';
  const layerRow = labelled('Layer', layerSelect);
  layerRow.hidden = layers.length < 2;
  const title = document.createElement('h2');
  title.className = 'lanterna-section-title';
  title.textContent = 'Base layer';
  panel.append(title, layerRow, labelled('Mode', modeSelect), sliders.element, reset);

  let shownLayer = '';
  const refresh = (): void => {
    const activeId = lanterna.getActiveLayer();
    const active = layers.find((l) => l.id === activeId);
    if (!active) {
      return;
    }
    layerSelect.value = activeId;
    const mode = lanterna.getRenderMode();
    if (shownLayer !== activeId) {
      shownLayer = activeId;
      modeSelect.replaceChildren(...modeOptions(active.modes));
    }
    modeSelect.value = mode;
    sliders.refresh({ key: activeId, mode, shading: active.shading, params: lanterna.getRenderParams() });
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
