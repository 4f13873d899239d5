/**
 * Which annotation of Mirador's annotation panel is which Lanterna thing, and where it is: pure
 * functions over the annotation JSON Mirador holds (`annotations[canvasId][pageId].json`).
 *
 * - an overlay level (an `Image` body with a `LanternaOverlayLevel` block: layer, level);
 * - a patch (an `Image` body with a `LanternaPatch` block: its layer; the viewer knows it by the
 *   patch image's URL);
 * - any other annotation with an `xywh` region (a `FragmentSelector`, or `#xywh=` in the target).
 *
 * Regions are in canvas pixels, as targets are written; {@link toImageRegion} scales them to the
 * image's pixels when the canvas is not the image's size.
 */
import type { PatchAnnotation } from '../../iiif/annotation-page';
import { PATCH_SERVICE_TYPE } from '../../iiif/annotation-page';
import { asArray, isRecord, type Json } from '../../iiif/json';
import { OVERLAY_SERVICE_TYPE } from '../../iiif/overlays';

/** A rectangle: x, y, width, height. */
export type Rect = readonly [number, number, number, number];

/** A width and a height. */
export interface Size {
  readonly width: number;
  readonly height: number;
}

/** What selecting an annotation points at. `region` is null when its target names no region (the whole canvas). */
export type AnnotationTarget =
  | { readonly kind: 'overlay'; readonly layer: string; readonly level: number; readonly region: Rect | null }
  | { readonly kind: 'patch'; readonly layer: string; readonly imageUrl: string; readonly region: Rect | null }
  | { readonly kind: 'region'; readonly region: Rect };

const XYWH = /(?:^|[#&?])xywh=(?:(pixel|percent):)?([^&]*)$/;

/**
 * The rectangle of a media fragment `xywh=[pixel:|percent:]x,y,w,h` (the whole string, or its
 * `#xywh=…` part); `percent:` needs the canvas size. Null when there is none, or it is malformed or empty.
 */
export function parseXywh(fragment: string, canvas: Size | null = null): Rect | null {
  const match = XYWH.exec(fragment.trim());
  if (!match) {
    return null;
  }
  const values = (match[2] ?? '').split(',').map((s) => (s.trim() === '' ? NaN : Number(s)));
  if (values.length !== 4 || !values.every(Number.isFinite)) {
    return null;
  }
  const [x, y, w, h] = values as [number, number, number, number];
  if (w <= 0 || h <= 0) {
    return null;
  }
  if (match[1] !== 'percent') {
    return [x, y, w, h];
  }
  if (!canvas) {
    return null;
  }
  const sx = canvas.width / 100;
  const sy = canvas.height / 100;
  return [x * sx, y * sy, w * sx, h * sy];
}

/**
 * The region of an annotation's (first) target: a `canvas#xywh=…` string, or a resource whose
 * `selector` (one or a list) has a `FragmentSelector` with an `xywh` value. Null: no region.
 */
export function targetRegion(annotation: unknown, canvas: Size | null = null): Rect | null {
  if (!isRecord(annotation)) {
    return null;
  }
  for (const target of asArray(annotation.target)) {
    if (typeof target === 'string') {
      const region = target.includes('#') ? parseXywh(target.slice(target.indexOf('#')), canvas) : null;
      if (region) {
        return region;
      }
      continue;
    }
    if (!isRecord(target)) {
      continue;
    }
    for (const selector of asArray(target.selector)) {
      if (isRecord(selector) && selector.type === 'FragmentSelector' && typeof selector.value === 'string') {
        const region = parseXywh(selector.value, canvas);
        if (region) {
          return region;
        }
      }
    }
    if (typeof target.id === 'string' && target.id.includes('#')) {
      const region = parseXywh(target.id.slice(target.id.indexOf('#')), canvas);
      if (region) {
        return region;
      }
    }
  }
  return null;
}

/** The first `Image` body of an annotation with a service block of `type`, and that block. */
function imageBlock(annotation: Json, type: string): { image: Json; block: Json } | null {
  for (const image of asArray(annotation.body)) {
    if (!isRecord(image) || image.type !== 'Image') {
      continue;
    }
    const block = asArray(image.service).find((s) => isRecord(s) && s.type === type);
    if (isRecord(block)) {
      return { image, block };
    }
  }
  return null;
}

/**
 * What an annotation points at (see the module's comment), or null when it is neither one of ours
 * nor has a region.
 */
export function annotationTarget(annotation: unknown, canvas: Size | null = null): AnnotationTarget | null {
  if (!isRecord(annotation)) {
    return null;
  }
  const region = targetRegion(annotation, canvas);
  const overlay = imageBlock(annotation, OVERLAY_SERVICE_TYPE);
  if (overlay) {
    const { layer, level } = overlay.block;
    if (typeof layer === 'string' && layer !== '' && typeof level === 'number' && Number.isInteger(level)
      && level >= 0) {
      return { kind: 'overlay', layer, level, region };
    }
  }
  const patch = imageBlock(annotation, PATCH_SERVICE_TYPE);
  if (patch) {
    const { layer } = patch.block;
    if (typeof layer === 'string' && layer !== '' && typeof patch.image.id === 'string') {
      return { kind: 'patch', layer, imageUrl: patch.image.id, region };
    }
  }
  return region ? { kind: 'region', region } : null;
}

/** The annotation of id `id` among the items of annotation pages (Mirador's page JSONs), or null. */
export function findAnnotation(pages: readonly unknown[], id: string): Json | null {
  for (const page of pages) {
    if (!isRecord(page)) {
      continue;
    }
    for (const item of asArray(page.items)) {
      if (isRecord(item) && item.id === id) {
        return item;
      }
    }
  }
  return null;
}

/** The id of the viewer's patch a `patch` target is (its image URL), or null when the viewer does not know it. */
export function matchPatch(patches: readonly Pick<PatchAnnotation, 'id' | 'imageUrl' | 'layer'>[],
  target: Extract<AnnotationTarget, { kind: 'patch' }>): string | null {
  return patches.find((p) => p.layer === target.layer && p.imageUrl === target.imageUrl)?.id ?? null;
}

/** The size of the canvas `canvasId` of a Presentation 3 manifest, or null when it has none. */
export function canvasSize(manifest: unknown, canvasId: string): Size | null {
  if (!isRecord(manifest)) {
    return null;
  }
  const canvas = asArray(manifest.items).find((c) => isRecord(c) && c.id === canvasId);
  if (!isRecord(canvas)) {
    return null;
  }
  const { width, height } = canvas;
  return typeof width === 'number' && typeof height === 'number' && width > 0 && height > 0
    ? { width, height } : null;
}

/**
 * A canvas-pixel rectangle in image pixels (the image stretched over the canvas), clipped to the
 * image; the whole image for `region` null. Null when nothing of it is on the image.
 */
export function toImageRegion(region: Rect | null, canvas: Size | null, image: Size): Rect | null {
  if (!region) {
    return [0, 0, image.width, image.height];
  }
  const sx = canvas ? image.width / canvas.width : 1;
  const sy = canvas ? image.height / canvas.height : 1;
  const x0 = Math.max(0, region[0] * sx);
  const y0 = Math.max(0, region[1] * sy);
  const x1 = Math.min(image.width, (region[0] + region[2]) * sx);
  const y1 = Math.min(image.height, (region[1] + region[3]) * sy);
  return x1 > x0 && y1 > y0 ? [x0, y0, x1 - x0, y1 - y0] : null;
}
