/**
 * Types and validation of the `LanternaRelight` service block (see `docs/dataset-format.md`).
 * Pure: no DOM, no GL, no network.
 */
import type { PcaBasis } from '../math/pca-weights';
import { BASES } from '../math/ptm-basis';
import { SH_TERM_COUNTS } from '../math/sh-basis';
import { RelightServiceError } from './errors';
import { embeddedImage, type EmbeddedImage } from './image-info';
import { isRecord } from './json';
import { isPcaType, parsePcaBlock, pcaChannelNames } from './pca-block';

/** Service `type` of the relight service block. */
export const RELIGHT_SERVICE_TYPE = 'LanternaRelight';
/** Service `profile` of version 1 of the relight service block. */
export const RELIGHT_PROFILE = 'urn:lanterna:relight:1';

/** Supported layer types. */
export type LayerType = 'ptm' | 'hsh' | 'sh' | 'svbrdf' | 'image' | 'rbf' | 'bilinear';
/** Every supported layer type. */
export const LAYER_TYPES: readonly LayerType[] = ['ptm', 'hsh', 'sh', 'svbrdf', 'image', 'rbf', 'bilinear'];
/** Colour spaces of a PTM layer. */
export type PtmColorspace = 'lrgb' | 'rgb';
/** How an svbrdf layer's kd and ks are encoded. */
/** How svbrdf kd/ks are encoded; `display`: display values, shaded as they are (docs/rendering.md). */
export type InputColorSpace = 'linear' | 'srgb' | 'display';

/** Term counts of an HSH layer. */
export const HSH_TERM_COUNTS = [4, 9, 16] as const;

/** Term counts of each layer type with per-term R, G, B planes (`terms` in the block). */
const TERM_COUNTS: Partial<Record<LayerType, readonly number[]>> = { hsh: HSH_TERM_COUNTS, sh: SH_TERM_COUNTS };

/** Channel groups of an svbrdf layer, by map. */
export const SVBRDF_MAPS = {
  normals: ['NX', 'NY', 'NZ'],
  kd: ['KD_R', 'KD_G', 'KD_B'],
  ks: ['KS_R', 'KS_G', 'KS_B'],
  gloss: ['GLOSS'],
  depth: ['DEPTH'],
} as const satisfies Record<string, readonly string[]>;
/** Map names of an svbrdf layer. */
export type SvbrdfMap = keyof typeof SVBRDF_MAPS;

/** Default `glossLimits` of an svbrdf layer. */
export const DEFAULT_GLOSS_LIMITS: readonly [number, number] = [0.01, 0.5];

/** One plane group: one IIIF image holding three channels (RGB) or one (single-band, grey). */
export interface PlaneGroup {
  /** IIIF Image service id (base URL, no `/info.json`). */
  readonly serviceId: string;
  /** Tile format, e.g. `png`. */
  readonly format: string;
  /** Channel names: three, or one for a single-band image. */
  readonly channels: readonly string[];
  /** Per-channel scale: `v = (t − bias) · scale` (same length as `channels`). */
  readonly scale: readonly number[];
  /** Per-channel bias, in texel/255 units (same length as `channels`). */
  readonly bias: readonly number[];
  /** The image description embedded in `service`, or null: then the viewer fetches its info.json. */
  readonly embedded: EmbeddedImage | null;
}

/** A validated relightable layer. */
export interface RelightLayer {
  /** Service id (URL of the layer document). */
  readonly id: string;
  readonly layerType: LayerType;
  /** `lrgb` or `rgb` for PTM; `rgb` for the other types (rbf/bilinear: their colour space is in `pca`). */
  readonly colorspace: PtmColorspace;
  readonly width: number;
  readonly height: number;
  readonly planes: readonly PlaneGroup[];
  /** HSH: 4, 9 or 16; SH: 4 or 9; 0 for the other types. */
  readonly terms: number;
  /** svbrdf: gloss range `[αmin, αmax]`. */
  readonly glossLimits: readonly [number, number];
  /** svbrdf: encoding of kd and ks. */
  readonly inputColorSpace: InputColorSpace;
  /** rbf, bilinear: the decoded PCA basis and its colour space; absent for the other types. */
  readonly pca?: PcaBasis;
}

/**
 * Channel names the contract prescribes for PTM, HSH, SH and RGB image layers, group by group.
 * (svbrdf groups are any subset of {@link SVBRDF_MAPS}; a single-band image layer is `[['Y']]`.)
 */
