/**
 * DOM helpers shared by the panel's sections: labelled rows, the layer and mode menus, sliders with
 * a value readout, and mounting a section that follows the viewer's changes.
 */
import type { LanternaViewer, LayerInfo } from '../api/viewer-api';
import { MODE_LABELS, type RenderMode } from '../render/modes';
import { layerLabels } from './layer-labels';

/** A section of the panel: its element and how to remove it. */
export interface PanelSection {
  readonly element: HTMLElement;
  destroy(): void;
}

/** A panel section: a fieldset of class `lanterna-controls NAME` whose legend is `title`. */
export function titledSection(name: string, title: string): HTMLFieldSetElement {
  const section = document.createElement('fieldset');
  section.className = `lanterna-controls ${name}`;
  const legend = document.createElement('legend');
  legend.textContent = title;
  section.append(legend);
  return section;
}

/** A `<label>` holding a caption and its control. */
/** A plain `<button type="button">` with a `name` (for tests and styles), a text and a tooltip. */
export function button(name: string, text: string, title: string): HTMLButtonElement {
  const b = document.createElement('button');
  b.type = 'button';
  b.name = name;
  b.textContent = text;
  b.title = title;
  return b;
}

export function labelled(text: string, control: HTMLElement): HTMLLabelElement {
  const label = document.createElement('label');
  const span = document.createElement('span');
  span.textContent = text;
  label.append(span, control);
  return label;
}

/** A `<select>` named `name` holding `options`. */
export function namedSelect(name: string, options: readonly HTMLOptionElement[] = []): HTMLSelectElement {
  const select = document.createElement('select');
  select.name = name;
  select.append(...options);
  return select;
}

/** One option per layer, valued by the layer id: its label (see `layer-labels.ts`), the type in the tooltip. */
export function layerOptions(layers: readonly LayerInfo[]): HTMLOptionElement[] {
  return layerLabels(layers).map(({ id, text, title }) => {
    const option = new Option(text, id);
    option.title = title;
    return option;
  });
}

/** One option per mode, labelled for menus. */
export function modeOptions(modes: readonly RenderMode[]): HTMLOptionElement[] {
  return modes.map((m) => new Option(MODE_LABELS[m], m));
}

/** A slider: a labelled range input followed by an `<output>` showing its value. */
export interface Slider {
  readonly row: HTMLLabelElement;
  readonly input: HTMLInputElement;
  readonly value: HTMLOutputElement;
}

/** Build a {@link Slider} named `name` over [min, max] in steps of `step`. */
export function slider(label: string, range: { name: string; min: number; max: number; step: number }): Slider {
  const input = document.createElement('input');
  Object.assign(input, {
    type: 'range', name: range.name, min: String(range.min), max: String(range.max), step: String(range.step),
  });
  const value = document.createElement('output');
  const row = labelled(label, input);
  row.append(value);
  return { row, input, value };
}

/**
 * Append a section's `element` to `parent` and keep it in line with the viewer: `refresh` runs now
 * and after every change. `destroy` stops that and removes the element.
 */
export function mountSection(lanterna: Pick<LanternaViewer, 'onChange'>, parent: HTMLElement, element: HTMLElement,
  refresh: () => void): PanelSection {
  parent.appendChild(element);
  const unsubscribe = lanterna.onChange(refresh);
  refresh();
  return {
    element,
    destroy: () => {
      unsubscribe();
      element.remove();
    },
  };
}
