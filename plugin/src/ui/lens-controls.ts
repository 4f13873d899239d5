/**
 * The panel's lens section: the layer and mode drawn in the lens, its opacity and where the
 * annotations show. Plain DOM, driven by the viewer's public API.
 */
import { ANNOTATION_DISPLAYS, type AnnotationDisplay } from '../lens/lens-state';
import { MODE_LABELS, type RenderMode } from '../render/modes';
import type { LanternaViewer } from '../viewer';
import { labelled } from './dom';

/** The section's DOM. */
export interface LensControls {
  readonly element: HTMLElement;
  destroy(): void;
}

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
  const layerSelect = document.createElement('select');
  layerSelect.name = 'lens-layer';
  const modeSelect = document.createElement('select');
  modeSelect.name = 'lens-mode';
  const opacity = document.createElement('input');
  Object.assign(opacity, { type: 'range', name: 'lens-opacity', min: '0', max: '1', step: '0.01' });
  const opacityValue = document.createElement('output');
  const display = document.createElement('select');
  display.name = 'lens-annotations';
  for (const d of ANNOTATION_DISPLAYS) {
    display.add(new Option(DISPLAY_LABELS[d], d));
  }
  const layers = lanterna.getLayers();
  for (const l of layers) {
    layerSelect.add(new Option(`${l.label} (${l.layerType})`, l.id));
  }
  const opacityRow = labelled('Opacity', opacity);
  opacityRow.append(opacityValue);
  const annotationsRow = labelled('Annotations', display);
  section.append(legend, labelled('Layer', layerSelect), labelled('Mode', modeSelect), opacityRow, annotationsRow);
  parent.appendChild(section);

  let shownLayer = '';
  const refresh = (): void => {
    const lens = lanterna.getLens();
    section.disabled = !lens.enabled;
    layerSelect.value = lens.layer;
    if (lens.layer !== shownLayer) {
      shownLayer = lens.layer;
      const modes = layers.find((l) => l.id === lens.layer)?.modes ?? [];
      modeSelect.replaceChildren(...modes.map((m) => new Option(MODE_LABELS[m], m)));
    }
    modeSelect.value = lens.mode;
    opacity.value = String(lens.opacity);
    opacityValue.textContent = lens.opacity.toFixed(2);
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
  opacity.addEventListener('input', () => { set({ opacity: Number(opacity.value) }); });
  display.addEventListener('change', () => { set({ annotations: display.value as AnnotationDisplay }); });
  const unsubscribe = lanterna.onChange(refresh);
  refresh();
  return {
    element: section,
    destroy: () => {
      unsubscribe();
      section.remove();
    },
  };
}