export function expectedChannels(layerType: LayerType, colorspace: PtmColorspace, terms = 0): string[][] {
  if (layerType === 'image') {
    return [['R', 'G', 'B']];
  }
  if (TERM_COUNTS[layerType]) {
    return Array.from({ length: terms }, (_, k) => [`R${k}`, `G${k}`, `B${k}`]);
  }
  if (layerType === 'svbrdf') {
    return Object.values(SVBRDF_MAPS).map((c) => [...c]);
  }
  if (colorspace === 'lrgb') {
    return [['L0', 'L1', 'L2'], ['L3', 'L4', 'L5'], ['R', 'G', 'B']];
  }
  const groups: string[][] = [];
  for (const c of ['R', 'G', 'B']) {
    groups.push([`${c}0`, `${c}1`, `${c}2`], [`${c}3`, `${c}4`, `${c}5`]);
  }
  return groups;
}

/**
 * Index of each svbrdf map's plane group in `layer.planes`, or -1 when the map is absent.
 */
export function svbrdfMapIndices(layer: Pick<RelightLayer, 'planes'>): Record<SvbrdfMap, number> {
  const out = { normals: -1, kd: -1, ks: -1, gloss: -1, depth: -1 };
  for (const map of Object.keys(SVBRDF_MAPS) as SvbrdfMap[]) {
    const want: readonly string[] = SVBRDF_MAPS[map];
    out[map] = layer.planes.findIndex((p) => p.channels.length === want.length
      && p.channels.every((c, i) => c === want[i]));
  }
  return out;
}

function numbers(x: unknown, n: number, what: string): number[] {
  if (!Array.isArray(x) || x.length !== n || !x.every((v) => typeof v === 'number' && Number.isFinite(v))) {
    throw new RelightServiceError(`${what} must be an array of ${n} finite number${n === 1 ? '' : 's'}`);
  }
  return x as number[];
}

function positiveInt(x: unknown, what: string): number {
  if (typeof x !== 'number' || !Number.isInteger(x) || x <= 0) {
    throw new RelightServiceError(`${what} must be a positive integer, got ${JSON.stringify(x)}`);
  }
  return x;
}

function parsePlane(p: unknown, i: number, blockId: string): PlaneGroup {
  if (!isRecord(p) || !isRecord(p.service) || typeof p.service.id !== 'string' || p.service.id === '') {
    throw new RelightServiceError(`plane ${i}: missing service.id`);
  }
  const channels = p.channels;
  if (!Array.isArray(channels) || (channels.length !== 1 && channels.length !== 3)
    || !channels.every((c) => typeof c === 'string')) {
    throw new RelightServiceError(`plane ${i}: channels must be 1 or 3 names, got ${JSON.stringify(channels)}`);
  }
  const format = p.format ?? 'png';
  if (typeof format !== 'string') {
    throw new RelightServiceError(`plane ${i}: format must be a string`);
  }
  const n = channels.length;
  return {
    serviceId: p.service.id.replace(/\/+$/, ''),
    format,
    channels: channels,
    scale: numbers(p.scale, n, `plane ${i}: scale`),
    bias: numbers(p.bias, n, `plane ${i}: bias`),
    embedded: embeddedImage(p.service, `manifest: ${blockId || RELIGHT_SERVICE_TYPE} planes[${i}].service`),
  };
}

const sameNames = (a: readonly string[], b: readonly string[]): boolean =>
  a.length === b.length && a.every((c, k) => c === b[k]);

/** Check the plane groups' channel names against the layer type's layout. */
function checkChannels(layerType: LayerType, colorspace: PtmColorspace, terms: number,
  planes: readonly PlaneGroup[], pca?: PcaBasis): void {
  if (layerType === 'svbrdf') {
    const seen = new Set<string>();
    planes.forEach((p, i) => {
      const map = (Object.keys(SVBRDF_MAPS) as SvbrdfMap[]).find((m) => sameNames(p.channels, SVBRDF_MAPS[m]));
      if (!map) {
        throw new RelightServiceError(`plane ${i}: ${JSON.stringify(p.channels)} is not an svbrdf map `
          + `(${Object.values(SVBRDF_MAPS).map((c) => JSON.stringify(c)).join(', ')})`);
      }
      if (seen.has(map)) {
        throw new RelightServiceError(`plane ${i}: the ${map} map is given twice`);
      }
      seen.add(map);
    });
    if (planes.length === 0) {
      throw new RelightServiceError('an svbrdf layer needs at least one map');
    }
    return;
  }
  if (layerType === 'image' && planes.length === 1 && sameNames(planes[0]?.channels ?? [], ['Y'])) {
    return;
  }
  const expected = pca ? pcaChannelNames(pca.nplanes) : expectedChannels(layerType, colorspace, terms);
  const kind = layerType === 'ptm' ? `ptm/${colorspace}` : TERM_COUNTS[layerType] ? `${layerType}${terms}`
    : pca ? `${layerType} with ${pca.nplanes} planes` : layerType;
  if (planes.length !== expected.length) {
    throw new RelightServiceError(`${kind} needs ${expected.length} plane groups, got ${planes.length}`);
  }
  planes.forEach((p, i) => {
    const want = expected[i] ?? [];
    if (!sameNames(p.channels, want)) {
      throw new RelightServiceError(`plane ${i}: channels must be ${JSON.stringify(want)}, got ${JSON.stringify(p.channels)}`);
    }
  });
}

