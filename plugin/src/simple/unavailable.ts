/**
 * The calm full-screen message shown when the object cannot be opened (the server is down, the
 * manifest is missing, no WebGL2): no dialog, nothing to dismiss; the page tries again on its own.
 */

/** The message screen. */
export interface UnavailableScreen {
  /**
   * Show it; `detail` (what went wrong) is shown small below, or not at all (kiosk); `retrying`:
   * say that the page tries again.
   */
  show(detail: string | null, retrying: boolean): void;
  hide(): void;
}

/** Use `element` (the page's `#unavailable`) as the message screen. */
export function createUnavailableScreen(element: HTMLElement, retrySeconds: number): UnavailableScreen {
  const title = document.createElement('p');
  title.className = 'title';
  title.textContent = 'This object is not available right now';
  const again = document.createElement('p');
  again.className = 'retry';
  again.textContent = `Trying again every ${retrySeconds} seconds.`;
  const detail = document.createElement('p');
  detail.className = 'detail';
  element.replaceChildren(title, again, detail);
  element.setAttribute('role', 'status');
  element.hidden = true;
  return {
    show(text, retrying) {
      again.hidden = !retrying;
      detail.textContent = text ?? '';
      detail.hidden = text === null;
      element.hidden = false;
    },
    hide() {
      element.hidden = true;
    },
  };
}
