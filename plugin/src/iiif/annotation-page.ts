/**
 * Read a layer's individual annotations (`docs/annotations.md`, "Individual annotations"): the
 * W3C / IIIF `AnnotationPage` a Lanterna manifest references per layer with patches, one
 * `Annotation` per patch whose `Image` body carries a `LanternaPatch` block. Annotations without
 * one (a comment someone else added, a Mirador note) are skipped. Pure: no DOM, no network.
 */
import { AnnotationPageError } from './errors';
import { findPaintingCanvas } from './manifest';
import { type Json, isRecord, asArray } from './json';

/** `type` of the machine-readable patch block. */
export const PATCH_SERVICE_TYPE = 'LanternaPatch';
/** `profile` of the patch block. */
export const PATCH_PROFILE = 'urn:lanterna:patch:1';

/** The render state a patch was drawn under (`null` when unknown, e.g. a file dropped in the store). */
export interface PatchRenderState {
  readonly layer: string;
  readonly mode: string;
  readonly params: Readonly<Record<string, number>>;
  readonly light: readonly [number, number];
}

/** One patch of a layer's overlay as an individual annotation. */
export interface PatchAnnotation {
  /** The patch id: its file stem `L_X_Y_W_H_O_INFO`. */
  readonly id: string;
  /** The layer whose overlay it belongs to. */
  readonly layer: string;
  /** Its level (0 = full resolution). */
  readonly level: number;
  /** Its rectangle in full-resolution canvas pixels. */
  readonly x: number;
  readonly y: number;
  readonly w: number;
  readonly h: number;
  /** Its order of application within the level. */
  readonly order: number;
  /** The short text (plain) and the long text (HTML from the author; sanitise before display). */
  readonly short: string;
  readonly long: string;
  readonly motivation: 'commenting' | 'tagging';
  /** The author's name ('' when none). */
  readonly author: string;
  /** ISO-8601 times ('' when absent). */
  readonly created: string;
  readonly modified: string;
  readonly state: PatchRenderState | null;
  /** The patch PNG and its size in pixels. */
  readonly imageUrl: string;
  readonly width: number;
  readonly height: number;
}

/**
 * The referenced annotation pages of a manifest's painting canvas: the entries of
 * `canvas.annotations` that carry no `items` of their own (the embedded overlay-level pages do).
 */
export function referencedPages(manifest: unknown): string[] {
  const { canvas } = findPaintingCanvas(manifest);
  return asArray(canvas.annotations).flatMap((page) => (isRecord(page) && page.items === undefined
    && page.type === 'AnnotationPage' && typeof page.id === 'string' ? [page.id] : []));
}

function str(x: unknown): string {
  return typeof x === 'string' ? x : '';
}

