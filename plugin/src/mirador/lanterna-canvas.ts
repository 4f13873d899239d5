/**
 * Whether a Mirador window's canvas is one Lanterna relights, and its layers. Pure.
 *
 * Lanterna's viewer shows the manifest's first canvas with painting images (`iiif/manifest.ts`), so a
 * window gets it only on that canvas, when one of its painting images (a `Choice` item) carries a
 * `LanternaRelight` service. Every other canvas is left to Mirador's own viewer.
 */
import { findPaintingCanvas, parseManifest } from '../iiif/manifest';
import { isRecord, asArray } from '../iiif/json';
import { RELIGHT_SERVICE_TYPE } from '../iiif/relight-service';

/** One Lanterna layer: its id in our viewer and its painting image's id (Mirador's layer id). */
export interface CanvasLayer {
  readonly id: string;
  readonly imageId: string;
}

/** A canvas Lanterna relights. */
export interface LanternaCanvas {
  /** The manifest URL our viewer opens. */
  readonly manifestUrl: string;
  readonly canvasId: string;
  /** The canvas size (Mirador's coordinates). */
  readonly width: number;
  readonly height: number;
  /** The relightable layers in manifest order; empty when their blocks do not parse (the viewer then says why). */
  readonly layers: readonly CanvasLayer[];
}

/**
 * The Lanterna canvas of a manifest's JSON when `canvasId` is its first painting canvas and that
 * canvas has a `LanternaRelight` service; else null.
 */
export function lanternaCanvas(manifestUrl: string, manifest: unknown, canvasId: string | undefined):
  LanternaCanvas | null {
  let found;
  try {
    found = findPaintingCanvas(manifest);
  } catch {
    return null;
  }
  const { canvas, images } = found;
  const relit = images.some((image) => asArray(image.service)
    .some((s) => isRecord(s) && s.type === RELIGHT_SERVICE_TYPE));
  if (!relit || typeof canvas.id !== 'string' || (canvasId !== undefined && canvas.id !== canvasId)) {
    return null;
  }
  let layers: CanvasLayer[];
  try {
    layers = parseManifest(manifest).layers.map((l) => ({ id: l.id, imageId: l.imageId }));
  } catch {
    layers = [];
  }
  const size = (v: unknown): number => (typeof v === 'number' && Number.isFinite(v) && v > 0 ? v : 1);
  return { manifestUrl, canvasId: canvas.id, width: size(canvas.width), height: size(canvas.height), layers };
}
