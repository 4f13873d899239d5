/**
 * `mountViewTools`: the shareable-view tools on a page in one call: the URL hash kept in step with
 * the view, the snapshot and help buttons in the page's toolbar, the scale bar, the help overlay and
 * the canvas keys (`docs/viewer-api.md`).
 */
import type { LanternaViewer } from '../api/viewer-api';
import { attempt as attemptReporting } from '../errors';
import { createHelpOverlay, type HelpOverlay } from './help-overlay';
import { attachKeys } from './keys';
import { createScaleBar, type ScaleBarWidget } from './scale-bar';
import { downloadSnapshot } from './snapshot-download';
import { addToolStyles } from './tool-styles';
import { attachUrlState } from './url-state';

/** Options of {@link mountViewTools}. */
export interface ViewToolsOptions {
  /** Where the Snapshot and ? buttons go (appended); none: no buttons (the keys still work). */
  readonly toolbar?: HTMLElement | null;
  /** Keep the URL hash and the view in step ({@link attachUrlState}). @default true */
  readonly urlState?: boolean;
  /** What H does. @default the viewport's home */
  readonly home?: () => void;
  /** The NAME of snapshot files `NAME_layer_mode.png`. @default the dataset's label */
  readonly name?: string;
  /** Class names added to the buttons (to match the page's own). */
  readonly buttonClass?: string;
}

/** The mounted tools. */
export interface ViewTools {
  readonly help: HelpOverlay;
  readonly scaleBar: ScaleBarWidget;
  /** The toolbar buttons (none without a toolbar). */
  readonly buttons: { readonly snapshot: HTMLButtonElement | null; readonly help: HTMLButtonElement | null };
  /** Save a snapshot of the view (the S key and the button). */
  snapshot(): Promise<void>;
  destroy(): void;
}

function button(text: string, title: string, extra: string | undefined): HTMLButtonElement {
  const b = document.createElement('button');
  b.type = 'button';
  b.className = `lanterna-tool${extra ? ` ${extra}` : ''}`;
  b.textContent = text;
  b.title = title;
  return b;
}

/** Mount the tools for `lanterna`; `destroy` removes them. */
export function mountViewTools(lanterna: LanternaViewer, options: ViewToolsOptions = {}): ViewTools {
  addToolStyles();
  const help = createHelpOverlay();
  const scaleBar = createScaleBar(lanterna);
  const snapshot = (): Promise<void> => downloadSnapshot(lanterna, options.name).catch((error: unknown) => {
    lanterna.reportError(error);
  });
  const attempt = (action: () => unknown): void => {
    attemptReporting(action, (error) => { lanterna.reportError(error); });
  };
  const detachKeys = attachKeys(lanterna, {
    lens: () => { attempt(() => lanterna.setLens({ enabled: !lanterna.getLens().enabled })); },
    annotations: () => { lanterna.setOverlaysVisible(!lanterna.getOverlaysVisible()); },
    home: () => { (options.home ?? (() => { lanterna.viewer.viewport.goHome(); }))(); },
    snapshot: () => { void snapshot(); },
    help: () => { help.open(); },
  });
  const detachUrl = options.urlState === false ? () => undefined : attachUrlState(lanterna);
  let snapshotButton: HTMLButtonElement | null = null;
  let helpButton: HTMLButtonElement | null = null;
  if (options.toolbar) {
    snapshotButton = button('Snapshot', 'Save a PNG of the view (S)', options.buttonClass);
    snapshotButton.addEventListener('click', () => { void snapshot(); });
    helpButton = button('?', 'Gestures and keys (?)', options.buttonClass);
    helpButton.setAttribute('aria-label', 'Help: gestures and keys');
    helpButton.setAttribute('aria-haspopup', 'dialog');
    helpButton.addEventListener('click', () => { help.open(); });
    options.toolbar.append(snapshotButton, helpButton);
  }
  return {
    help,
    scaleBar,
    buttons: { snapshot: snapshotButton, help: helpButton },
    snapshot,
    destroy() {
      detachKeys();
      detachUrl();
      help.destroy();
      scaleBar.destroy();
      snapshotButton?.remove();
      helpButton?.remove();
    },
  };
}
