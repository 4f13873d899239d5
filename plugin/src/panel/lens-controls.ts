/**
 * The panel's lens section: the layer and mode drawn in the lens, every parameter of that mode (the
 * lens's own light intensity included: one light direction for base and lens, seed paper §6.2.1),
 * its opacity and where the annotations show. Plain DOM, driven by the viewer's public API.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { ANNOTATION_DISPLAYS, type AnnotationDisplay } from '../lens/lens-state';
import type { RenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS } from '../render/params';
import {
  labelled, layerOptions, modeOptions, mountSection, namedSelect, slider, titledSection, type PanelSection,
} from './panel-dom';
import { createParamSliders } from './param-sliders';

/** The section's DOM. */
export type LensControls = PanelSection;

const DISPLAY_LABELS: Readonly<Record<AnnotationDisplay, string>> = {
  everywhere: 'Everywhere', inside: 'Inside the lens', outside: 'Outside the lens',
};

/** Build the lens section into `parent` for a ready viewer. */
export function createLensControls(lanterna: LanternaViewer, parent: HTMLElement,
  onError: (error: unknown) => void = () => undefined): LensControls {
  const section = titledSection('lanterna-lens-controls', 'Lens');
  const layers = lanterna.getLayers();
  const layerSelect = namedSelect('lens-layer', layerOptions(layers));
  const modeSelect = namedSelect('lens-mode');
  const set = (update: Parameters<LanternaViewer['setLens']>[0]): void => {
    try {
      lanterna.setLens(update).catch(onError);
    } catch (error) {
      onError(error);
    }
  };
  const sliders = createParamSliders('lens-', (params) => { set({ params }); });
  const opacity = slider('Opacity', { name: 'lens-opacity', min: 0, max: 1, step: 0.01 });
  const reset = document.createElement('button');
  reset.type = 'button';
  reset.textContent = 'Reset';
  reset.title = 'Reset the lens parameters to their defaults';
  const display = namedSelect('lens-annotations', ANNOTATION_DISPLAYS.map((d) => new Option(DISPLAY_LABELS[d], d)));
  const annotationsRow = labelled('Annotations', display);
  const layerRow = labelled('Layer', layerSelect);
  layerRow.hidden = layers.length < 2;
  annotationsRow.hidden = !lanterna.manifest?.layers.some((l) => l.overlays.length > 0);
  section.append(layerRow, labelled('Mode', modeSelect), sliders.element, opacity.row, reset,
    annotationsRow);

  let shownLayer = '';
  const refresh = (): void => {
    const lens = lanterna.getLens();
    section.disabled = !lens.enabled;
    section.title = lens.enabled ? '' : 'Switch the lens on (toolbar) to change it';
    layerSelect.value = lens.layer;
    const info = layers.find((l) => l.id === lens.layer);
    if (lens.layer !== shownLayer) {
      shownLayer = lens.layer;
      modeSelect.replaceChildren(...modeOptions(info?.modes ?? []));
    }
    modeSelect.value = lens.mode;
    if (info) {
      sliders.refresh({ key: lens.layer, mode: lens.mode, shading: info.shading, params: lens.params });
    }
    opacity.input.value = String(lens.opacity);
    opacity.value.textContent = lens.opacity.toFixed(2);
    display.value = lens.annotations;
  };
  layerSelect.addEventListener('change', () => { set({ layer: layerSelect.value }); });
  modeSelect.addEventListener('change', () => { set({ mode: modeSelect.value as RenderMode }); });
  opacity.input.addEventListener('input', () => { set({ opacity: Number(opacity.input.value) }); });
  reset.addEventListener('click', () => { set({ params: DEFAULT_RENDER_PARAMS }); });
  display.addEventListener('change', () => { set({ annotations: display.value as AnnotationDisplay }); });
  return mountSection(lanterna, parent, section, refresh);
}
