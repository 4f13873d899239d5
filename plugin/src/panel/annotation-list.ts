/**
 * The panel's "Annotations" section (`docs/viewer.md`, "Annotations"): the active layer's patches,
 * each with its short text, level and author. Pointing at one (or focusing it with the keyboard)
 * outlines its rectangle over the view; its button (click, Enter or Space) zooms to it and restores
 * the render state it was drawn under; its checkbox shows or hides it. The section is hidden while
 * no layer has any annotation, and follows layer changes and refreshes.
 */
import type { LanternaViewer } from '../api/viewer-api';
import type { PatchAnnotation } from '../iiif/annotation-page';
import { mountSection, type PanelSection, titledSection } from './panel-dom';

/** What the list needs of a viewer. */
export type AnnotationListViewer = Pick<LanternaViewer, 'onChange' | 'getAnnotations' | 'getLayers'
  | 'getActiveLayer' | 'setAnnotationHidden' | 'isAnnotationHidden' | 'highlightAnnotation' | 'focusAnnotation'>;

/** The row's second line: the level and the author. */
export function annotationMeta(patch: PatchAnnotation): string {
  return [`Level ${patch.level}`, patch.author].filter((s) => s !== '').join(' · ');
}

/** The row's text: the short text, else the patch id. */
export function annotationTitle(patch: PatchAnnotation): string {
  return patch.short.trim() || patch.id;
}

function row(lanterna: AnnotationListViewer, patch: PatchAnnotation, onError: (error: unknown) => void): HTMLLIElement {
  const li = document.createElement('li');
  li.className = 'lanterna-annotation-row';
  li.dataset.id = patch.id;
  Object.assign(li.style, { display: 'flex', gap: '6px', alignItems: 'flex-start' });
  const shown = document.createElement('input');
  shown.type = 'checkbox';
  shown.className = 'lanterna-annotation-shown';
  shown.checked = !lanterna.isAnnotationHidden(patch.id);
  shown.title = 'Show this patch in the overlay';
  shown.setAttribute('aria-label', `Show “${annotationTitle(patch)}”`);
  shown.addEventListener('change', () => {
    try {
      lanterna.setAnnotationHidden(patch.id, !shown.checked);
    } catch (error) {
      onError(error);
    }
  });
  const focus = document.createElement('button');
  focus.type = 'button';
  focus.className = 'lanterna-annotation-focus';
  focus.title = 'Zoom to it, with the light, layer and mode it was drawn under';
  Object.assign(focus.style, { flex: '1', minWidth: '0', textAlign: 'left', display: 'flex', flexDirection: 'column' });
  const text = document.createElement('span');
  text.className = 'lanterna-annotation-text';
  text.textContent = annotationTitle(patch);
  Object.assign(text.style, { overflow: 'hidden', textOverflow: 'ellipsis', whiteSpace: 'nowrap', maxWidth: '100%' });
  const meta = document.createElement('small');
  meta.className = 'lanterna-annotation-meta';
  meta.textContent = annotationMeta(patch);
  Object.assign(meta.style, { color: '#aaa' });
  focus.append(text, meta);
  focus.addEventListener('click', () => { lanterna.focusAnnotation(patch.id).catch(onError); });
  li.append(shown, focus);
  const highlight = (on: boolean): void => {
    try {
      lanterna.highlightAnnotation(on ? patch.id : null);
    } catch (error) {
      onError(error);
    }
  };
  li.addEventListener('pointerenter', () => { highlight(true); });
  li.addEventListener('pointerleave', () => { highlight(li.contains(document.activeElement)); });
  li.addEventListener('focusin', () => { highlight(true); });
  li.addEventListener('focusout', (event) => {
    if (!li.contains(event.relatedTarget as Node | null)) {
      highlight(false);
    }
  });
  return li;
}

/** Build the section into `parent`; `onError` gets the errors of its actions (e.g. a failed focus). */
export function createAnnotationList(lanterna: AnnotationListViewer, parent: HTMLElement,
  onError: (error: unknown) => void): PanelSection {
  const section = titledSection('lanterna-annotations', 'Annotations');
  const empty = document.createElement('p');
  empty.className = 'lanterna-annotations-empty';
  empty.textContent = 'No annotations on this layer.';
  Object.assign(empty.style, { margin: '0', color: '#aaa' });
  const list = document.createElement('ul');
  list.className = 'lanterna-annotation-list';
  Object.assign(list.style, { listStyle: 'none', margin: '0', padding: '0', display: 'flex', flexDirection: 'column',
    gap: '4px', maxHeight: '40vh', overflowY: 'auto' });
  section.append(empty, list);
  let shownKey = '';
  const refresh = (): void => {
    const patches = lanterna.getAnnotations();
    section.hidden = lanterna.getLayers().every((l) => lanterna.getAnnotations(l.id).length === 0);
    const key = JSON.stringify([lanterna.getActiveLayer(), patches.map((p) => [p.id, p.short, p.author, p.level,
      p.modified, lanterna.isAnnotationHidden(p.id)])]);
    if (key === shownKey) {
      return; // unchanged: keep the rows (and the keyboard focus)
    }
    shownKey = key;
    // A toggled checkbox rebuilds the rows: the same control of the same patch keeps the focus.
    const active = document.activeElement;
    const focused = (active?.closest('.lanterna-annotation-row') as HTMLElement | null)?.dataset.id;
    const control = active?.classList.contains('lanterna-annotation-shown') ? 'input' : 'button';
    const rows = patches.map((p) => row(lanterna, p, onError));
    list.replaceChildren(...rows);
    empty.hidden = patches.length > 0;
    rows.find((r) => r.dataset.id === focused)?.querySelector<HTMLElement>(control)?.focus();
  };
  return mountSection(lanterna, parent, section, refresh);
}