const isLayerType = (x: unknown): x is LayerType => (LAYER_TYPES as readonly unknown[]).includes(x);

function parseGlossLimits(x: unknown): readonly [number, number] {
  if (x === undefined) {
    return DEFAULT_GLOSS_LIMITS;
  }
  const [lo, hi] = numbers(x, 2, 'glossLimits') as [number, number];
  if (!(lo > 0 && lo <= hi)) {
    throw new RelightServiceError(`glossLimits must satisfy 0 < min <= max, got ${JSON.stringify(x)}`);
  }
  return [lo, hi];
}

/**
 * Validate a relight service block and return it typed.
 *
 * @param block - the JSON object from the manifest's `service` list (or a layer document)
 * @throws {@link RelightServiceError} when any field breaks the contract; {@link ImageInfoError} when a
 *   plane service embeds a malformed image description
 */
export function parseRelightService(block: unknown): RelightLayer {
  if (!isRecord(block)) {
    throw new RelightServiceError('relight service block must be an object');
  }
  if (block.type !== RELIGHT_SERVICE_TYPE) {
    throw new RelightServiceError(`service type must be ${RELIGHT_SERVICE_TYPE}, got ${JSON.stringify(block.type)}`);
  }
  if (block.profile !== RELIGHT_PROFILE) {
    throw new RelightServiceError(`unsupported relight profile ${JSON.stringify(block.profile)}`);
  }
  const id = typeof block.id === 'string' ? block.id : '';
  const layerType = block.layerType;
  if (!isLayerType(layerType)) {
    throw new RelightServiceError(`unsupported layerType ${JSON.stringify(layerType)}`);
  }
  const at = `${id.split(/[?#]/)[0]?.replace(/\/+$/, '').split('/').pop()?.replace(/\.json$/, '') || 'layer'}.`;
  const pca = isPcaType(layerType) ? parsePcaBlock(block, layerType, at) : undefined;
  const colorspace = pca ? 'rgb' : block.colorspace ?? 'rgb';
  if (colorspace !== 'lrgb' && colorspace !== 'rgb') {
    throw new RelightServiceError(`unsupported colorspace ${JSON.stringify(colorspace)}`);
  }
  if (layerType !== 'ptm' && colorspace !== 'rgb') {
    throw new RelightServiceError(`an ${layerType} layer must have colorspace rgb`);
  }
  let terms = 0;
  const counts = TERM_COUNTS[layerType];
  if (counts) {
    terms = block.terms as number;
    if (!(counts as readonly unknown[]).includes(terms)) {
      throw new RelightServiceError(`${layerType} terms must be ${counts.slice(0, -1).join(', ')} or `
        + `${String(counts.at(-1))}, got ${JSON.stringify(block.terms)}`);
    }
  }
  const basis = BASES[layerType];
  if (basis && layerType === 'ptm') {
    const given = block.basis;
    if (!Array.isArray(given) || given.length !== basis.terms.length || given.some((t, i) => t !== basis.terms[i])) {
      throw new RelightServiceError(`basis must be ${JSON.stringify(basis.terms)}, got ${JSON.stringify(given)}`);
    }
  }
  const inputColorSpace = block.inputColorSpace ?? 'linear';
  if (inputColorSpace !== 'linear' && inputColorSpace !== 'srgb' && inputColorSpace !== 'display') {
    throw new RelightServiceError(
      `inputColorSpace must be "linear", "srgb" or "display", got ${JSON.stringify(inputColorSpace)}`);
  }
  const glossLimits = parseGlossLimits(block.glossLimits);
  const width = positiveInt(block.width, 'width');
  const height = positiveInt(block.height, 'height');
  if (!Array.isArray(block.planes)) {
    throw new RelightServiceError('planes must be an array');
  }
  const planes = block.planes.map((p, i) => parsePlane(p, i, id));
  checkChannels(layerType, colorspace, terms, planes, pca);
  return {
    id, layerType, colorspace, width, height, planes, terms, glossLimits, inputColorSpace,
    ...(pca ? { pca } : {}),
  };
}
