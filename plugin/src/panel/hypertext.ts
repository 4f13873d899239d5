/**
 * The hypertext widget: the short text of the overlay level shown now, expandable to its long text
 * (sanitised HTML), or "No annotation at this level".
 */
import type { OverlayState } from '../overlay/overlay-state';

/** The widget's DOM and its update function. */
export interface HypertextWidget {
  readonly element: HTMLElement;
  /**
   * Show a state. `hasOverlay` = the active layer has any overlay level (else the widget hides);
   * `visible` = overlays are switched on (else the widget hides).
   */
  update(state: OverlayState, hasOverlay: boolean, visible: boolean): void;
  destroy(): void;
}

/** The text shown at a level without an overlay image. */
export const NO_ANNOTATION_TEXT = 'No annotation at this level';

/** Create the widget inside `parent` (bottom-right corner, `bottom` CSS px above its bottom edge). */
export function createHypertext(parent: HTMLElement, bottom = 12): HypertextWidget {
  const box = document.createElement('section');
  box.className = 'lanterna-hypertext';
  box.setAttribute('aria-label', 'Annotation');
  box.setAttribute('aria-live', 'polite');
  Object.assign(box.style, {
    position: 'absolute', right: '12px', bottom: `${bottom}px`, zIndex: '10', maxWidth: 'min(360px, 60%)',
    maxHeight: '45%', overflow: 'auto', boxSizing: 'border-box', padding: '8px 12px', borderRadius: '6px',
    background: 'rgba(20, 20, 20, 0.82)', border: '1px solid #444', color: '#eee',
    font: '13px system-ui, sans-serif', lineHeight: '1.4',
  });
  const head = document.createElement('div');
  Object.assign(head.style, { display: 'flex', gap: '8px', alignItems: 'baseline', justifyContent: 'space-between' });
  const short = document.createElement('div');
  short.className = 'lanterna-hypertext-short';
  const more = document.createElement('button');
  more.type = 'button';
  more.className = 'lanterna-hypertext-more';
  more.textContent = 'More';
  more.setAttribute('aria-expanded', 'false');
  Object.assign(more.style, {
    font: 'inherit', padding: '1px 8px', borderRadius: '4px', border: '1px solid #777', background: '#222',
    color: '#eee', cursor: 'pointer',
  });
  const long = document.createElement('div');
  long.className = 'lanterna-hypertext-long';
  long.hidden = true;
  Object.assign(long.style, { marginTop: '6px', borderTop: '1px solid #3a3a3a', paddingTop: '6px' });
  head.append(short, more);
  box.append(head, long);
  box.hidden = true;
  parent.appendChild(box);

  let expanded = false;
  let shownLong = '';
  const setExpanded = (value: boolean): void => {
    expanded = value;
    long.hidden = !expanded || shownLong === '';
    more.textContent = expanded ? 'Less' : 'More';
    more.setAttribute('aria-expanded', String(expanded));
  };
  more.addEventListener('click', () => { setExpanded(!expanded); });
  // Clicks and drags on the widget must not reach the viewer (no light change, no pan).
  for (const type of ['pointerdown', 'wheel', 'dblclick'] as const) {
    box.addEventListener(type, (e) => { e.stopPropagation(); });
  }

  return {
    element: box,
    update(state, hasOverlay, visible) {
      box.hidden = !hasOverlay || !visible;
      if (!state.available) {
        short.textContent = NO_ANNOTATION_TEXT;
        short.style.color = '#999';
        more.hidden = true;
        shownLong = '';
        long.replaceChildren();
        setExpanded(expanded);
        return;
      }
      short.textContent = state.short || 'Annotation';
      short.style.color = '';
      more.hidden = state.long === '';
      if (state.long !== shownLong) {
        shownLong = state.long;
        // `state.long` is the output of sanitizeHtml: only allow-listed tags and attributes.
        long.innerHTML = state.long;
      }
      setExpanded(expanded);
    },
    destroy() {
      box.remove();
    },
  };
}
