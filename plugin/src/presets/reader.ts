/**
 * Reading untyped JSON with errors that name the JSON path (`source: base[2].layer: problem`). Pure.
 */
import { PresetError } from './library';

const ID = /^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$/;
/** Longest label. */
export const MAX_LABEL = 200;
/** Longest list. */
const MAX_ENTRIES = 64;

/** A JSON object. */
export type Obj = Record<string, unknown>;

/** True for a non-null, non-array object. */
export function isObj(x: unknown): x is Obj {
  return typeof x === 'object' && x !== null && !Array.isArray(x);
}



/** Reads one document, failing with `source: path: problem`. */
export class Reader {
  constructor(private readonly source: string) {}

  fail(path: string, problem: string): never {
    throw new PresetError(`${this.source}: ${path || '(top level)'}: ${problem}`);
  }

  object(x: unknown, path: string, allowed: readonly string[], required: readonly string[]): Obj {
    if (!isObj(x)) {
      this.fail(path, `expected an object, got ${describe(x)}`);
    }
    for (const key of Object.keys(x)) {
      if (!allowed.includes(key)) {
        this.fail(join(path, key), `unknown field (expected one of ${allowed.join(', ')})`);
      }
    }
    for (const key of required) {
      if (!(key in x)) {
        this.fail(join(path, key), 'is missing');
      }
    }
    return x;
  }

  label(x: unknown, path: string): string {
    if (typeof x !== 'string' || x.length === 0 || x.length > MAX_LABEL) {
      this.fail(path, `expected a non-empty text of at most ${MAX_LABEL} characters, got ${describe(x)}`);
    }
    return x;
  }

  id(x: unknown, path: string): string {
    if (typeof x !== 'string' || !ID.test(x)) {
      this.fail(path, `expected an id (a letter or digit, then letters, digits, '.', '_' or '-'; at most 64), `
        + `got ${describe(x)}`);
    }
    return x;
  }

  number(x: unknown, path: string, min: number, max: number): number {
    if (typeof x !== 'number' || !Number.isFinite(x) || x < min || x > max) {
      this.fail(path, `expected a number from ${min} to ${max}, got ${describe(x)}`);
    }
    return x;
  }

  numbers(x: unknown, path: string, n: number): number[] {
    if (!Array.isArray(x) || x.length !== n || !x.every((v) => typeof v === 'number' && Number.isFinite(v))) {
      this.fail(path, `expected ${n} numbers, got ${describe(x)}`);
    }
    return x as number[];
  }

  list(x: unknown, path: string): unknown[] {
    if (!Array.isArray(x)) {
      this.fail(path, `expected a list, got ${describe(x)}`);
    }
    if (x.length > MAX_ENTRIES) {
      this.fail(path, `at most ${MAX_ENTRIES} entries, got ${x.length}`);
    }
    return x;
  }
}

export function join(path: string, key: string | number): string {
  if (typeof key === 'number') {
    return `${path}[${key}]`;
  }
  return path ? `${path}.${key}` : key;
}

export function describe(x: unknown): string {
  const text = JSON.stringify(x) ?? String(x);
  return text.length > 60 ? `${text.slice(0, 57)}…` : text;
}

