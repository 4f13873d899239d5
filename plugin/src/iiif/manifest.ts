/**
 * Find the relightable layer in a IIIF Presentation 3 manifest. Pure: no DOM, no network.
 */
import { ManifestError, MissingRelightServiceError } from './errors';
import { parseOverlays, type OverlayLevel } from './overlays';
import { parseRelightService, RELIGHT_SERVICE_TYPE, type RelightLayer } from './relight-service';
import { type Json, isRecord, asArray } from './json';

/** One layer of a manifest: a painting `Image` (a `Choice` item) with its relight service. */
export interface ManifestLayer {
  /** Layer id: the file name of the relight service id (`…/layers/ptm.json` → `ptm`), else of the image service's. */
  readonly id: string;
  /** The image's label, or the id. */
  readonly label: string;
  /** The painting image's id (its colour image URL). */
  readonly imageId: string;
  /** The validated relight layer. */
  readonly layer: RelightLayer;
  /** Its overlay levels (`docs/annotations.md`), ascending; empty when it has no overlay. */
  readonly overlays: readonly OverlayLevel[];
}

/** What the viewer needs from a manifest. */
export interface ManifestInfo {
  /** The manifest's label (first value of its language map), or '' if none. */
  readonly label: string;
  /** Every relightable layer, in manifest order (the first is the default). */
  readonly layers: readonly ManifestLayer[];
  /** The default layer's image id (= `layers[0].imageId`). */
  readonly imageId: string;
  /** The default layer (= `layers[0].layer`). */
  readonly layer: RelightLayer;
  /** The manifest's summary (first value of its language map), or ''. */
  readonly summary: string;
  /** Its `metadata` pairs (first values of their language maps), in order. */
  readonly metadata: readonly LabelValue[];
  /** Its `requiredStatement` (attribution), or null. */
  readonly requiredStatement: LabelValue | null;
  /** Its `rights` URL, or ''. */
  readonly rights: string;
  /**
   * Its preset library service block (`docs/presets.md`: `type` `LanternaPresets`), unparsed: it is read
   * against the layers by `parsePresetLibrary`. Null when there is none.
   */
  readonly presets: unknown;
  /** The canvas's physical scale (a IIIF `physdim` service), or null when it has none. */
  readonly physicalScale: PhysicalScale | null;
}

/** A label and a value (IIIF `metadata`, `requiredStatement`), as plain strings. */
export interface LabelValue {
  readonly label: string;
  /** May hold the small HTML subset IIIF allows: sanitise before showing it as HTML. */
  readonly value: string;
}

/** The physical size of one canvas pixel (the IIIF Physical Dimensions service). */
export interface PhysicalScale {
  /** Units per canvas pixel. */
  readonly scale: number;
  readonly units: PhysicalUnits;
}

/** The units of the Physical Dimensions service. */
export type PhysicalUnits = 'mm' | 'cm' | 'in';

/** The profile of the IIIF Physical Dimensions service. */
export const PHYSDIM_PROFILE = 'http://iiif.io/api/annex/services/physdim';
/** The `type` of a preset library service block. */
const PRESETS_SERVICE_TYPE = 'LanternaPresets';

/**
 * First string of a IIIF language map (`{"en": ["Ushabti"]}`), preferring `en`, then `none`.
 */
export function labelText(label: unknown): string {
  if (typeof label === 'string') {
    return label;
  }
  if (!isRecord(label)) {
    return '';
  }
  for (const key of ['en', 'none', ...Object.keys(label)]) {
    const values = asArray(label[key]);
    const first = values.find((v) => typeof v === 'string');
    if (typeof first === 'string') {
      return first;
    }
  }
  return '';
}

/** The painting images of one canvas: every `Image` body, or every `Image` of a `Choice`, in order. */
function canvasPaintingImages(canvas: Json): Json[] {
  const images: Json[] = [];
  for (const page of asArray(canvas.items)) {
    if (!isRecord(page)) {
      continue;
    }
    for (const anno of asArray(page.items)) {
      if (!isRecord(anno) || !asArray(anno.motivation).includes('painting')) {
        continue;
      }
      for (const body of asArray(anno.body)) {
        if (!isRecord(body)) {
          continue;
        }
        if (body.type === 'Image') {
          images.push(body);
        } else if (body.type === 'Choice') {
          images.push(...asArray(body.items).filter((it): it is Json => isRecord(it) && it.type === 'Image'));
        }
      }
    }
  }
  return images;
}

/**
 * The first canvas that has painting images, with those images.
 *
 * @throws {@link ManifestError} when there is none
 */
