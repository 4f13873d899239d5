/**
 * Pointer interaction on the viewer: a plain drag moves the light (or pans, in pan mode),
 * Shift+drag does the other; in measure mode a primary drag does neither; right- or middle-drag
 * always pans; wheel and pinch zoom (OSD default). A pinch leaves the light where it was: its first
 * finger starts a light drag, undone when the second finger lands.
 */
import OpenSeadragon from 'openseadragon';
import { lightFromPointer, type Light } from '../math/light';

/**
 * What a plain primary-button (or one-finger) drag does: move the light, pan, or nothing (`measure`:
 * the measurement widget follows the pointer, measure/measure-widget.ts).
 */
export type DragMode = 'light' | 'pan' | 'measure';

/** Options of {@link attachInteraction}. */
export interface InteractionOptions {
  /** Current drag mode. */
  getMode(): DragMode;
  /** Called with the light under the pointer (its position in the viewer element, {@link lightFromPointer}). */
  setLight(light: Light): void;
  /** The light now (restored when a second finger turns a one-finger light drag into a pinch). */
  getLight(): Light;
  /** True while another handler (the lens) owns the current gesture: no light, no pan. */
  claimed?(): boolean;
}

interface PointerEventArgs {
  position: OpenSeadragon.Point;
  shift?: boolean;
  button?: number;
  originalEvent?: Event;
  preventDefaultAction?: boolean;
}

/**
 * Install the handlers; returns a function removing them.
 */
export function attachInteraction(viewer: OpenSeadragon.Viewer, options: InteractionOptions): () => void {
  const element = viewer.element;
  const drivesLight = (shift: boolean): boolean => (options.getMode() === 'light') !== shift;
  const shiftOf = (e: PointerEventArgs): boolean =>
    e.shift ?? (e.originalEvent instanceof MouseEvent ? e.originalEvent.shiftKey : false);
  let lightDrag = false;
  // The light before the current light drag: a second finger landing makes the gesture a pinch,
  // whose first finger must not have moved the light (fingers land one after the other).
  let lightBefore: Light | null = null;
  const touches = new Set<number>();

  const light = (e: PointerEventArgs): void => {
    options.setLight(lightFromPointer(e.position.x, e.position.y, element.clientWidth, element.clientHeight));
  };
  // In measure mode a primary drag is the measurement's, as a lens gesture is the lens's.
  const claimed = (): boolean => options.getMode() === 'measure' || (options.claimed?.() ?? false);
  const onPress = (e: PointerEventArgs): void => {
    if (claimed()) {
      lightDrag = false;
      lightBefore = null;
      e.preventDefaultAction = true;
      return;
    }
    lightDrag = drivesLight(shiftOf(e));
    lightBefore = lightDrag ? options.getLight() : null;
    if (lightDrag) {
      light(e);
    }
  };
  const onTouchDown = (ev: PointerEvent): void => {
    if (ev.pointerType !== 'touch') {
      return;
    }
    touches.add(ev.pointerId);
    if (touches.size >= 2 && lightBefore) {
      options.setLight(lightBefore);
      lightBefore = null;
      lightDrag = false;
    }
  };
  const onTouchUp = (ev: PointerEvent): void => {
    touches.delete(ev.pointerId);
    if (touches.size === 0) {
      lightBefore = null;
    }
  };
  const onDrag = (e: PointerEventArgs): void => {
    if (claimed()) {
      e.preventDefaultAction = true;
      return;
    }
    if (lightDrag || drivesLight(shiftOf(e))) {
      e.preventDefaultAction = true;
      light(e);
    }
  };
  const onDragEnd = (e: PointerEventArgs): void => {
    if (lightDrag || claimed()) {
      e.preventDefaultAction = true; // no flick
    }
  };
  const onClick = (e: PointerEventArgs): void => {
    if (lightDrag || claimed()) {
      e.preventDefaultAction = true; // no click-to-zoom while lighting
    }
  };

  // Right/middle drag pans, in either mode.
  let panFrom: { x: number; y: number } | null = null;
  const onPanMove = (ev: PointerEvent): void => {
    if (!panFrom) {
      return;
    }
    const delta = new OpenSeadragon.Point(panFrom.x - ev.clientX, panFrom.y - ev.clientY);
    panFrom = { x: ev.clientX, y: ev.clientY };
    viewer.viewport.panBy(viewer.viewport.deltaPointsFromPixels(delta, true), true);
  };
  const onPanEnd = (): void => {
    panFrom = null;
    window.removeEventListener('pointermove', onPanMove);
    window.removeEventListener('pointerup', onPanEnd);
    viewer.viewport.applyConstraints();
  };
  const onNonPrimaryPress = (e: PointerEventArgs): void => {
    if ((e.button === 1 || e.button === 2) && e.originalEvent instanceof PointerEvent) {
      panFrom = { x: e.originalEvent.clientX, y: e.originalEvent.clientY };
      window.addEventListener('pointermove', onPanMove);
      window.addEventListener('pointerup', onPanEnd);
    }
  };
  const onContextMenu = (ev: Event): void => { ev.preventDefault(); };

  const handlers: [string, (e: PointerEventArgs) => void][] = [
    ['canvas-press', onPress],
    ['canvas-drag', onDrag],
    ['canvas-drag-end', onDragEnd],
    ['canvas-click', onClick],
    ['canvas-nonprimary-press', onNonPrimaryPress],
  ];
  const add = viewer.addHandler.bind(viewer) as (name: string, h: (e: PointerEventArgs) => void) => void;
  const remove = viewer.removeHandler.bind(viewer) as (name: string, h: (e: PointerEventArgs) => void) => void;
  for (const [name, h] of handlers) {
    add(name, h);
  }
  element.addEventListener('contextmenu', onContextMenu);
  const touchListeners: [string, (ev: PointerEvent) => void][] = [
    ['pointerdown', onTouchDown], ['pointerup', onTouchUp], ['pointercancel', onTouchUp],
  ];
  for (const [type, fn] of touchListeners) {
    element.addEventListener(type, fn as EventListener, { capture: true });
  }
  return () => {
    for (const [type, fn] of touchListeners) {
      element.removeEventListener(type, fn as EventListener, { capture: true });
    }
    for (const [name, h] of handlers) {
      remove(name, h);
    }
    element.removeEventListener('contextmenu', onContextMenu);
    onPanEnd();
  };
}
