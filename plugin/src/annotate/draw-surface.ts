/**
 * The drawing surface: a transparent canvas of exactly the patch's pixel size, laid over the viewer
 * at the patch's rectangle and CSS-scaled, following the view when it moves (toolbar zoom, keys, a
 * resize). Pointer Events draw on it: mouse, pen (pressure → width) and touch, one pointer at a time.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { brushWidth } from './pen-width';
import { frameImageRect, rectOnScreen, toDrawing, type PatchFrame, type Rect } from './patch-frame';
import { visibleOperations, StrokeHistory, type Stroke, type StrokePoint, type StrokeTool } from './stroke-history';
import { copyCanvas, StrokeRenderer } from './stroke-render';

/** What the next stroke is drawn with. */
export interface Brush {
  readonly tool: StrokeTool;
  readonly color: string;
  /** Width in drawing (level) pixels. */
  readonly size: number;
  /** 0–1. */
  readonly opacity: number;
}

/** A drawing surface over the viewer. */
export interface DrawSurface {
  /** The canvas whose pixels are the patch. */
  readonly canvas: HTMLCanvasElement;
  readonly frame: PatchFrame;
  readonly history: StrokeHistory;
  /** Where the canvas is now, CSS px of the viewer element. */
  screenRect(): Rect;
  undo(): void;
  redo(): void;
  clear(): void;
  /** Forget the drawing (after an upload). */
  reset(): void;
  /** Take strokes or not (not while an upload is under way). */
  setEnabled(enabled: boolean): void;
  destroy(): void;
}

/**
 * Lay a surface for `frame` over `lanterna`'s viewer; `brush()` gives the current brush and
 * `changed()` is called after every change of the drawing (a stroke ended, undo, redo, clear).
 */
export function createDrawSurface(lanterna: Pick<LanternaViewer, 'viewer' | 'getState'>, frame: PatchFrame,
  brush: () => Brush, changed: () => void): DrawSurface {
  const host = lanterna.viewer.element;
  const canvas = document.createElement('canvas');
  canvas.className = 'lanterna-draw-surface';
  canvas.width = frame.width;
  canvas.height = frame.height;
  Object.assign(canvas.style, {
    position: 'absolute', left: '0', top: '0', zIndex: '4', touchAction: 'none', cursor: 'crosshair',
    outline: '1px dashed rgba(255, 215, 94, 0.9)', boxShadow: '0 0 0 1px rgba(0, 0, 0, 0.6)',
  });
  host.appendChild(canvas);
  const committed = document.createElement('canvas');
  committed.width = frame.width;
  committed.height = frame.height;
  const renderer = new StrokeRenderer(frame.width, frame.height);
  const history = new StrokeHistory();
  let rect: Rect = [0, 0, 1, 1];
  let enabled = true;

  const place = (): void => {
    const view = lanterna.getState().view;
    rect = rectOnScreen(frameImageRect(frame), view, host.clientWidth, host.clientHeight);
    Object.assign(canvas.style, {
      width: `${rect[2]}px`, height: `${rect[3]}px`, transform: `translate(${rect[0]}px, ${rect[1]}px)`,
    });
  };
  const redraw = (): void => {
    renderer.replay(committed, visibleOperations(history.operations));
    copyCanvas(canvas, committed);
  };

  let active: { id: number; points: StrokePoint[]; brush: Brush } | null = null;
  const pointOf = (e: PointerEvent, b: Brush): StrokePoint => {
    const box = canvas.getBoundingClientRect();
    const [x, y] = toDrawing(frame, [box.left, box.top, box.width, box.height], e.clientX, e.clientY);
    return { x, y, width: brushWidth(b.size, e.pointerType, e.pressure) };
  };
  const strokeOf = (a: NonNullable<typeof active>): Stroke => ({
    kind: 'stroke', tool: a.brush.tool, color: a.brush.color, opacity: a.brush.opacity, points: a.points,
  });
  const showActive = (): void => {
    if (active) {
      copyCanvas(canvas, committed);
      renderer.draw(canvas, strokeOf(active));
    }
  };
  const onDown = (e: PointerEvent): void => {
    if (!enabled || active || (e.pointerType === 'mouse' && e.button !== 0)) {
      return;
    }
    e.preventDefault();
    canvas.setPointerCapture(e.pointerId);
    const b = brush();
    active = { id: e.pointerId, points: [pointOf(e, b)], brush: b };
    showActive();
  };
  const onMove = (e: PointerEvent): void => {
    if (active?.id !== e.pointerId) {
      return;
    }
    e.preventDefault();
    const events = typeof e.getCoalescedEvents === 'function' ? e.getCoalescedEvents() : [];
    for (const ev of events.length > 0 ? events : [e]) {
      active.points.push(pointOf(ev, active.brush));
    }
    showActive();
  };
  const onUp = (e: PointerEvent): void => {
    if (active?.id !== e.pointerId) {
      return;
    }
    const done = active;
    active = null;
    if (e.type === 'pointercancel') {
      copyCanvas(canvas, committed);
      return;
    }
    history.push(strokeOf(done));
    redraw();
    changed();
  };
  canvas.addEventListener('pointerdown', onDown);
  canvas.addEventListener('pointermove', onMove);
  canvas.addEventListener('pointerup', onUp);
  canvas.addEventListener('pointercancel', onUp);
  const events = ['viewport-change', 'resize', 'animation', 'update-viewport'] as const;
  for (const name of events) {
    lanterna.viewer.addHandler(name, place);
  }
  place();

  const act = (f: () => unknown): void => {
    if (f() !== false) {
      redraw();
      changed();
    }
  };
  return {
    canvas, frame, history,
    screenRect: () => rect,
    undo: () => { act(() => history.undo()); },
    redo: () => { act(() => history.redo()); },
    clear: () => { act(() => history.push({ kind: 'clear' })); },
    reset: () => { act(() => { history.reset(); }); },
    setEnabled(on) {
      enabled = on;
      canvas.style.cursor = on ? 'crosshair' : 'progress';
    },
    destroy() {
      for (const name of events) {
        lanterna.viewer.removeHandler(name, place);
      }
      canvas.remove();
    },
  };
}
