/**
 * The measurement widget: while enabled, the drag mode is `measure` (a one-finger drag moves neither
 * the light nor the image) and a pointer hover (mouse, pen) or a one-finger drag (touch) shows, beside
 * the pointer and kept inside the viewer, the plot of {@link measureAt} with a caption.
 */
import type { LanternaViewer } from '../api/viewer-api';
import type { DragMode } from '../ui/interaction';
import { diskPixelOf } from '../math/reflectance-disk';
import { measurementCaption } from './caption';
import { measureAt } from './measure-at';
import { placeBeside } from './placement';
import type { Measurement } from './plot-of';
import { PlanePixels } from './plane-pixels';
import { plotRgba } from './plot-rgba';

/** Side of the plot on screen (CSS px). */
const PLOT_PX = 128;

/** A measurement widget (see {@link createMeasurement}). */
export interface MeasurementWidget {
  /** Turn the measurement mode on (drag mode `measure`) or off (the previous drag mode back). */
  setEnabled(on: boolean): void;
  isEnabled(): boolean;
  /** Measure at (x, y) CSS px of the viewer element and show it there (what a hover does). */
  measure(x: number, y: number): Promise<Measurement | null>;
  /** The measurement shown, if any. */
  current(): Measurement | null;
  /** Resolves once the measurements the pointer asked for so far are shown. */
  idle(): Promise<void>;
  /** The widget's element (hidden while nothing is shown). */
  readonly element: HTMLElement;
  destroy(): void;
}

function buildElement(): { root: HTMLElement; canvas: HTMLCanvasElement; caption: HTMLElement } {
  const root = document.createElement('div');
  root.className = 'lanterna-measure';
  root.hidden = true;
  root.setAttribute('role', 'status');
  Object.assign(root.style, {
    position: 'absolute', zIndex: '20', pointerEvents: 'none', padding: '6px', borderRadius: '6px',
    background: 'rgba(20, 20, 20, 0.85)', color: '#eee', font: '12px/1.3 system-ui, sans-serif', maxWidth: '220px',
  });
  const canvas = document.createElement('canvas');
  canvas.width = PLOT_PX;
  canvas.height = PLOT_PX;
  Object.assign(canvas.style, { display: 'block', width: `${PLOT_PX}px`, height: `${PLOT_PX}px` });
  const caption = document.createElement('div');
  caption.className = 'lanterna-measure-caption';
  root.append(canvas, caption);
  return { root, canvas, caption };
}

function draw(canvas: HTMLCanvasElement, m: Measurement): void {
  const context = canvas.getContext('2d');
  if (!context) {
    return;
  }
  const { width, height } = m.plot;
  const small = new OffscreenCanvas(width, height);
  small.getContext('2d')?.putImageData(new ImageData(plotRgba(m.kind, m.plot), width, height), 0, 0);
  context.clearRect(0, 0, canvas.width, canvas.height);
  context.imageSmoothingEnabled = m.kind === 'reflectance-disk';
  context.drawImage(small, 0, 0, canvas.width, canvas.height);
  if (m.kind === 'reflectance-disk') {
    const p = diskPixelOf(m.light.lu, m.light.lv, canvas.width);
    // the current light: a white ring in a dark one, visible on any colour
    for (const [style, width] of [['#000', 4], ['#fff', 2]] as const) {
      context.strokeStyle = style;
      context.lineWidth = width;
      context.beginPath();
      context.arc(p.x, p.y, 5, 0, 2 * Math.PI);
      context.stroke();
    }
  } else if (m.kind === 'brdf-slice') {
    // θh grows to the right, θd downwards (both 0–90°)
    context.font = '11px system-ui, sans-serif';
    context.strokeStyle = '#000';
    context.lineWidth = 3;
    context.fillStyle = '#fff';
    for (const [text, x, y] of [['θh →', canvas.width - 34, 12], ['θd ↓', 3, 28]] as const) {
      context.strokeText(text, x, y);
      context.fillText(text, x, y);
    }
  }
}

