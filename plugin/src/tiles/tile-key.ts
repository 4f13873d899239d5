/**
 * Cache key of a bundle tile. Pure.
 */

/** Separator between plane URLs in a bundle's cache key (cannot occur in a URL). */
export const BUNDLE_KEY_SEPARATOR = '\n';

/**
 * The cache key of a bundle: every plane URL, in plane order, so two layers that reuse the same
 * planes share cache records, and two bundles differing in any plane never collide.
 */
export function bundleKey(urls: readonly string[]): string {
  return urls.join(BUNDLE_KEY_SEPARATOR);
}
