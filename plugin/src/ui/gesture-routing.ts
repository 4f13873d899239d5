/**
 * Which action a pointer gesture drives, decided when the gesture starts or changes its number of
 * contacts (`docs/annotations.md`, "Gestures"). Pure: no DOM.
 *
 * | contacts | starts on the lens   | elsewhere                                         |
 * |----------|----------------------|---------------------------------------------------|
 * | 1        | inside → move lens, border → resize lens | light (or pan: drag mode, Shift) |
 * | 2        | move and scale lens  | pan and zoom the image (pinch)                    |
 * | wheel    | resize lens          | zoom the image                                    |
 *
 * Right- and middle-button drags always pan. A gesture keeps its two-contact action until every
 * contact is lifted (lifting one finger of a pinch does not start a light drag).
 */
import type { LensHit } from '../math/lens';
import type { DragMode } from './interaction';

/** What a gesture does. */
export type GestureAction =
  | 'lens-move' | 'lens-resize' | 'lens-transform'
  | 'light' | 'pan' | 'image-pinch' | 'image-zoom' | 'none';

/** A gesture at a change of its contact count. */
export interface GestureStart {
  /** Contacts now down (1 or 2; more are treated as 2). */
  readonly contacts: number;
  /** Where it started relative to the lens: the first contact, or the midpoint of two; `null` = no lens. */
  readonly hit: LensHit | null;
  /** Mouse button of a one-contact gesture (0 primary, 1 middle, 2 right). @default 0 */
  readonly button?: number;
  /** Shift held. @default false */
  readonly shift?: boolean;
  /** What a plain drag does outside the lens. */
  readonly dragMode: DragMode;
  /** The action so far in this gesture (before the contact count changed), if any. */
  readonly previous?: GestureAction | null;
}

/** Actions that belong to the lens (OpenSeadragon's default for the gesture must be suppressed). */
export function isLensAction(action: GestureAction): boolean {
  return action === 'lens-move' || action === 'lens-resize' || action === 'lens-transform';
}

/** The action of a pointer gesture. */
export function routeGesture(g: GestureStart): GestureAction {
  if (g.contacts <= 0) {
    return 'none';
  }
  if (g.contacts >= 2) {
    return g.hit === 'inside' || g.hit === 'border' ? 'lens-transform' : 'image-pinch';
  }
  // One contact left after a two-contact gesture: nothing until every contact is up.
  if (g.previous === 'lens-transform' || g.previous === 'image-pinch' || g.previous === 'none') {
    return 'none';
  }
  if (g.button === 1 || g.button === 2) {
    return 'pan';
  }
  if (g.hit === 'inside') {
    return 'lens-move';
  }
  if (g.hit === 'border') {
    return 'lens-resize';
  }
  return (g.dragMode === 'light') !== (g.shift ?? false) ? 'light' : 'pan';
}

/** The action of a wheel step at a point. */
export function routeWheel(hit: LensHit | null): GestureAction {
  return hit === 'inside' || hit === 'border' ? 'lens-resize' : 'image-zoom';
}
