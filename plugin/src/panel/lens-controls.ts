/**
 * The panel's lens section: the layer and mode drawn in the lens, its opacity and where the
 * annotations show. Plain DOM, driven by the viewer's public API.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { ANNOTATION_DISPLAYS, type AnnotationDisplay } from '../lens/lens-state';
import type { RenderMode } from '../render/modes';
import { labelled, layerOptions, modeOptions, mountSection, namedSelect, slider, type PanelSection } from './panel-dom';

/** The section's DOM. */
export type LensControls = PanelSection;

const DISPLAY_LABELS: Readonly<Record<AnnotationDisplay, string>> = {
  everywhere: 'Everywhere', inside: 'Inside the lens', outside: 'Outside the lens',
};

/** Build the lens section into `parent` for a ready viewer. */
export function createLensControls(lanterna: LanternaViewer, parent: HTMLElement,
  onError: (error: unknown) => void = () => undefined): LensControls {
  const section = document.createElement('fieldset');
  section.className = 'lanterna-controls lanterna-lens-controls';
  Object.assign(section.style, { border: '0', borderTop: '1px solid #3a3a3a', padding: '8px 0 0', margin: '8px 0 0' });
  const legend = document.createElement('legend');
  legend.textContent = 'Lens';
  const layers = lanterna.getLayers();
  const layerSelect = namedSelect('lens-layer', layerOptions(layers));
  const modeSelect = namedSelect('lens-mode');
  const opacity = slider('Opacity', { name: 'lens-opacity', min: 0, max: 1, step: 0.01 });
  const display = namedSelect('lens-annotations', ANNOTATION_DISPLAYS.map((d) => new Option(DISPLAY_LABELS[d], d)));
  const annotationsRow = labelled('Annotations', display);
  section.append(legend, labelled('Layer', layerSelect), labelled('Mode', modeSelect), opacity.row, annotationsRow);

  let shownLayer = '';
  const refresh = (): void => {
    const lens = lanterna.getLens();
    section.disabled = !lens.enabled;
    layerSelect.value = lens.layer;
    if (lens.layer !== shownLayer) {
      shownLayer = lens.layer;
      modeSelect.replaceChildren(...modeOptions(layers.find((l) => l.id === lens.layer)?.modes ?? []));
    }
    modeSelect.value = lens.mode;
    opacity.input.value = String(lens.opacity);
    opacity.value.textContent = lens.opacity.toFixed(2);
    display.value = lens.annotations;
    annotationsRow.hidden = !lanterna.manifest?.layers.some((l) => l.overlays.length > 0);
  };
  const set = (update: Parameters<LanternaViewer['setLens']>[0]): void => {
    try {
      lanterna.setLens(update).catch(onError);
    } catch (error) {
      onError(error);
    }
  };
  layerSelect.addEventListener('change', () => { set({ layer: layerSelect.value }); });
  modeSelect.addEventListener('change', () => { set({ mode: modeSelect.value as RenderMode }); });
  opacity.input.addEventListener('input', () => { set({ opacity: Number(opacity.input.value) }); });
  display.addEventListener('change', () => { set({ annotations: display.value as AnnotationDisplay }); });
  return mountSection(lanterna, parent, section, refresh);
}
