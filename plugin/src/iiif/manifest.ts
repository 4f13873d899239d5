/**
 * Find the relightable layer in a IIIF Presentation 3 manifest. Pure: no DOM, no network.
 */
import { ManifestError, MissingRelightServiceError } from './errors';
import { parseRelightService, RELIGHT_SERVICE_TYPE, type RelightLayer } from './relight-service';

/** What the viewer needs from a manifest. */
export interface ManifestInfo {
  /** The manifest's label (first value of its language map), or '' if none. */
  readonly label: string;
  /** The painting image's id (its colour image URL). */
  readonly imageId: string;
  /** The validated relight layer of the painting image. */
  readonly layer: RelightLayer;
}

type Json = Record<string, unknown>;

function isRecord(x: unknown): x is Json {
  return typeof x === 'object' && x !== null && !Array.isArray(x);
}

function asArray(x: unknown): unknown[] {
  if (Array.isArray(x)) {
    return x;
  }
  return x === undefined || x === null ? [] : [x];
}

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

/**
 * The painting body of the first canvas: an `Image`, or the first `Image` of a `Choice`.
 *
 * @throws {@link ManifestError} when there is none
 */
export function findPaintingImage(manifest: unknown): Json {
  if (!isRecord(manifest) || manifest.type !== 'Manifest') {
    throw new ManifestError('not a IIIF Presentation 3 manifest (type must be "Manifest")');
  }
  for (const canvas of asArray(manifest.items)) {
    if (!isRecord(canvas)) {
      continue;
    }
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
            return body;
          }
          if (body.type === 'Choice') {
            const image = asArray(body.items).find((it) => isRecord(it) && it.type === 'Image');
            if (isRecord(image)) {
              return image;
            }
          }
        }
      }
    }
  }
  throw new ManifestError('the manifest has no painting Image (or Choice of Images) on any canvas');
}

/**
 * Parse a manifest into the relight layer of its painting image.
 *
 * @throws {@link ManifestError} no painting image;
 *   {@link MissingRelightServiceError} the image has no `LanternaRelight` service;
 *   {@link RelightServiceError} the service block is invalid
 */
export function parseManifest(manifest: unknown): ManifestInfo {
  const image = findPaintingImage(manifest);
  const service = asArray(image.service).find((s) => isRecord(s) && s.type === RELIGHT_SERVICE_TYPE);
  if (service === undefined) {
    throw new MissingRelightServiceError(
      `the painting image ${String(image.id)} has no ${RELIGHT_SERVICE_TYPE} service`,
    );
  }
  const label = isRecord(manifest) ? labelText(manifest.label) : '';
  return { label, imageId: typeof image.id === 'string' ? image.id : '', layer: parseRelightService(service) };
}
