/**
 * The scale bar: a round physical length ({@link chooseScaleBar}) drawn at its true on-screen length,
 * bottom left (right of the light widget), redrawn on every viewport change. Only when the manifest
 * has a physical scale (its canvas's IIIF physdim service).
 */
import type { LanternaViewer } from '../api/viewer-api';
import { chooseScaleBar } from '../math/scale-bar';
import { addToolStyles } from './tool-styles';

/** The bar's DOM and its controls. */
export interface ScaleBarWidget {
  readonly element: HTMLElement;
  /** Redraw for the current view (done on every viewport change). */
  update(): void;
  destroy(): void;
}

/** Longest bar, CSS px (and at most a third of the viewer's width). */
const MAX_PX = 160;

/** Create the bar in the viewer's element; it shows once the manifest says the physical scale. */
export function createScaleBar(lanterna: LanternaViewer): ScaleBarWidget {
  addToolStyles();
  const viewer = lanterna.viewer;
  const element = document.createElement('div');
  element.className = 'lanterna-scale-bar';
  element.setAttribute('role', 'img');
  element.hidden = true;
  const bar = document.createElement('div');
  bar.className = 'lanterna-scale-bar-line';
  const label = document.createElement('span');
  label.className = 'lanterna-scale-bar-label';
  element.append(label, bar);
  viewer.element.append(element);
  const widget = viewer.element.querySelector<HTMLElement>('.lanterna-light-widget');
  element.style.left = widget ? `${widget.offsetLeft + widget.offsetWidth + 12}px` : '12px';

  const update = (): void => {
    const physical = lanterna.manifest?.physicalScale ?? null;
    const width = lanterna.manifest?.layer.width ?? 0;
    const container = viewer.viewport.getContainerSize();
    // CSS px per image px: the image is 1 viewport unit wide, and zoom 1 fits a unit to the width.
    const perImage = (viewer.viewport.getZoom(true) * container.x) / width;
    const chosen = physical ? chooseScaleBar(physical.scale, physical.units, perImage, Math.min(MAX_PX, container.x / 3))
      : null;
    element.hidden = chosen === null;
    if (chosen) {
      bar.style.width = `${chosen.px}px`;
      label.textContent = chosen.label;
      element.setAttribute('aria-label', `Scale bar: ${chosen.label}`);
      element.dataset.length = String(chosen.value);
      element.dataset.unit = chosen.unit;
    }
  };
  const events = ['viewport-change', 'update-viewport', 'resize', 'open'] as const;
  for (const name of events) {
    viewer.addHandler(name, update);
  }
  lanterna.ready.then(update, () => undefined);
  return {
    element,
    update,
    destroy() {
      for (const name of events) {
        viewer.removeHandler(name, update);
      }
      element.remove();
    },
  };
}
