/**
 * The help overlay: a modal dialog listing gestures and keys ({@link HELP_SECTIONS}). Esc or the
 * Close button closes it; Tab stays inside while it is open; focus returns to where it was.
 */
import { HELP_SECTIONS } from './help-content';

/** The overlay and its controls. */
export interface HelpOverlay {
  readonly element: HTMLElement;
  open(): void;
  close(): void;
  isOpen(): boolean;
  destroy(): void;
}

/** The elements inside `root` that Tab reaches. */
function focusables(root: HTMLElement): HTMLElement[] {
  return [...root.querySelectorAll<HTMLElement>('button, [href], input, select, textarea, [tabindex]')]
    .filter((el) => el.tabIndex >= 0 && !el.hasAttribute('disabled'));
}

/** Create the (closed) overlay in `parent` (default `document.body`). */
export function createHelpOverlay(parent: HTMLElement = document.body): HelpOverlay {
  const backdrop = document.createElement('div');
  backdrop.className = 'lanterna-help';
  backdrop.hidden = true;
  const dialog = document.createElement('div');
  dialog.className = 'lanterna-help-dialog';
  dialog.setAttribute('role', 'dialog');
  dialog.setAttribute('aria-modal', 'true');
  dialog.setAttribute('aria-labelledby', 'lanterna-help-title');
  dialog.tabIndex = -1;
  const title = document.createElement('h2');
  title.id = 'lanterna-help-title';
  title.textContent = 'Gestures and keys';
  dialog.append(title);
  for (const section of HELP_SECTIONS) {
    const h = document.createElement('h3');
    h.textContent = section.title;
    const list = document.createElement('dl');
    for (const [what, does] of section.rows) {
      const dt = document.createElement('dt');
      dt.textContent = what;
      const dd = document.createElement('dd');
      dd.textContent = does;
      list.append(dt, dd);
    }
    dialog.append(h, list);
  }
  const close = document.createElement('button');
  close.type = 'button';
  close.className = 'lanterna-tool lanterna-help-close';
  close.textContent = 'Close';
  dialog.append(close);
  backdrop.append(dialog);
  parent.append(backdrop);

  let returnTo: Element | null = null;
  const overlay: HelpOverlay = {
    element: backdrop,
    open() {
      if (!backdrop.hidden) {
        return;
      }
      returnTo = document.activeElement;
      backdrop.hidden = false;
      close.focus();
    },
    close() {
      if (backdrop.hidden) {
        return;
      }
      backdrop.hidden = true;
      if (returnTo instanceof HTMLElement) {
        returnTo.focus();
      }
      returnTo = null;
    },
    isOpen: () => !backdrop.hidden,
    destroy() {
      backdrop.remove();
    },
  };
  close.addEventListener('click', () => { overlay.close(); });
  backdrop.addEventListener('click', (ev) => {
    if (ev.target === backdrop) {
      overlay.close();
    }
  });
  backdrop.addEventListener('keydown', (ev) => {
    if (ev.key === 'Escape') {
      ev.preventDefault();
      overlay.close();
    } else if (ev.key === 'Tab') {
      // Keep Tab inside the dialog: wrap from the last control to the first and back.
      const items = focusables(dialog);
      const first = items[0];
      const last = items[items.length - 1];
      if (!first || !last) {
        ev.preventDefault();
      } else if (ev.shiftKey && (document.activeElement === first || !dialog.contains(document.activeElement))) {
        ev.preventDefault();
        last.focus();
      } else if (!ev.shiftKey && (document.activeElement === last || !dialog.contains(document.activeElement))) {
        ev.preventDefault();
        first.focus();
      }
    }
    ev.stopPropagation();
  });
  return overlay;
}