/**
 * Create the measurement widget of a viewer, inside `host` (the viewer's element by default).
 *
 * @example
 * ```ts
 * const measurement = createMeasurement(lanterna);
 * measurement.setEnabled(true);
 * ```
 */
export function createMeasurement(lanterna: LanternaViewer, host: HTMLElement = lanterna.viewer.element):
  MeasurementWidget {
  const { root, canvas, caption } = buildElement();
  host.append(root);
  const pixels = new PlanePixels();
  const element = lanterna.viewer.element;
  let enabled = false;
  let previous: DragMode = 'light';
  let shown: Measurement | null = null;
  let busy = false;
  let running: Promise<void> = Promise.resolve();
  let next: { x: number; y: number } | null = null;
  const touches = new Set<number>();

  const show = (m: Measurement | null, x: number, y: number): void => {
    shown = m;
    root.hidden = m === null || !enabled;
    if (!m) {
      return;
    }
    draw(canvas, m);
    caption.textContent = measurementCaption(m);
    const at = placeBeside(x, y, { w: root.offsetWidth, h: root.offsetHeight },
      { w: host.clientWidth, h: host.clientHeight });
    root.style.left = `${at.left}px`;
    root.style.top = `${at.top}px`;
  };
  const measure = async (x: number, y: number): Promise<Measurement | null> => {
    const m = await measureAt(lanterna, x, y, pixels);
    show(m, x, y);
    return m;
  };
  /** Measure at the latest point, one measurement at a time. */
  const request = (x: number, y: number): void => {
    next = { x, y };
    if (busy) {
      return;
    }
    busy = true;
    running = (async () => {
      while (next) {
        const p = next;
        next = null;
        try {
          await measure(p.x, p.y);
        } catch (error) {
          lanterna.reportError(error);
        }
      }
      busy = false;
    })();
  };
  const onMove = (ev: PointerEvent): void => {
    if (!enabled || (ev.pointerType === 'touch' && (!touches.has(ev.pointerId) || touches.size !== 1))) {
      return;
    }
    const r = element.getBoundingClientRect();
    request(ev.clientX - r.left, ev.clientY - r.top);
  };
  const onDown = (ev: PointerEvent): void => {
    if (ev.pointerType === 'touch') {
      touches.add(ev.pointerId);
    }
    onMove(ev);
  };
  const onUp = (ev: PointerEvent): void => { touches.delete(ev.pointerId); };
  const onLeave = (ev: PointerEvent): void => {
    if (ev.pointerType === 'mouse') {
      show(null, 0, 0);
    }
  };
  // A measurement of another layer is stale.
  const unsubscribe = lanterna.onChange(() => {
    if (shown && shown.layer !== lanterna.getActiveLayer()) {
      show(null, 0, 0);
    }
  });
  const listeners: [string, (ev: PointerEvent) => void][] = [['pointerdown', onDown], ['pointermove', onMove],
    ['pointerup', onUp], ['pointercancel', onUp], ['pointerleave', onLeave]];
  for (const [name, f] of listeners) {
    element.addEventListener(name, f as EventListener, { capture: true, passive: true });
  }

  return {
    element: root,
    setEnabled(on: boolean) {
      if (on === enabled) {
        return;
      }
      enabled = on;
      if (on) {
        previous = lanterna.getMode();
        lanterna.setMode('measure');
      } else {
        if (lanterna.getMode() === 'measure') {
          lanterna.setMode(previous === 'measure' ? 'light' : previous);
        }
        show(null, 0, 0);
      }
    },
    isEnabled: () => enabled,
    measure,
    current: () => shown,
    idle: () => running,
    destroy() {
      unsubscribe();
      for (const [name, f] of listeners) {
        element.removeEventListener(name, f as EventListener, { capture: true });
      }
      pixels.clear();
      root.remove();
    },
  };
}
