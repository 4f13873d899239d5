/**
 * The simplified viewer's controls on a running viewer (seed paper §6.2.2, §6.3): the base-preset
 * menu, the lens-preset menu, the lens toggle and the measurement toggle, and the return to the
 * start (the first base preset, lens off, the home view) that a kiosk makes after a quiet period.
 * Everything else is done by gestures on the image (the viewer's own: one finger lights, two fingers
 * pan and pinch the image or, starting inside the lens, move and scale the lens).
 */
import type { LanternaViewer } from '../index';
import { simpleControls, type SimpleControls } from './capabilities';
import { connectMeasurement, type MeasurementMode } from './measurement';
import type { PageNote } from './page-note';
import { createPresetMenu } from './preset-menu';

/** The page's elements the controls live in. */
export interface SimpleElements {
  readonly baseMenu: HTMLElement;
  readonly baseList: HTMLElement;
  readonly lensMenu: HTMLElement;
  readonly lensList: HTMLElement;
  readonly lensToggle: HTMLButtonElement;
  readonly measureToggle: HTMLButtonElement;
}

/** The running controls. */
export interface SimpleViewer {
  /** Which controls are shown. */
  readonly controls: SimpleControls;
  /** Back to the start: measurement off, lens off (and where it began), home view, first base preset. */
  reset(): Promise<void>;
  destroy(): void;
}

/** What the page says about a failed action (the kiosk: a calm line; else the error's message). */
function failureText(error: unknown, kiosk: boolean): string {
  if (kiosk || !(error instanceof Error)) {
    return 'That view could not be shown.';
  }
  return error.message;
}

/**
 * Build the controls for `lanterna` (ready) and go to the start. Actions run one after the other, in
 * the order they were asked for; a failed one is logged and told in `note`.
 */
export async function startSimpleViewer(lanterna: LanternaViewer, elements: SimpleElements, note: PageNote,
  kiosk: boolean): Promise<SimpleViewer> {
  const library = lanterna.getPresetLibrary();
  const controls = simpleControls(library, lanterna.getLayers());
  const start = { layer: lanterna.getActiveLayer(), mode: lanterna.getRenderMode(), light: lanterna.getLight() };
  let lensIndex = 0;
  let measuring = false;
  const measurement: MeasurementMode | null = controls.measureToggle
    ? connectMeasurement(lanterna, lanterna.viewer.element) : null;

  let queue: Promise<void> = Promise.resolve();
  const run = (action: () => Promise<void> | void): Promise<void> => {
    queue = queue.then(action).catch((error: unknown) => {
      console.warn('[lanterna]', error);
      note.show(failureText(error, kiosk));
    });
    return queue;
  };

  const sync = (): void => {
    const on = lanterna.getLens().enabled;
    elements.lensToggle.setAttribute('aria-pressed', String(on));
    lensMenu.setActive(on && controls.lensMenu ? lensIndex : null);
    elements.measureToggle.setAttribute('aria-pressed', String(measuring));
  };
  const baseMenu = createPresetMenu(elements.baseList, library.base.map((e) => e.label), (index) => {
    void run(async () => {
      await lanterna.applyPreset('base', index);
      baseMenu.setActive(index);
    });
  });
  const lensMenu = createPresetMenu(elements.lensList, library.lens.map((e) => e.label), (index) => {
    void run(async () => {
      await lanterna.applyPreset('lens', index); // switches the lens on
      lensIndex = index;
      sync();
    });
  });
  const setMeasuring = (on: boolean): void => {
    measuring = on && measurement !== null;
    measurement?.setEnabled(measuring);
    sync();
  };
  const toggleLens = (): void => {
    void run(async () => {
      if (lanterna.getLens().enabled) {
        await lanterna.setLens({ enabled: false });
      } else if (controls.lensMenu) {
        await lanterna.applyPreset('lens', lensIndex);
      } else {
        await lanterna.setLens({ enabled: true }); // no presets: the lens shows the base layer
      }
      sync();
    });
  };
  const toggleMeasure = (): void => { setMeasuring(!measuring); };
  elements.lensToggle.addEventListener('click', toggleLens);
  elements.measureToggle.addEventListener('click', toggleMeasure);
  elements.baseMenu.hidden = !controls.baseMenu;
  elements.lensMenu.hidden = !controls.lensMenu;
  elements.lensToggle.hidden = !controls.lensToggle;
  elements.measureToggle.hidden = !controls.measureToggle;
  const unsubscribe = lanterna.onChange(sync);
  // The lens starts in the middle of the viewer as the page is laid out now, with its menus (the
  // viewer was made before them, in a larger element).
  const box = lanterna.viewer.element;
  const lensHome = {
    center: [box.clientWidth / 2, box.clientHeight / 2] as const,
    radius: Math.min(box.clientWidth, box.clientHeight) / 5,
  };

  const reset = (): Promise<void> => run(async () => {
    setMeasuring(false);
    lensIndex = 0;
    await lanterna.setLens({ enabled: false, ...lensHome });
    lanterna.viewer.viewport.goHome(true);
    if (controls.baseMenu) {
      await lanterna.applyPreset('base', 0); // its view, if it has one, replaces the home view
      baseMenu.setActive(0);
    } else {
      await lanterna.setActiveLayer(start.layer);
      lanterna.setRenderMode(start.mode);
      lanterna.resetRenderParams();
      lanterna.setLight(start.light.lu, start.light.lv);
    }
    sync();
  });

  if (controls.noPresets) {
    note.show('No presets for this object: it is shown in its default rendering.');
  }
  await reset();
  return {
    controls,
    reset,
    destroy() {
      unsubscribe();
      elements.lensToggle.removeEventListener('click', toggleLens);
      elements.measureToggle.removeEventListener('click', toggleMeasure);
      measurement?.destroy();
    },
  };
}
