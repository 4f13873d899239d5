/**
 * The content of the Lanterna companion window (docs/mirador.md): the viewer page's panel
 * sections (`panel/`, plain DOM over the public viewer API) for one window's Lanterna viewer —
 * what a drag does, the lens and annotation-overlay switches, the render mode and its parameter
 * sliders, the light (angles and raking buttons), the lens section and the presets.
 *
 * The layer menu of the mode section is hidden: Mirador's layers panel chooses the layer.
 */
import type { LanternaViewer } from '../../api/viewer-api';
import { createControls } from '../../panel/controls';
import { createLensControls } from '../../panel/lens-controls';
import { createLightTools } from '../../panel/light-tools';
import { labelled, mountSection, namedSelect, type PanelSection, titledSection } from '../../panel/panel-dom';
import { createPresetsPanel } from '../../panel/presets-panel';
import type { DragMode } from '../../ui/interaction';

/** Options of {@link mountControlsPanel}. */
export interface ControlsPanelOptions {
  /** The manifest's absolute URL (the presets section finds the authoring API from it). */
  readonly manifestUrl: string;
  /** Errors of the controls' actions. @default shown as the viewer's notices */
  readonly onError?: (error: unknown) => void;
}

const DRAG_LABELS: Readonly<Record<Exclude<DragMode, 'measure'>, string>> = {
  light: 'Moves the light', pan: 'Pans the view',
};

/** A checkbox row (`label.lanterna-check`) named `name`. */
function check(name: string, text: string, title: string): { row: HTMLLabelElement; input: HTMLInputElement } {
  const input = document.createElement('input');
  input.type = 'checkbox';
  input.name = name;
  const row = document.createElement('label');
  row.className = 'lanterna-check';
  row.title = title;
  row.append(input, ` ${text}`);
  return { row, input };
}

/** The "View" section: what a drag does, and the lens and annotation-overlay switches. */
function createViewSwitches(lanterna: LanternaViewer, parent: HTMLElement,
  onError: (error: unknown) => void): PanelSection {
  const section = titledSection('lanterna-mirador-view', 'View');
  const drag = namedSelect('drag', Object.entries(DRAG_LABELS).map(([mode, text]) => new Option(text, mode)));
  const lens = check('lens', 'Lens', 'Show the lens (drag it; its ring resizes it)');
  const overlays = check('overlays', 'Annotations', 'Show the annotation overlays of the current level');
  section.append(labelled('A drag', drag), lens.row, overlays.row);
  drag.addEventListener('change', () => { lanterna.setMode(drag.value as DragMode); });
  lens.input.addEventListener('change', () => {
    try {
      lanterna.setLens({ enabled: lens.input.checked }).catch(onError);
    } catch (error) {
      onError(error);
    }
  });
  overlays.input.addEventListener('change', () => { lanterna.setOverlaysVisible(overlays.input.checked); });
  const refresh = (): void => {
    const mode = lanterna.getMode();
    drag.value = mode === 'measure' ? 'pan' : mode;
    lens.input.checked = lanterna.getLens().enabled;
    const layers = lanterna.manifest?.layers ?? [];
    const here = layers.some((l) => l.id === lanterna.getActiveLayer() && l.overlays.length > 0);
    overlays.row.hidden = !layers.some((l) => l.overlays.length > 0);
    overlays.input.disabled = !here;
    overlays.input.checked = here && lanterna.getOverlaysVisible();
  };
  return mountSection(lanterna, parent, section, refresh);
}

/**
 * Build the panel into `parent` for a ready viewer; `destroy` removes every section and its
 * listeners (the viewer itself is left as it is).
 */
export function mountControlsPanel(lanterna: LanternaViewer, parent: HTMLElement,
  options: ControlsPanelOptions): PanelSection {
  const onError = options.onError ?? ((error: unknown) => { lanterna.reportError(error); });
  const element = document.createElement('div');
  element.className = 'lanterna-mirador-panel';
  parent.appendChild(element);
  const sections = [
    createViewSwitches(lanterna, element, onError),
    createControls(lanterna, element, onError),
    createLightTools(lanterna, element),
    createLensControls(lanterna, element, onError),
    createPresetsPanel(lanterna, element, { manifestUrl: options.manifestUrl, dropTarget: element, onError }),
  ];
  const layerMenu = sections[1]?.element.querySelector('select[name="layer"]')?.closest('label');
  if (layerMenu instanceof HTMLElement) {
    layerMenu.hidden = true;
  }
  return {
    element,
    destroy: () => {
      for (const section of sections) {
        section.destroy();
      }
      element.remove();
    },
  };
}
