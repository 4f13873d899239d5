/** Small guards for reading untyped JSON (manifests, service blocks) without `any`. */

/** A JSON object. */
export type Json = Record<string, unknown>;

/** True for a non-null, non-array object. */
export function isRecord(x: unknown): x is Json {
  return typeof x === 'object' && x !== null && !Array.isArray(x);
}

/** The value as a list: arrays as they are, a single value wrapped, null/undefined as `[]`. */
export function asArray(x: unknown): unknown[] {
  if (Array.isArray(x)) {
    return x;
  }
  return x === undefined || x === null ? [] : [x];
}
