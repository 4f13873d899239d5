/**
 * The page's note: one short line over the image that clears itself after a while (a notice never
 * needs to be dismissed, least of all by a museum visitor). Screen readers hear it (`role=status`).
 */

/** The note's default time on screen (s). */
export const NOTE_SECONDS = 8;

/** The note and how to show it. */
export interface PageNote {
  /** Show `text` for `seconds` (replacing the note shown). */
  show(text: string, seconds?: number): void;
  /** Hide it now. */
  clear(): void;
  /** The text shown now ('' when hidden). */
  text(): string;
}

/** Use `element` (hidden at first) as the page's note. */
export function createPageNote(element: HTMLElement): PageNote {
  let timer: ReturnType<typeof setTimeout> | null = null;
  element.setAttribute('role', 'status');
  element.setAttribute('aria-live', 'polite');
  const clear = (): void => {
    if (timer !== null) {
      clearTimeout(timer);
      timer = null;
    }
    element.textContent = '';
    element.hidden = true;
  };
  clear();
  return {
    show(text, seconds = NOTE_SECONDS) {
      clear();
      element.textContent = text;
      element.hidden = false;
      timer = setTimeout(clear, seconds * 1000);
    },
    clear,
    text: () => (element.hidden ? '' : element.textContent ?? ''),
  };
}
