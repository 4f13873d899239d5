/**
 * The draw plan of a layer's overlay at a level (`docs/annotations.md`, "Toggling patches"): what
 * the overlay pass draws so that the picture is the level's pyramid minus the hidden patches. Pure:
 * no DOM, no OpenSeadragon.
 *
 * While no patch of the level is hidden, the level's pyramid (the tiler's composite of all its
 * patches) is drawn as it always was. Once one is, the pyramid is not drawn; the level's visible
 * patches are drawn instead from their own images, each at its destination rectangle
 * (docs/annotations.md, "Building" and "Placement"), in application order, premultiplied
 * source-over — the same sum the tiler makes, without the hidden ones.
 */
import { applicationOrder, type PatchAnnotation } from '../iiif/annotation-page';
import { overlayAt, type OverlayLevel } from '../iiif/overlays';

/** A rectangle in OpenSeadragon viewport units (the canvas is 1 unit wide, at x = y = 0). */
export interface ViewportRect {
  readonly x: number;
  readonly y: number;
  readonly width: number;
  readonly height: number;
}

/** The level's pyramid, drawn whole. */
export interface PlannedLevel {
  readonly kind: 'level';
  /** Identifies the item across plans: the same key is the same picture at the same place. */
  readonly key: string;
  readonly level: OverlayLevel;
  readonly rect: ViewportRect;
  /** Drawing order among the overlay items (lowest first). */
  readonly order: number;
}

/** A rectangle in pixels. */
export interface PixelBox {
  readonly x: number;
  readonly y: number;
  readonly width: number;
  readonly height: number;
}

/** One patch, drawn from its own image. */
export interface PlannedPatch {
  readonly kind: 'patch';
  readonly key: string;
  readonly patch: PatchAnnotation;
  /** Where the drawn part lands: the destination rectangle clipped to the level image. */
  readonly rect: ViewportRect;
  /** Its destination size in level pixels: the size its image is drawn at (resized if need be). */
  readonly size: { readonly width: number; readonly height: number };
  /** The part of the destination-size image inside the level image (all of it, unless it hangs over an edge). */
  readonly crop: PixelBox;
  readonly order: number;
}

/** One overlay item of a plan. */
export type PlannedItem = PlannedLevel | PlannedPatch;

/** What {@link drawPlan} plans from. */
export interface DrawPlanInput {
  /** The layer's overlay levels. */
  readonly levels: readonly OverlayLevel[];
  /** The layer's patches (any order). */
  readonly patches: readonly PatchAnnotation[];
  /** Ids of the hidden patches. */
  readonly hidden: ReadonlySet<string>;
  /** The current level. */
  readonly level: number;
  /** The canvas width in pixels (1 viewport unit). */
  readonly canvasWidth: number;
}

/**
 * Where a patch lands at its level, in viewport units: its destination rectangle
 * `floor(X/2^L) … ceil((X+W)/2^L)` (and the same in y), each level pixel `2^L` canvas pixels wide.
 */
export function patchRect(patch: PatchAnnotation, canvasWidth: number): ViewportRect {
  const f = 2 ** patch.level;
  const [x0, y0, x1, y1] = destination(patch);
  return { x: (x0 * f) / canvasWidth, y: (y0 * f) / canvasWidth,
    width: ((x1 - x0) * f) / canvasWidth, height: ((y1 - y0) * f) / canvasWidth };
}

/** A patch's destination rectangle in level pixels, `[x0, y0, x1, y1]` (docs/annotations.md, "Building"). */
export function destination(patch: PatchAnnotation): [number, number, number, number] {
  const f = 2 ** patch.level;
  return [Math.floor(patch.x / f), Math.floor(patch.y / f), Math.ceil((patch.x + patch.w) / f),
    Math.ceil((patch.y + patch.h) / f)];
}

/** A patch's own rectangle (X, Y, W, H in canvas pixels) in viewport units: what the highlight outlines. */
export function outlineRect(patch: PatchAnnotation, canvasWidth: number): ViewportRect {
  return { x: patch.x / canvasWidth, y: patch.y / canvasWidth, width: patch.w / canvasWidth,
    height: patch.h / canvasWidth };
}

/** Where a level image lands: at (0, 0), `width·2^L` canvas pixels wide (it may overhang the canvas). */
export function levelRect(level: OverlayLevel, canvasWidth: number): ViewportRect {
  const f = 2 ** level.level;
  return { x: 0, y: 0, width: (level.width * f) / canvasWidth, height: (level.height * f) / canvasWidth };
}

function rectKey(r: ViewportRect): string {
  return `${r.x},${r.y},${r.width},${r.height}`;
}

/** The key of a level pyramid item (its image service: a rebuilt level has a new one). */
export function levelKey(level: OverlayLevel): string {
  return `level|${level.layer}|${level.level}|${level.serviceId}`;
}

/**
 * The overlay items to draw for a layer at a level: none when the layer has no overlay image
 * there; the level's pyramid when none of its patches is hidden; else its visible patches, in
 * application order.
 */
export function drawPlan(input: DrawPlanInput): PlannedItem[] {
  const ov = overlayAt(input.levels, input.level);
  if (!ov) {
    return [];
  }
  const own = input.hidden.size === 0 ? []
    : input.patches.filter((p) => p.level === input.level && p.layer === ov.layer);
  if (!own.some((p) => input.hidden.has(p.id))) {
    return [{ kind: 'level', key: levelKey(ov), level: ov, rect: levelRect(ov, input.canvasWidth), order: 0 }];
  }
  // Each patch's order is its place in the level's whole application order, so an item keeps its
  // order (and key) whichever other patches are hidden.
  return own.sort(applicationOrder).flatMap((patch, i) => {
    if (input.hidden.has(patch.id)) {
      return [];
    }
    // Clipped to the level image, as the tiler clips it (docs/annotations.md, "Building").
    const [x0, y0, x1, y1] = destination(patch);
    const [cx0, cy0] = [Math.max(x0, 0), Math.max(y0, 0)];
    const [cx1, cy1] = [Math.min(x1, ov.width), Math.min(y1, ov.height)];
    if (cx1 <= cx0 || cy1 <= cy0) {
      return [];
    }
    const f = 2 ** patch.level;
    const w = input.canvasWidth;
    const rect = { x: (cx0 * f) / w, y: (cy0 * f) / w, width: ((cx1 - cx0) * f) / w, height: ((cy1 - cy0) * f) / w };
    const crop = { x: cx0 - x0, y: cy0 - y0, width: cx1 - cx0, height: cy1 - cy0 };
    return [{
      kind: 'patch' as const, patch, rect, size: { width: x1 - x0, height: y1 - y0 }, crop, order: i + 1,
      key: `patch|${patch.layer}|${patch.id}|${patch.imageUrl}|${patch.modified}|${rectKey(rect)}`,
    }];
  });
}
