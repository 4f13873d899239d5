/**
 * The page's layout: the panel beside the viewer on wide screens, a bottom sheet on small ones
 * (collapsed there by default on touch screens), a toggle button for it, and Home fitting the object into the part of
 * the viewer the toolbar and the panel leave free.
 */
import type { LanternaViewer } from '../index';
import { freeArea, homeRegion, type Box } from './home-fit';

/** Small screens: phones in portrait (narrow) or landscape (short). */
export const SMALL_SCREEN = '(max-width: 600px), (max-height: 430px)';
/** Touch screens: the panel starts collapsed on small ones (a small desktop window keeps it open). */
export const TOUCH_SCREEN = '(pointer: coarse)';

/** The page layout's controls. */
export interface Layout {
  /** Show or hide the panel. */
  setPanelOpen(open: boolean): void;
  isPanelOpen(): boolean;
  /** Fit the whole object into the free area, immediately. */
  home(): void;
}

function boxIn(el: HTMLElement | null, origin: DOMRect): Box | null {
  if (!el || el.hidden) {
    return null;
  }
  const r = el.getBoundingClientRect();
  if (r.width === 0 || r.height === 0) {
    return null;
  }
  return { left: r.left - origin.left, top: r.top - origin.top, right: r.right - origin.left, bottom: r.bottom - origin.top };
}

/** Wire the panel toggle `toggle` to `panel` and provide Home for `lanterna`. */
export function createLayout(lanterna: LanternaViewer, panel: HTMLElement, toolbar: HTMLElement,
  toggle: HTMLButtonElement): Layout {
  const small = window.matchMedia(SMALL_SCREEN);
  const touch = window.matchMedia(TOUCH_SCREEN);
  const collapsed = (): boolean => small.matches && touch.matches;
  let open = !collapsed();
  const apply = (): void => {
    panel.hidden = !open;
    document.body.classList.toggle('lanterna-small', small.matches);
    toggle.setAttribute('aria-expanded', String(open));
    toggle.title = open ? 'Hide the panel' : 'Show the panel (layer, mode, lens, presets, about)';
  };
  toggle.addEventListener('click', () => {
    open = !open;
    apply();
  });
  small.addEventListener('change', () => {
    open = !collapsed();
    apply();
  });
  apply();
  return {
    setPanelOpen(value) {
      open = value;
      apply();
    },
    isPanelOpen: () => open,
    home() {
      const info = lanterna.manifest;
      const element = lanterna.viewer.element;
      if (!info) {
        lanterna.viewer.viewport.goHome(true);
        return;
      }
      const origin = element.getBoundingClientRect();
      const free = freeArea(origin.width, origin.height, boxIn(toolbar, origin), boxIn(panel, origin));
      const [x, y, w, h] = homeRegion(origin.width, origin.height, free, info.layer.width, info.layer.height);
      lanterna.showImageRegion(x, y, w, h);
    },
  };
}
