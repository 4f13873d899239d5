/**
 * The fields of a PCA relight block (`layerType` `rbf` or `bilinear`, docs/dataset-format.md),
 * validated and decoded into a {@link PcaBasis}. Pure: no DOM, no GL, no network.
 */
import { decodeBasis, MAX_PCA_PLANES, type PcaBasis, type PcaColorspace, type PcaType } from '../math/pca-weights';
import { RelightServiceError } from './errors';
import type { Json } from './json';

/** Layer types with a PCA basis. */
export const PCA_LAYER_TYPES: readonly PcaType[] = ['rbf', 'bilinear'];
/** Colour spaces of a PCA layer. */
export const PCA_COLORSPACES: readonly PcaColorspace[] = ['mrgb', 'mycc'];

/** Whether a layer type has a PCA basis. */
export function isPcaType(layerType: unknown): layerType is PcaType {
  return (PCA_LAYER_TYPES as readonly unknown[]).includes(layerType);
}

/** The channel names of a PCA layer's plane groups: `P0, P1, P2`, …; padding `X{q}` (scale 0). */
export function pcaChannelNames(nplanes: number): string[][] {
  const groups: string[][] = [];
  for (let g = 0; g < nplanes; g += 3) {
    groups.push([g, g + 1, g + 2].map((q) => (q < nplanes ? `P${q}` : `X${q}`)));
  }
  return groups;
}

const describe = (x: unknown): string => {
  const s = JSON.stringify(x);
  return s === undefined ? 'nothing' : s.length > 40 ? `${s.slice(0, 37)}...` : s;
};

/** An integer in `[lo, hi]`, or a one-line error naming `path`. */
function integerIn(x: unknown, lo: number, hi: number, path: string): number {
  if (typeof x !== 'number' || !Number.isInteger(x) || x < lo || x > hi) {
    throw new RelightServiceError(`${path} must be an integer in ${lo}..${hi}, got ${describe(x)}`);
  }
  return x;
}

/** An array of `n` numbers each passing `ok`, or a one-line error naming the first bad entry. */
function numberArray(x: unknown, n: number, path: string, ok: (v: number) => boolean, what: string): number[] {
  if (!Array.isArray(x)) {
    throw new RelightServiceError(`${path} must be an array of ${n} values, got ${describe(x)}`);
  }
  if (x.length !== n) {
    throw new RelightServiceError(`${path}: ${x.length} values, expected ${n}`);
  }
  const bad = x.findIndex((v) => typeof v !== 'number' || !ok(v));
  if (bad >= 0) {
    throw new RelightServiceError(`${path}[${bad}] must be ${what}, got ${describe(x[bad])}`);
  }
  return x as number[];
}

const finite = (v: number): boolean => Number.isFinite(v);
const positive = (v: number): boolean => Number.isFinite(v) && v > 0;
const byte = (v: number): boolean => Number.isInteger(v) && v >= 0 && v <= 255;

/** mycc's `yccplanes` `[ny, nc, nc]` with `ny + 2·nc = N`. */
function parseYccPlanes(x: unknown, nplanes: number, path: string): [number, number, number] {
  const [ny, nc, nc2] = numberArray(x, 3, path, (v) => Number.isInteger(v) && v >= 0, 'an integer >= 0');
  if (nc !== nc2 || (ny ?? 0) + 2 * (nc ?? 0) !== nplanes || (ny ?? 0) < 1) {
    throw new RelightServiceError(`${path} must be [ny, nc, nc] with ny >= 1 and ny + 2·nc = nplanes `
      + `(${nplanes}), got ${describe(x)}`);
  }
  return [ny ?? 0, nc ?? 0, nc2 ?? 0];
}

/** The light samples of the basis: rbf's acquisition lights and σ, or bilinear's grid. */
function parseSamples(block: Json, layerType: PcaType, at: string):
  Pick<PcaBasis, 'ndimensions' | 'lights' | 'sigma' | 'resolution'> {
  if (layerType === 'bilinear') {
    const resolution = integerIn(block.resolution, 2, 256, `${at}resolution`);
    return { ndimensions: resolution * resolution, lights: null, sigma: 0, resolution };
  }
  const given = block.lights;
  const count = Array.isArray(given) ? given.length : 0;
  if (count === 0 || count % 3 !== 0) {
    throw new RelightServiceError(`${at}lights must be a non-empty array of D·3 numbers, got ${describe(given)}`);
  }
  const lights = numberArray(given, count, `${at}lights`, finite, 'a finite number');
  const sigma = block.sigma;
  if (typeof sigma !== 'number' || !positive(sigma)) {
    throw new RelightServiceError(`${at}sigma must be a number > 0, got ${describe(sigma)}`);
  }
  return { ndimensions: count / 3, lights: Float64Array.from(lights), sigma, resolution: 0 };
}

/**
 * Validate and decode the PCA fields of a relight block of type `rbf` or `bilinear`.
 *
 * @param at - the JSON path prefix errors name (e.g. `rbf27.`)
 * @throws {@link RelightServiceError} naming the field and the value that breaks the contract
 */
export function parsePcaBlock(block: Json, layerType: PcaType, at: string): PcaBasis {
  const colorspace = block.colorspace;
  if (!(PCA_COLORSPACES as readonly unknown[]).includes(colorspace)) {
    throw new RelightServiceError(`${at}colorspace: unsupported colour space ${describe(colorspace)} for `
      + `${layerType} (${PCA_COLORSPACES.join(', ')})`);
  }
  const cs = colorspace as PcaColorspace;
  const nplanes = integerIn(block.nplanes, 1, MAX_PCA_PLANES, `${at}nplanes`);
  const yccplanes = cs === 'mycc' ? parseYccPlanes(block.yccplanes, nplanes, `${at}yccplanes`) : null;
  const ranges = numberArray(block.range, nplanes, `${at}range`, positive, 'a number > 0');
  const samples = parseSamples(block, layerType, at);
  const bytes = numberArray(block.basis, (nplanes + 1) * samples.ndimensions * 3, `${at}basis`, byte,
    'an integer in 0..255');
  return {
    layerType,
    colorspace: cs,
    nplanes,
    values: decodeBasis(bytes, ranges, samples.ndimensions),
    yccplanes,
    ...samples,
  };
}
