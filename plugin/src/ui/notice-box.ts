/**
 * The notice box: short, non-blocking messages over the viewer (the context is lost, some tiles
 * could not be loaded, an error), each with an optional button (Retry, Dismiss). The box takes no
 * pointer events, so the image can be dragged and zoomed under it; only its buttons do.
 */

/** How a notice looks: a warning (amber) or an error (red). */
export type NoticeTone = 'warning' | 'error';

/** One notice as the box shows it. */
export interface NoticeView {
  /** Stable name (`data-kind` of its element). */
  readonly kind: string;
  readonly tone: NoticeTone;
  readonly message: string;
  /** Longer text (URLs, reasons), shown as the notice's tooltip. */
  readonly detail?: string;
  /** A button after the message. */
  readonly action?: { readonly label: string; readonly title?: string; readonly run: () => void };
}

/** The box and its update function. */
export interface NoticeBox {
  readonly element: HTMLElement;
  /** Show these notices (none: the box hides). */
  update(notices: readonly NoticeView[]): void;
  destroy(): void;
}

/** Options of {@link createNoticeBox}. */
export interface NoticeBoxOptions {
  /**
   * Distance from the bottom of the viewer element (CSS px; at most 20 % of its height), e.g. to
   * clear the light widget. @default 12
   */
  readonly bottom?: number;
}

const TONES: Readonly<Record<NoticeTone, string>> = { warning: '#ffb84d', error: '#ff6b6b' };

function noticeElement(view: NoticeView): HTMLElement {
  const item = document.createElement('div');
  item.className = 'lanterna-notice';
  item.dataset.kind = view.kind;
  item.title = view.detail ?? '';
  Object.assign(item.style, {
    display: 'flex', gap: '10px', alignItems: 'center', padding: '6px 10px', borderRadius: '6px',
    background: 'rgba(20, 20, 20, 0.88)', border: '1px solid #555', borderLeft: `4px solid ${TONES[view.tone]}`,
    boxShadow: '0 1px 6px rgba(0, 0, 0, 0.6)', overflowWrap: 'anywhere',
  });
  const text = document.createElement('span');
  text.className = 'lanterna-notice-text';
  text.textContent = view.message;
  item.appendChild(text);
  if (view.action) {
    const { label, title, run } = view.action;
    const button = document.createElement('button');
    button.type = 'button';
    button.className = 'lanterna-notice-action';
    button.textContent = label;
    button.title = title ?? label;
    Object.assign(button.style, {
      font: 'inherit', padding: '2px 10px', borderRadius: '4px', border: '1px solid #777', background: '#222',
      color: '#eee', cursor: 'pointer', pointerEvents: 'auto', flex: 'none', marginLeft: 'auto',
    });
    button.addEventListener('click', (e) => {
      e.stopPropagation();
      run();
    });
    item.appendChild(button);
  }
  return item;
}

/** Create the box inside `parent` (the viewer element), centred near its bottom. */
export function createNoticeBox(parent: HTMLElement, options: NoticeBoxOptions = {}): NoticeBox {
  const box = document.createElement('div');
  box.className = 'lanterna-notices';
  box.setAttribute('role', 'status');
  box.setAttribute('aria-live', 'polite');
  Object.assign(box.style, {
    // Lower in short viewers (20 % of the height at most), so that it stays in view.
    position: 'absolute', left: '50%', bottom: `min(${options.bottom ?? 12}px, 20%)`, transform: 'translateX(-50%)',
    zIndex: '25', display: 'flex', flexDirection: 'column', gap: '6px', width: 'max-content',
    maxWidth: 'min(520px, calc(100% - 24px))', pointerEvents: 'none', color: '#eee',
    font: '13px system-ui, sans-serif', lineHeight: '1.35',
  });
  box.hidden = true;
  parent.appendChild(box);
  let shown = '';
  return {
    element: box,
    update(notices) {
      const key = JSON.stringify(notices.map((n) => [n.kind, n.message, n.detail, n.action?.label]));
      if (key === shown) {
        return;
      }
      shown = key;
      box.replaceChildren(...notices.map(noticeElement));
      box.hidden = notices.length === 0;
    },
    destroy() {
      box.remove();
    },
  };
}
