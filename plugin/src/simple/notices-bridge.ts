/**
 * The viewer's notices (tiles that failed, a lost graphics context, errors) as the page's
 * self-clearing note: each kind is told once when it appears, errors are logged and then dropped from
 * the viewer's list, so nothing piles up and nothing waits for a visitor to dismiss it.
 */
import type { LanternaViewer } from '../index';
import type { PageNote } from './page-note';

/** What a notice is about (`tiles-failed`, `context-lost`, `error`). */
type NoticeKind = ReturnType<LanternaViewer['getNotices']>[number]['kind'];

/** What a kiosk says (calm, without URLs or error names). */
const KIOSK_TEXT: Readonly<Record<NoticeKind, string>> = {
  'tiles-failed': 'Part of the image is still loading.',
  'context-lost': 'The image is being redrawn.',
  error: 'Something could not be shown; the object is still here.',
};

/** Show `lanterna`'s new notices in `note`; returns the unsubscribe function. */
export function bridgeNotices(lanterna: LanternaViewer, note: PageNote, kiosk: boolean): () => void {
  let shown = new Set<NoticeKind>();
  return lanterna.onChange(() => {
    const notices = lanterna.getNotices();
    const now = new Set(notices.map((n) => n.kind));
    const fresh = notices.filter((n) => !shown.has(n.kind) || n.kind === 'error');
    shown = now;
    const last = fresh.at(-1);
    if (last) {
      note.show(kiosk ? KIOSK_TEXT[last.kind] : last.message);
    }
    if (now.has('error')) {
      lanterna.dismissErrors(); // logged by the viewer already; the note says it once
    }
  });
}
