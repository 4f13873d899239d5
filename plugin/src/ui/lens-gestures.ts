/**
 * The pointer layer of the lens: it tracks the contacts of each gesture on the viewer's canvas
 * (mouse, touch, pen), decides what the gesture drives with {@link routeGesture}, moves and sizes
 * the lens itself, and suppresses OpenSeadragon's default action (pan, pinch, wheel zoom) for
 * gestures that belong to the lens.
 */
import type OpenSeadragon from 'openseadragon';
import {
  lensHit, moveLens, resizeLensTo, scaleLens, twoFingerLens, wheelFactor, type Circle, type LensHit,
} from '../math/lens';
import { isLensAction, routeGesture, routeWheel, type GestureAction } from './gesture-routing';
import type { DragMode } from './interaction';

/** Options of {@link attachLensGestures}. */
export interface LensGestureOptions {
  /** The lens as a circle, or null when it is off. */
  getLens(): Circle | null;
  /** Move or resize the lens (CSS px of the viewer element). */
  setLens(circle: Circle): void;
  /** What a plain drag does outside the lens. */
  getDragMode(): DragMode;
}

/** The running pointer layer. */
export interface LensGestures {
  /** The current gesture's action ('none' between gestures). */
  action(): GestureAction;
  /** True while a gesture belongs to the lens, or is a pinch's leftover contact: no light, no pan. */
  claimed(): boolean;
  destroy(): void;
}

interface Contact {
  x: number;
  y: number;
}

interface PinchArgs {
  preventDefaultPanAction?: boolean;
  preventDefaultZoomAction?: boolean;
  preventDefaultRotateAction?: boolean;
}

interface ScrollArgs {
  position: OpenSeadragon.Point;
  scroll: number;
  preventDefaultAction?: boolean;
}

interface ClickArgs {
  position: OpenSeadragon.Point;
  preventDefaultAction?: boolean;
}

function pair(contacts: Map<number, Contact>): { x: number; y: number; distance: number } | null {
  const [a, b] = [...contacts.values()];
  return a && b ? { x: (a.x + b.x) / 2, y: (a.y + b.y) / 2, distance: Math.hypot(a.x - b.x, a.y - b.y) } : null;
}

/** Install the pointer layer on `viewer`; returns its handle. */
export function attachLensGestures(viewer: OpenSeadragon.Viewer, options: LensGestureOptions): LensGestures {
  const element = viewer.element;
  const canvas = viewer.canvas;
  const contacts = new Map<number, Contact>();
  let action: GestureAction = 'none';
  let lastPair: { x: number; y: number; distance: number } | null = null;

  const local = (e: PointerEvent | MouseEvent): Contact => {
    const rect = element.getBoundingClientRect();
    return { x: e.clientX - rect.left, y: e.clientY - rect.top };
  };
  const hitAt = (p: Contact): LensHit | null => {
    const lens = options.getLens();
    return lens ? lensHit(lens, p.x, p.y) : null;
  };
  const onCanvas = (e: Event): boolean => e.target instanceof Node && canvas.contains(e.target);

  const onDown = (e: PointerEvent): void => {
    if (!onCanvas(e)) {
      return;
    }
    if (e.pointerType === 'mouse' || contacts.has(e.pointerId)) {
      // A mouse has one contact: anything left over is stale (a release we did not see).
      for (const [id] of contacts) {
        if (id === e.pointerId || e.pointerType === 'mouse') {
          contacts.delete(id);
        }
      }
    }
    const fresh = contacts.size === 0;
    const p = local(e);
    contacts.set(e.pointerId, p);
    const two = pair(contacts);
    const at = contacts.size >= 2 && two ? two : p;
    action = routeGesture({
      contacts: contacts.size, hit: hitAt(at), button: e.button, shift: e.shiftKey,
      dragMode: options.getDragMode(), previous: fresh ? null : action,
    });
    lastPair = two;
  };

  const onMove = (e: PointerEvent): void => {
    const before = contacts.get(e.pointerId);
    if (!before) {
      if (onCanvas(e) && e.pointerType !== 'touch') {
        const hit = hitAt(local(e));
        canvas.style.cursor = hit === 'inside' ? 'move' : hit === 'border' ? 'nwse-resize' : '';
      }
      return;
    }
    const p = local(e);
    contacts.set(e.pointerId, p);
    const lens = options.getLens();
    if (!lens) {
      return;
    }
    if (action === 'lens-move' && contacts.size === 1) {
      options.setLens(moveLens(lens, p.x - before.x, p.y - before.y));
    } else if (action === 'lens-resize' && contacts.size === 1) {
      options.setLens(resizeLensTo(lens, p.x, p.y));
    } else if (action === 'lens-transform') {
      const now = pair(contacts);
      if (now && lastPair) {
        options.setLens(twoFingerLens(lens, lastPair, now));
      }
      lastPair = now;
    }
  };

  const onUp = (e: PointerEvent): void => {
    if (!contacts.delete(e.pointerId)) {
      return;
    }
    if (contacts.size === 0) {
      action = 'none';
      lastPair = null;
      return;
    }
    const [rest] = [...contacts.values()];
    action = routeGesture({
      contacts: contacts.size, hit: rest ? hitAt(rest) : null, dragMode: options.getDragMode(), previous: action,
    });
    lastPair = pair(contacts);
  };

  const onPinch = (e: PinchArgs): void => {
    if (action === 'lens-transform') {
      e.preventDefaultPanAction = true;
      e.preventDefaultZoomAction = true;
      e.preventDefaultRotateAction = true;
    }
  };
  const onScroll = (e: ScrollArgs): void => {
    const lens = options.getLens();
    if (lens && routeWheel(lensHit(lens, e.position.x, e.position.y)) === 'lens-resize') {
      e.preventDefaultAction = true;
      options.setLens(scaleLens(lens, wheelFactor(e.scroll)));
    }
  };
  const onDoubleClick = (e: ClickArgs): void => {
    const lens = options.getLens();
    if (lens && lensHit(lens, e.position.x, e.position.y) !== 'outside') {
      e.preventDefaultAction = true;
    }
  };

  const listeners: [string, (e: PointerEvent) => void][] = [
    ['pointerdown', onDown], ['pointermove', onMove], ['pointerup', onUp], ['pointercancel', onUp],
  ];
  for (const [type, fn] of listeners) {
    element.addEventListener(type, fn as EventListener, { capture: true });
  }
  type Handler = (e: PinchArgs & ScrollArgs & ClickArgs) => void;
  const handlers: [string, Handler][] = [
    ['canvas-pinch', onPinch], ['canvas-scroll', onScroll], ['canvas-double-click', onDoubleClick],
  ];
  const add = viewer.addHandler.bind(viewer) as unknown as (name: string, h: Handler) => void;
  const remove = viewer.removeHandler.bind(viewer) as unknown as (name: string, h: Handler) => void;
  for (const [name, h] of handlers) {
    add(name, h);
  }
  return {
    action: () => action,
    claimed: () => isLensAction(action) || (action === 'none' && contacts.size > 0),
    destroy() {
      for (const [type, fn] of listeners) {
        element.removeEventListener(type, fn as EventListener, { capture: true });
      }
      for (const [name, h] of handlers) {
        remove(name, h);
      }
      contacts.clear();
    },
  };
}
