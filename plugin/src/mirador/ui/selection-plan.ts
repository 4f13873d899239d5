/**
 * What the Lanterna view does when an annotation is selected in Mirador's annotation panel: the
 * steps, worked out purely from the annotation's target and what the viewer shows
 * (docs/mirador.md, "Controls and annotations").
 *
 * - a patch the viewer knows: `focusAnnotation` (its rectangle, with the render state it was drawn under), overlays on;
 * - an overlay level: its layer made active (when it is another), overlays on, the view fitted to the
 *   level drawing's region (the whole image when the annotation names none);
 * - a patch the viewer does not know, or any other annotation with a region: the view fitted to it.
 */
import type { PatchAnnotation } from '../../iiif/annotation-page';
import {
  annotationTarget, matchPatch, type Rect, type Size, toImageRegion,
} from './annotation-target';

/** One step, in order. */
export type SelectionStep =
  | { readonly step: 'focus'; readonly patch: string }
  | { readonly step: 'layer'; readonly layer: string }
  | { readonly step: 'overlays' }
  | { readonly step: 'region'; readonly region: Rect };

/** What the plan needs to know of the viewer. */
export interface ViewerFacts {
  /** The viewer's layer ids. */
  readonly layers: readonly string[];
  readonly activeLayer: string;
  /** The patches of every layer. */
  readonly patches: readonly Pick<PatchAnnotation, 'id' | 'imageUrl' | 'layer'>[];
  /** The image's size in pixels. */
  readonly image: Size;
  /** The canvas's size (null: the image's). */
  readonly canvas: Size | null;
}

/** The steps for selecting `annotation` (empty: nothing to do, e.g. no region and not one of ours). */
export function selectionPlan(annotation: unknown, facts: ViewerFacts): SelectionStep[] {
  const target = annotationTarget(annotation, facts.canvas);
  if (!target) {
    return [];
  }
  const fit = (region: Rect | null): SelectionStep[] => {
    const rect = toImageRegion(region, facts.canvas, facts.image);
    return rect ? [{ step: 'region', region: rect }] : [];
  };
  switch (target.kind) {
    case 'patch': {
      const patch = matchPatch(facts.patches, target);
      return patch ? [{ step: 'focus', patch }, { step: 'overlays' }] : fit(target.region);
    }
    case 'overlay': {
      if (!facts.layers.includes(target.layer)) {
        return fit(target.region);
      }
      const layer: SelectionStep[] = target.layer === facts.activeLayer ? [] : [{ step: 'layer', layer: target.layer }];
      return [...layer, { step: 'overlays' }, ...fit(target.region)];
    }
    case 'region':
      return fit(target.region);
  }
}

/** The viewer's patch to outline while Mirador's panel hovers `annotation` (null: none). */
export function hoverPatch(annotation: unknown, facts: Pick<ViewerFacts, 'patches'>): string | null {
  const target = annotationTarget(annotation);
  return target?.kind === 'patch' ? matchPatch(facts.patches, target) : null;
}