/** The last path segment of a URL, decoded, without `.json` / `.png` (`…/vis/1_0_0_8_8_0_a.json` → `1_0_0_8_8_0_a`). */
function stemOf(url: string): string {
  const path = url.split(/[?#]/)[0] ?? '';
  const name = path.replace(/\/+$/, '').split('/').pop() ?? '';
  let decoded = name;
  try {
    decoded = decodeURIComponent(name);
  } catch {
    // keep it as written
  }
  return decoded.replace(/\.(json|png)$/i, '');
}

/** An integer field of the patch block; `min` the least value allowed. */
function int(block: Json, key: string, min: number, where: string): number {
  const v = block[key];
  if (typeof v !== 'number' || !Number.isInteger(v) || v < min) {
    throw new AnnotationPageError(`${where}: "${key}" must be an integer ≥ ${min}, got ${JSON.stringify(v)}`);
  }
  return v;
}

function renderState(raw: unknown, where: string): PatchRenderState | null {
  if (raw === null || raw === undefined) {
    return null;
  }
  const bad = (what: string): AnnotationPageError => new AnnotationPageError(`${where}: "state" ${what}`);
  if (!isRecord(raw)) {
    throw bad('must be an object or null');
  }
  const { layer, mode, params, light } = raw;
  if (typeof layer !== 'string' || typeof mode !== 'string') {
    throw bad('needs a "layer" and a "mode" (strings)');
  }
  if (!Array.isArray(light) || light.length !== 2 || !light.every((v) => typeof v === 'number' && Number.isFinite(v))) {
    throw bad(`"light" must be [lu, lv], got ${JSON.stringify(light)}`);
  }
  const values: Record<string, number> = {};
  for (const [name, v] of Object.entries(isRecord(params) ? params : {})) {
    if (typeof v !== 'number' || !Number.isFinite(v)) {
      throw bad(`"params.${name}" must be a number, got ${JSON.stringify(v)}`);
    }
    values[name] = v;
  }
  return { layer, mode, params: values, light: [light[0] as number, light[1] as number] };
}

/** The texts of an annotation's `TextualBody`s: the short one (commenting / tagging) and the long one (HTML). */
function texts(bodies: readonly unknown[]): { short: string; long: string; tagging: boolean } {
  let short = '';
  let long = '';
  let tagging = false;
  for (const b of bodies) {
    if (!isRecord(b) || b.type !== 'TextualBody' || typeof b.value !== 'string') {
      continue;
    }
    const purposes = asArray(b.purpose);
    if (b.format === 'text/html' || purposes.includes('describing')) {
      long ||= b.value;
    } else {
      short ||= b.value;
      tagging ||= purposes.includes('tagging');
    }
  }
  return { short, long, tagging };
}

function parseItem(anno: Json, image: Json, block: Json, where: string): PatchAnnotation {
  const { layer } = block;
  if (typeof layer !== 'string' || layer === '') {
    throw new AnnotationPageError(`${where}: the ${PATCH_SERVICE_TYPE} block needs a "layer" id`);
  }
  const imageUrl = str(image.id);
  const { width, height } = image;
  if (imageUrl === '' || typeof width !== 'number' || typeof height !== 'number' || width <= 0 || height <= 0) {
    throw new AnnotationPageError(`${where}: the patch image needs an "id" and a positive "width" and "height"`);
  }
  const id = stemOf(str(anno.id)) || stemOf(imageUrl);
  const { short, long, tagging } = texts(asArray(anno.body));
  const creator = asArray(anno.creator).find(isRecord);
  return {
    id,
    layer,
    level: int(block, 'level', 0, where),
    x: int(block, 'x', -Infinity, where),
    y: int(block, 'y', -Infinity, where),
    w: int(block, 'w', 1, where),
    h: int(block, 'h', 1, where),
    order: int(block, 'order', -Infinity, where),
    short,
    long,
    motivation: tagging || asArray(anno.motivation).includes('tagging') ? 'tagging' : 'commenting',
    author: str(creator?.name),
    created: str(anno.created),
    modified: str(anno.modified),
    state: renderState(block.state, where),
    imageUrl,
    width,
    height,
  };
}

/**
 * The patches of an `AnnotationPage`, in application order (level, order, id).
 *
 * @param page - the page document
 * @param url - where it came from (named in errors)
 * @param layerIds - the manifest's layer ids; a patch of another layer is an error
 * @throws {@link AnnotationPageError} naming the page and the item: not a page, a malformed patch
 *   block, an unknown layer, or one id given twice
 */
export function parseAnnotationPage(page: unknown, url: string, layerIds: readonly string[]): PatchAnnotation[] {
  if (!isRecord(page) || page.type !== 'AnnotationPage') {
    throw new AnnotationPageError(`annotation page ${url}: not an AnnotationPage (type must be "AnnotationPage")`);
  }
  const out: PatchAnnotation[] = [];
  asArray(page.items).forEach((anno, i) => {
    if (!isRecord(anno)) {
      return;
    }
    const where = `annotation page ${url}: item ${i}${typeof anno.id === 'string' ? ` (${anno.id})` : ''}`;
    for (const image of asArray(anno.body)) {
      const block = isRecord(image) && image.type === 'Image'
        ? asArray(image.service).find((s) => isRecord(s) && s.type === PATCH_SERVICE_TYPE) : undefined;
      if (!isRecord(image) || !isRecord(block)) {
        continue;
      }
      const patch = parseItem(anno, image, block, where);
      if (!layerIds.includes(patch.layer)) {
        throw new AnnotationPageError(`${where}: no layer ${JSON.stringify(patch.layer)} (layers: ${layerIds.join(', ')})`);
      }
      if (out.some((p) => p.layer === patch.layer && p.id === patch.id)) {
        throw new AnnotationPageError(`${where}: patch ${patch.id} is given twice`);
      }
      out.push(patch);
    }
  });
  return out.sort(applicationOrder);
}

/** The compositing order of patches: level, then order, then id (the tiler's file-name tie-break). */
export function applicationOrder(a: PatchAnnotation, b: PatchAnnotation): number {
  if (a.level !== b.level) {
    return a.level - b.level;
  }
  if (a.order !== b.order) {
    return a.order - b.order;
  }
  // The tiler sorts file names by code point (Python's str ordering).
  const fa = `${a.id}.png`;
  const fb = `${b.id}.png`;
  return fa < fb ? -1 : fa > fb ? 1 : 0;
}
