/**
 * How the panel names layers in its menus: the layer's label alone, and the layer type as a short
 * suffix only where two layers share a label (the type and id are always in the option's tooltip).
 * Pure: no DOM.
 */
import type { LayerInfo } from '../api/viewer-api';

/** A menu entry of a layer. */
export interface LayerLabel {
  readonly id: string;
  /** What the menu shows. */
  readonly text: string;
  /** The tooltip: label, type and id. */
  readonly title: string;
}

/** The menu entries of `layers`, in order. */
export function layerLabels(layers: readonly Pick<LayerInfo, 'id' | 'label' | 'layerType'>[]): LayerLabel[] {
  const count = new Map<string, number>();
  for (const l of layers) {
    count.set(l.label, (count.get(l.label) ?? 0) + 1);
  }
  const texts = layers.map((l) => ((count.get(l.label) ?? 0) > 1 ? `${l.label} · ${l.layerType}` : l.label));
  return layers.map((l, i) => {
    const text = texts[i] ?? l.label;
    // Same label and same type: the id tells them apart.
    const shown = texts.filter((t) => t === text).length > 1 ? `${text} (${l.id})` : text;
    return { id: l.id, text: shown, title: `${l.label} — ${l.layerType} layer "${l.id}"` };
  });
}
