/**
 * Which standard OpenSeadragon drawer a page's viewer gets back when an attached Lanterna viewer is
 * destroyed (docs/embedding.md): the one it had, if it was a standard one, else WebGL, else canvas.
 */

/** OpenSeadragon 6's own drawers, by their `getType()`. */
export const STANDARD_DRAWERS: readonly string[] = ['webgl', 'canvas', 'html'];

/**
 * The drawer types to request, in order, for a viewer whose drawer had type `previous` before
 * Lanterna's (`null`: none, or not known).
 */
export function restoreCandidates(previous: string | null): string[] {
  const fallback = ['webgl', 'canvas'];
  if (previous !== null && STANDARD_DRAWERS.includes(previous)) {
    return [previous, ...fallback.filter((t) => t !== previous)];
  }
  return fallback;
}