export function findPaintingCanvas(manifest: unknown): { canvas: Json; images: Json[] } {
  if (!isRecord(manifest) || manifest.type !== 'Manifest') {
    throw new ManifestError('not a IIIF Presentation 3 manifest (type must be "Manifest")');
  }
  for (const canvas of asArray(manifest.items)) {
    if (!isRecord(canvas)) {
      continue;
    }
    const images = canvasPaintingImages(canvas);
    if (images.length > 0) {
      return { canvas, images };
    }
  }
  throw new ManifestError('the manifest has no painting Image (or Choice of Images) on any canvas');
}

/**
 * The painting images of the first canvas that has any: an `Image` body, or every `Image` of a
 * `Choice`, in order.
 *
 * @throws {@link ManifestError} when there is none
 */
export function findPaintingImages(manifest: unknown): Json[] {
  return findPaintingCanvas(manifest).images;
}

/**
 * The painting body of the first canvas: an `Image`, or the first `Image` of a `Choice`.
 *
 * @throws {@link ManifestError} when there is none
 */
export function findPaintingImage(manifest: unknown): Json {
  return findPaintingImages(manifest)[0];
}

/** The last path segment of a URL without its extension (`…/layers/ptm.json` → `ptm`). */
export function idFromUrl(url: string): string {
  const path = url.split(/[?#]/)[0] ?? '';
  const name = path.replace(/\/+$/, '').split('/').pop() ?? '';
  return name.replace(/\.[^.]*$/, '');
}

/**
 * Parse a manifest into its relightable layers (every painting image with a `LanternaRelight`
 * service; images without one are skipped).
 *
 * @throws {@link ManifestError} no painting image, or two layers with the same id;
 *   {@link OverlayError} a malformed overlay level annotation;
 *   {@link MissingRelightServiceError} no image has a `LanternaRelight` service;
 *   {@link RelightServiceError} a service block is invalid
 */
export function parseManifest(manifest: unknown): ManifestInfo {
  const { canvas, images } = findPaintingCanvas(manifest);
  const layers: ManifestLayer[] = [];
  for (const image of images) {
    const service = asArray(image.service).find((s) => isRecord(s) && s.type === RELIGHT_SERVICE_TYPE);
    if (service === undefined) {
      continue;
    }
    const layer = parseRelightService(service);
    const imageId = typeof image.id === 'string' ? image.id : '';
    const imageService = asArray(image.service).find((s) => isRecord(s) && s.type !== RELIGHT_SERVICE_TYPE);
    const serviceId = isRecord(imageService) && typeof imageService.id === 'string' ? imageService.id : '';
    const id = idFromUrl(layer.id) || idFromUrl(serviceId) || `layer${layers.length}`;
    if (layers.some((l) => l.id === id)) {
      throw new ManifestError(`two layers have the id ${JSON.stringify(id)}`);
    }
    layers.push({ id, label: labelText(image.label) || id, imageId, layer, overlays: [] });
  }
  const first = layers[0];
  if (!first) {
    throw new MissingRelightServiceError(
      `the painting image ${String(images[0]?.id)} has no ${RELIGHT_SERVICE_TYPE} service`,
    );
  }
  const overlays = parseOverlays(canvas, layers.map((l) => l.id));
  const withOverlays = layers.map((l) => ({ ...l, overlays: overlays.get(l.id) ?? [] }));
  const doc: Json = isRecord(manifest) ? manifest : {};
  return {
    label: labelText(doc.label),
    layers: withOverlays,
    imageId: first.imageId,
    layer: first.layer,
    summary: labelText(doc.summary),
    metadata: asArray(doc.metadata).map(labelValue).filter((m): m is LabelValue => m !== null),
    requiredStatement: labelValue(doc.requiredStatement),
    rights: typeof doc.rights === 'string' ? doc.rights : '',
    presets: asArray(doc.service).find((s) => isRecord(s) && s.type === PRESETS_SERVICE_TYPE) ?? null,
    physicalScale: physicalScaleOf(canvas),
  };
}

/** A IIIF `{label, value}` pair as strings, or null when it is not one. */
function labelValue(x: unknown): LabelValue | null {
  if (!isRecord(x)) {
    return null;
  }
  const label = labelText(x.label);
  const value = labelText(x.value);
  return label || value ? { label, value } : null;
}

/**
 * The canvas's physdim service (found by its profile; `physicalScale` a positive number and
 * `physicalUnits` mm, cm or in), or null. A malformed one is ignored: a scale bar is optional.
 */
function physicalScaleOf(canvas: Json): PhysicalScale | null {
  for (const s of asArray(canvas.service)) {
    if (!isRecord(s) || asArray(s.profile).every((p) => p !== PHYSDIM_PROFILE)) {
      continue;
    }
    const scale = s.physicalScale;
    const units = s.physicalUnits;
    if (typeof scale === 'number' && Number.isFinite(scale) && scale > 0
      && (units === 'mm' || units === 'cm' || units === 'in')) {
      return { scale, units };
    }
  }
  return null;
}
