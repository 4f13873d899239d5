/**
 * Keeps one Mirador window and its Lanterna viewer in step, both ways: the viewport (Mirador's
 * `viewers[windowId]`, e.g. its zoom buttons ↔ our pans and zooms, sent on OpenSeadragon's
 * `animation` events at most every {@link SEND_INTERVAL_MS} and once more at `animation-finish`) and
 * the layers (Mirador's layers panel picks our active layer and its opacity; a layer chosen in our
 * viewer becomes Mirador's top visible layer). A change is passed on only when the other side does
 * not show it already, so nothing echoes back.
 */
import type { LanternaViewer } from '../api/viewer-api';
import type { LanternaCanvas } from './lanterna-canvas';
import { payloadForActive, topVisibleLayer } from './layer-map';
import type { MiradorCanvasLayers, MiradorViewport } from './types';
import { imageRectToViewport, isViewport, sameViewport, viewportToImageRect, type Size } from './viewport-map';

/** The shortest time between two viewport updates sent to Mirador while our view moves. */
export const SEND_INTERVAL_MS = 150;

/** What the sync dispatches into Mirador's store. */
export interface MiradorDispatch {
  updateViewport(windowId: string, payload: MiradorViewport): void;
  updateLayers(windowId: string, canvasId: string, payload: MiradorCanvasLayers): void;
}

export class WindowSync {
  private mirador: MiradorViewport | null = null;
  /** The viewport we sent last: when Mirador hands it back, our view may have moved on since. */
  private sent: MiradorViewport | null = null;
  private layers: MiradorCanvasLayers | undefined;
  private lastActive: string;
  private requested = '';
  private lastSent = 0;
  private timer: ReturnType<typeof setTimeout> | null = null;
  private readonly unsubscribe: () => void;
  private readonly image: Size;

  constructor(private readonly lanterna: LanternaViewer, private readonly element: HTMLElement,
    private readonly windowId: string, private readonly canvas: LanternaCanvas,
    private readonly dispatch: MiradorDispatch) {
    const layer = lanterna.manifest?.layer;
    this.image = { width: layer?.width ?? canvas.width, height: layer?.height ?? canvas.height };
    this.lastActive = lanterna.getActiveLayer();
    lanterna.viewer.addHandler('animation', this.onMove);
    lanterna.viewer.addHandler('animation-finish', this.onSettled);
    this.unsubscribe = lanterna.onChange(this.onLanternaChange);
  }

  /** Mirador's viewport changed (or is first known): show it, or tell Mirador ours when it has none. */
  fromMirador(viewport: Partial<MiradorViewport> | null | undefined): void {
    if (!isViewport(viewport)) {
      this.mirador = null;
      this.send();
      return;
    }
    this.mirador = { x: viewport.x, y: viewport.y, zoom: viewport.zoom };
    if (this.sent && sameViewport(this.sent, this.mirador)) {
      return;
    }
    const ours = this.ourViewport();
    const aspect = this.element.clientWidth / this.element.clientHeight;
    if ((ours && sameViewport(ours, this.mirador)) || !(aspect > 0 && Number.isFinite(aspect))) {
      return;
    }
    this.sent = null;
    const [x, y, w, h] = viewportToImageRect(this.mirador, this.canvas, this.image, aspect);
    this.lanterna.showImageRegion(x, y, w, h);
  }

  /** Mirador's layer state changed: show its top visible layer at its opacity (none visible: nothing). */
  fromMiradorLayers(layers: MiradorCanvasLayers | undefined): void {
    this.layers = layers;
    const top = topVisibleLayer(this.imageIds(), layers);
    this.element.style.opacity = String(top ? top.opacity : 0);
    const id = this.canvas.layers.find((l) => l.imageId === top?.imageId)?.id;
    if (id !== undefined && id !== this.lanterna.getActiveLayer() && id !== this.requested) {
      this.requested = id;
      this.lanterna.setActiveLayer(id).catch((e: unknown) => { this.lanterna.reportError(e); });
    }
  }

  /** Fit the whole image in view (Mirador's "reset zoom"). */
  zoomToWorld(): void {
    this.lanterna.showImageRegion(0, 0, this.image.width, this.image.height);
  }

  destroy(): void {
    this.lanterna.viewer.removeHandler('animation', this.onMove);
    this.lanterna.viewer.removeHandler('animation-finish', this.onSettled);
    this.unsubscribe();
    if (this.timer !== null) {
      clearTimeout(this.timer);
      this.timer = null;
    }
  }

  private imageIds(): string[] {
    return this.canvas.layers.map((l) => l.imageId);
  }

  private ourViewport(): MiradorViewport | null {
    const view = this.lanterna.getState().view;
    return view[2] > 0 && view[3] > 0 ? imageRectToViewport(view, this.canvas, this.image) : null;
  }

  private readonly onMove = (): void => {
    const wait = this.lastSent + SEND_INTERVAL_MS - Date.now();
    if (wait <= 0) {
      this.send();
    } else if (this.timer === null) {
      this.timer = setTimeout(() => { this.send(); }, wait);
    }
  };

  private readonly onSettled = (): void => {
    this.send();
  };

  /** Tell Mirador our viewport, unless it shows it already. */
  private send(): void {
    if (this.timer !== null) {
      clearTimeout(this.timer);
      this.timer = null;
    }
    const ours = this.ourViewport();
    if (!ours || (this.mirador && sameViewport(ours, this.mirador))) {
      return;
    }
    this.mirador = ours;
    this.sent = ours;
    this.lastSent = Date.now();
    this.dispatch.updateViewport(this.windowId, ours);
  }

  /** Our active layer changed (not at Mirador's request): make it Mirador's top visible layer. */
  private readonly onLanternaChange = (): void => {
    const active = this.lanterna.getActiveLayer();
    if (active === this.lastActive) {
      return;
    }
    this.lastActive = active;
    if (active === this.requested) {
      this.requested = '';
      return;
    }
    const imageId = this.canvas.layers.find((l) => l.id === active)?.imageId;
    const payload = imageId === undefined ? null : payloadForActive(this.imageIds(), this.layers, imageId);
    if (payload) {
      this.dispatch.updateLayers(this.windowId, this.canvas.canvasId, payload);
    }
  };
}
