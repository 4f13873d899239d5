/**
 * The panel's "About" section: the manifest's summary, metadata, required statement (attribution)
 * and rights, as the IIIF Presentation 3 manifest gives them. HTML values are sanitised.
 */
import type { ManifestInfo } from '../iiif/manifest';
import { sanitizeHtml } from '../ui/sanitize-html';

/** Put a IIIF value into `el`: as sanitised HTML when it looks like HTML, else as text. */
function setValue(el: HTMLElement, value: string): void {
  if (/^\s*</.test(value)) {
    // sanitizeHtml keeps only allow-listed tags and attributes.
    el.innerHTML = sanitizeHtml(value);
  } else {
    el.textContent = value;
  }
}

/** Whether the manifest has anything to show in the section. */
export function hasAbout(info: ManifestInfo): boolean {
  return info.summary !== '' || info.metadata.length > 0 || info.requiredStatement !== null || info.rights !== '';
}

/** Build the section (a `<details>`, closed) into `parent`; null when the manifest has nothing to show. */
export function createAbout(info: ManifestInfo, parent: HTMLElement): HTMLElement | null {
  if (!hasAbout(info)) {
    return null;
  }
  const details = document.createElement('details');
  details.className = 'lanterna-about';
  const summary = document.createElement('summary');
  summary.textContent = 'About';
  details.appendChild(summary);
  if (info.summary) {
    const p = document.createElement('p');
    p.className = 'lanterna-about-summary';
    setValue(p, info.summary);
    details.appendChild(p);
  }
  const pairs = [...info.metadata, ...(info.requiredStatement ? [info.requiredStatement] : [])];
  if (pairs.length > 0) {
    const dl = document.createElement('dl');
    for (const { label, value } of pairs) {
      const dt = document.createElement('dt');
      dt.textContent = label;
      const dd = document.createElement('dd');
      setValue(dd, value);
      dl.append(dt, dd);
    }
    details.appendChild(dl);
  }
  if (info.rights) {
    const p = document.createElement('p');
    p.className = 'lanterna-about-rights';
    p.append('Rights: ');
    details.appendChild(p);
    if (!/^https?:\/\//i.test(info.rights)) {
      p.append(info.rights);
    } else {
      const a = document.createElement('a');
      a.href = info.rights;
      a.textContent = info.rights;
      a.target = '_blank';
      a.rel = 'noopener noreferrer';
      p.appendChild(a);
    }
  }
  parent.appendChild(details);
  return details;
}
