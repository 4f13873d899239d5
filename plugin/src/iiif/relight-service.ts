/**
 * Types and validation of the `LanternaRelight` service block (see `docs/dataset-format.md`).
 * Pure: no DOM, no GL, no network.
 */
import { BASES } from '../math/ptm-basis';
import { RelightServiceError } from './errors';

/** Service `type` of the relight service block. */
export const RELIGHT_SERVICE_TYPE = 'LanternaRelight';
/** Service `profile` of version 1 of the relight service block. */
export const RELIGHT_PROFILE = 'urn:lanterna:relight:1';

/** Supported layer types. */
export type LayerType = 'ptm' | 'image';
/** Colour spaces of a PTM layer. */
export type PtmColorspace = 'lrgb' | 'rgb';

/** One plane group: an RGB IIIF image holding three channels. */
export interface PlaneGroup {
  /** IIIF Image service id (base URL, no `/info.json`). */
  readonly serviceId: string;
  /** Tile format, e.g. `png`. */
  readonly format: string;
  /** Channel names, three per group. */
  readonly channels: readonly [string, string, string];
  /** Per-channel scale: `v = (t − bias) · scale`. */
  readonly scale: readonly [number, number, number];
  /** Per-channel bias, in texel/255 units. */
  readonly bias: readonly [number, number, number];
}

/** A validated relightable layer. */
export interface RelightLayer {
  /** Service id (URL of the layer document). */
  readonly id: string;
  readonly layerType: LayerType;
  /** `lrgb` or `rgb` for PTM; `rgb` for an image layer. */
  readonly colorspace: PtmColorspace;
  readonly width: number;
  readonly height: number;
  readonly planes: readonly PlaneGroup[];
}

/** Channel names the contract prescribes, per layer type and colour space, group by group. */
export function expectedChannels(layerType: LayerType, colorspace: PtmColorspace): string[][] {
  if (layerType === 'image') {
    return [['R', 'G', 'B']];
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

function isRecord(x: unknown): x is Record<string, unknown> {
  return typeof x === 'object' && x !== null && !Array.isArray(x);
}

function triple(x: unknown, what: string): [number, number, number] {
  if (!Array.isArray(x) || x.length !== 3 || !x.every((v) => typeof v === 'number' && Number.isFinite(v))) {
    throw new RelightServiceError(`${what} must be an array of 3 finite numbers`);
  }
  return [x[0] as number, x[1] as number, x[2] as number];
}

function positiveInt(x: unknown, what: string): number {
  if (typeof x !== 'number' || !Number.isInteger(x) || x <= 0) {
    throw new RelightServiceError(`${what} must be a positive integer, got ${JSON.stringify(x)}`);
  }
  return x;
}

/**
 * Validate a relight service block and return it typed.
 *
 * @param block - the JSON object from the manifest's `service` list (or a layer document)
 * @throws {@link RelightServiceError} when any field breaks the contract
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
  if (layerType !== 'ptm' && layerType !== 'image') {
    throw new RelightServiceError(`unsupported layerType ${JSON.stringify(layerType)}`);
  }
  const colorspace = block.colorspace ?? 'rgb';
  if (colorspace !== 'lrgb' && colorspace !== 'rgb') {
    throw new RelightServiceError(`unsupported colorspace ${JSON.stringify(colorspace)}`);
  }
  if (layerType === 'image' && colorspace !== 'rgb') {
    throw new RelightServiceError('an image layer must have colorspace rgb');
  }
  const basis = BASES[layerType];
  if (basis) {
    const given = block.basis;
    if (!Array.isArray(given) || given.length !== basis.terms.length || given.some((t, i) => t !== basis.terms[i])) {
      throw new RelightServiceError(`basis must be ${JSON.stringify(basis.terms)}, got ${JSON.stringify(given)}`);
    }
  }
  const width = positiveInt(block.width, 'width');
  const height = positiveInt(block.height, 'height');
  if (!Array.isArray(block.planes)) {
    throw new RelightServiceError('planes must be an array');
  }
  const expected = expectedChannels(layerType, colorspace);
  if (block.planes.length !== expected.length) {
    throw new RelightServiceError(
      `${layerType}/${colorspace} needs ${expected.length} plane groups, got ${block.planes.length}`,
    );
  }
  const planes = block.planes.map((p: unknown, i: number): PlaneGroup => {
    if (!isRecord(p) || !isRecord(p.service) || typeof p.service.id !== 'string' || p.service.id === '') {
      throw new RelightServiceError(`plane ${i}: missing service.id`);
    }
    const channels = p.channels;
    const want = expected[i] ?? [];
    if (!Array.isArray(channels) || channels.length !== 3 || channels.some((c, k) => c !== want[k])) {
      throw new RelightServiceError(`plane ${i}: channels must be ${JSON.stringify(want)}, got ${JSON.stringify(channels)}`);
    }
    const format = p.format ?? 'png';
    if (typeof format !== 'string') {
      throw new RelightServiceError(`plane ${i}: format must be a string`);
    }
    return {
      serviceId: p.service.id.replace(/\/+$/, ''),
      format,
      channels: [want[0] ?? '', want[1] ?? '', want[2] ?? ''],
      scale: triple(p.scale, `plane ${i}: scale`),
      bias: triple(p.bias, `plane ${i}: bias`),
    };
  });
  return { id, layerType, colorspace, width, height, planes };
}
