/**
 * Fullscreen: the page's button, and the request made on a user gesture (browsers refuse one made
 * without). The whole page goes fullscreen, so the menus stay with the image.
 */

/** Whether the page is fullscreen now. */
export function isFullscreen(doc: Document): boolean {
  return doc.fullscreenElement !== null;
}

/** Ask for fullscreen (from a user gesture); a refusal is logged, never shown. */
export function enterFullscreen(doc: Document): void {
  if (!doc.fullscreenEnabled || isFullscreen(doc)) {
    return;
  }
  doc.documentElement.requestFullscreen({ navigationUI: 'hide' }).catch((error: unknown) => {
    console.warn('[lanterna] fullscreen refused:', error);
  });
}

/**
 * Make `button` toggle fullscreen and show the state (`aria-pressed`, its label); hidden when the
 * browser has no fullscreen for this page. Returns a function removing the listeners.
 */
export function wireFullscreenButton(button: HTMLButtonElement, doc: Document): () => void {
  const label = button.querySelector('.label') ?? button;
  const sync = (): void => {
    const on = isFullscreen(doc);
    button.setAttribute('aria-pressed', String(on));
    label.textContent = on ? 'Exit full screen' : 'Full screen';
  };
  const click = (): void => {
    if (isFullscreen(doc)) {
      doc.exitFullscreen().catch((error: unknown) => { console.warn('[lanterna]', error); });
    } else {
      enterFullscreen(doc);
    }
  };
  button.hidden = !doc.fullscreenEnabled;
  button.addEventListener('click', click);
  doc.addEventListener('fullscreenchange', sync);
  sync();
  return () => {
    button.removeEventListener('click', click);
    doc.removeEventListener('fullscreenchange', sync);
  };
}
