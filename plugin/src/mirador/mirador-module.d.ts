/**
 * The parts of the `mirador` package (4.0–4.2) that the plugin imports: Mirador ships no types.
 * Read from Mirador 4.0.0's `src/state/selectors/*`, `src/state/actions/*` and `src/init.js`.
 */
declare module 'mirador' {
  /** The current canvas of a window: a manifesto.js Canvas (its JSON in `__jsonld`). */
  export function getCurrentCanvas(state: unknown, props: { windowId: string }):
    { readonly id: string; readonly __jsonld?: unknown } | undefined;
  /** A window's manifest entry (`manifests[window.manifestId]`). */
  export function getManifest(state: unknown, props: { windowId: string }):
    { readonly id: string; readonly json?: unknown; readonly isFetching?: boolean } | undefined;
  /** A canvas's layer states, by image resource id (undefined until a layer is changed). */
  export function getLayers(state: unknown, props: { windowId: string; canvasId: string }):
    Readonly<Record<string, { visibility?: boolean; opacity?: number; index?: number }>> | undefined;
  export function updateLayers(windowId: string, canvasId: string,
    payload: Readonly<Record<string, { visibility?: boolean; opacity?: number; index?: number }>>): unknown;
  export function updateViewport(windowId: string, payload: Readonly<Record<string, unknown>>): unknown;
  /** Mount Mirador in `config.id`; returns the instance (its redux store in `.store`). */
  export function viewer(config: Readonly<Record<string, unknown>>, plugins?: readonly unknown[]):
    { readonly store: unknown };
}
