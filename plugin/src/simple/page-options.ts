/**
 * The simplified viewer's URL: `simple.html?manifest=URL[&presets=URL][&kiosk=1][&idle=SECONDS]`
 * (docs/simple-viewer.md). Pure: reads a query string, touches no DOM.
 */

/** How long a kiosk waits without input before it returns to its first preset (s). */
export const DEFAULT_IDLE_SECONDS = 120;
/** How often the page tries again to open an object that could not be opened (s). */
export const RETRY_SECONDS = 30;

/** The page's options, read from its URL. */
export interface SimplePageOptions {
  /** The manifest's URL (absolute). */
  readonly manifest: string;
  /** The preset library's URL (absolute), or undefined: the manifest's own. */
  readonly presets: string | undefined;
  /** Kiosk mode: fullscreen, no context menu or selection, idle reset, no dialogs. */
  readonly kiosk: boolean;
  /** Seconds without input before the reset; 0: never. */
  readonly idleSeconds: number;
  /** Test-only: OpenSeadragon's `minPixelRatio` (as on the advanced page), or null. */
  readonly minPixelRatio: number | null;
  /** Test-only: the advanced page's `wholeLevelMaxSide`, or undefined. */
  readonly wholeLevelMaxSide: number | undefined;
  /** Seconds between two tries to open an object that could not be opened (test-only `&retry=`). */
  readonly retrySeconds: number;
}

/** The URL does not say what to show. */
export class PageOptionsError extends Error {}

const TRUE = new Set(['1', 'true', 'yes', 'on', '']);

/** A finite number ≥ 0 from a parameter, or undefined. */
function number(value: string | null): number | undefined {
  if (value === null || value.trim() === '') {
    return undefined;
  }
  const n = Number(value);
  return Number.isFinite(n) && n >= 0 ? n : undefined;
}

/**
 * Read the page's options from its query string, resolving URLs against `base` (the page's URL).
 * `idle` applies in kiosk mode (default {@link DEFAULT_IDLE_SECONDS}) and, when given, without it.
 *
 * @throws {@link PageOptionsError} without a manifest, or when a URL cannot be read
 */
export function readPageOptions(search: string, base: string): SimplePageOptions {
  const params = new URLSearchParams(search);
  const resolve = (name: string): string | undefined => {
    const value = params.get(name);
    if (value === null || value === '') {
      return undefined;
    }
    try {
      return new URL(value, base).href;
    } catch {
      throw new PageOptionsError(`the ${name} parameter is not a URL: ${JSON.stringify(value)}`);
    }
  };
  const manifest = resolve('manifest');
  if (manifest === undefined) {
    throw new PageOptionsError('no manifest given: open this page as …/viewer/simple.html?manifest=URL_OF_MANIFEST.json');
  }
  const kioskValue = params.get('kiosk');
  const kiosk = kioskValue !== null && TRUE.has(kioskValue.toLowerCase());
  const idle = number(params.get('idle'));
  const ratio = number(params.get('minPixelRatio'));
  const retry = number(params.get('retry'));
  return {
    manifest,
    presets: resolve('presets'),
    kiosk,
    idleSeconds: idle ?? (kiosk ? DEFAULT_IDLE_SECONDS : 0),
    minPixelRatio: ratio !== undefined && ratio > 0 ? ratio : null,
    wholeLevelMaxSide: number(params.get('wholeLevelMaxSide')),
    retrySeconds: retry !== undefined && retry > 0 ? retry : RETRY_SECONDS,
  };
}
