/**
 * Read the overlay levels of a Lanterna manifest (`docs/annotations.md`, "Storage and manifest"):
 * annotations in `canvas.annotations` whose `Image` body carries a `LanternaOverlayLevel` service,
 * motivated `commenting` (since the encoding stock viewers list; the target is the drawing's own
 * region and a `TextualBody` holds the short text) or `supplementing` (manifests written before,
 * whole-canvas targets). Pure: no DOM, no network.
 */
import { OverlayError } from './errors';
import { embeddedImage, type EmbeddedImage } from './image-info';
import { type Json, isRecord, asArray } from './json';

/** `type` of the machine-readable overlay level block. */
export const OVERLAY_SERVICE_TYPE = 'LanternaOverlayLevel';
/** `profile` of the overlay level block. */
export const OVERLAY_PROFILE = 'urn:lanterna:overlay:1';

/** One level of a layer's overlay pyramid. */
export interface OverlayLevel {
  /** Id of the layer the overlay belongs to. */
  readonly layer: string;
  /** Level of detail (0 = full resolution). */
  readonly level: number;
  /** Short hypertext (plain text). */
  readonly short: string;
  /** Long hypertext (HTML from the dataset author; sanitise before display). */
  readonly long: string;
  /** The level image's IIIF `ImageService3` id (tiles and info.json). */
  readonly serviceId: string;
  /** The level image's size: `ceil(W/2^L) × ceil(H/2^L)`. */
  readonly width: number;
  readonly height: number;
  /** The level image's description embedded in the manifest, or null: then its info.json is fetched. */
  readonly embedded: EmbeddedImage | null;
}

function text(x: unknown): string {
  return typeof x === 'string' ? x : '';
}

/** The motivations of an overlay level annotation: the current one and the earlier one. */
export const OVERLAY_MOTIVATIONS: readonly string[] = ['commenting', 'supplementing'];

/** The long text of the annotation: its `TextualBody` of purpose `describing` (or HTML), if any. */
function describingText(bodies: readonly unknown[]): string {
  for (const b of bodies) {
    if (isRecord(b) && b.type === 'TextualBody' && typeof b.value === 'string'
      && (asArray(b.purpose).includes('describing') || b.format === 'text/html')) {
      return b.value;
    }
  }
  return '';
}

function parseLevel(annotationId: string, image: Json, block: Json, bodies: readonly unknown[]): OverlayLevel {
  const where = `overlay annotation ${annotationId}`;
  const { layer, level } = block;
  if (typeof layer !== 'string' || layer === '') {
    throw new OverlayError(`${where}: the ${OVERLAY_SERVICE_TYPE} block needs a "layer" id`);
  }
  if (typeof level !== 'number' || !Number.isInteger(level) || level < 0) {
    throw new OverlayError(`${where}: "level" must be an integer ≥ 0, got ${JSON.stringify(level)}`);
  }
  const imageService = asArray(image.service).find((s) => isRecord(s) && s.type !== OVERLAY_SERVICE_TYPE
    && typeof s.id === 'string');
  if (!isRecord(imageService)) {
    throw new OverlayError(`${where}: the level image has no IIIF image service`);
  }
  const { width, height } = image;
  if (typeof width !== 'number' || typeof height !== 'number' || width <= 0 || height <= 0) {
    throw new OverlayError(`${where}: the level image needs a positive width and height`);
  }
  return {
    layer,
    level,
    short: text(block.short),
    long: typeof block.long === 'string' ? block.long : describingText(bodies),
    serviceId: String(imageService.id).replace(/\/+$/, ''),
    width,
    height,
    embedded: embeddedImage(imageService, `manifest: ${where}: the level image's service`),
  };
}

/**
 * The overlay levels of every layer, from a canvas's `annotations` pages. Annotations without a
 * `LanternaOverlayLevel` block (other supplementing content) are ignored.
 *
 * @param canvas - the canvas holding the painting images
 * @param layerIds - the manifest's layer ids; overlays of other layers are an error
 * @returns layer id → its levels, ascending (layers without an overlay are absent)
 * @throws {@link OverlayError} a malformed block, an unknown layer, or a level given twice
 */
export function parseOverlays(canvas: unknown, layerIds: readonly string[]): Map<string, OverlayLevel[]> {
  const result = new Map<string, OverlayLevel[]>();
  if (!isRecord(canvas)) {
    return result;
  }
  for (const page of asArray(canvas.annotations)) {
    if (!isRecord(page)) {
      continue;
    }
    for (const anno of asArray(page.items)) {
      if (!isRecord(anno) || !asArray(anno.motivation).some((m) => OVERLAY_MOTIVATIONS.includes(String(m)))) {
        continue;
      }
      const bodies = asArray(anno.body);
      for (const image of bodies) {
        if (!isRecord(image) || image.type !== 'Image') {
          continue;
        }
        const block = asArray(image.service).find((s) => isRecord(s) && s.type === OVERLAY_SERVICE_TYPE);
        if (!isRecord(block)) {
          continue;
        }
        const level = parseLevel(text(anno.id) || '(no id)', image, block, bodies);
        if (!layerIds.includes(level.layer)) {
          throw new OverlayError(`overlay annotation ${text(anno.id)}: no layer ${JSON.stringify(level.layer)} `
            + `(layers: ${layerIds.join(', ')})`);
        }
        const levels = result.get(level.layer) ?? [];
        if (levels.some((l) => l.level === level.level)) {
          throw new OverlayError(`layer ${level.layer} has two overlays for level ${level.level}`);
        }
        levels.push(level);
        result.set(level.layer, levels);
      }
    }
  }
  for (const levels of result.values()) {
    levels.sort((a, b) => a.level - b.level);
  }
  return result;
}

/** The overlay of `level` among `levels`, or null when that level has none. */
export function overlayAt(levels: readonly OverlayLevel[], level: number): OverlayLevel | null {
  return levels.find((l) => l.level === level) ?? null;
}
