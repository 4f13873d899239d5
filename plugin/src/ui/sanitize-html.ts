/**
 * Sanitise the long hypertext of an overlay level (HTML written by the dataset author) to a small
 * allow-list before it is shown. Pure: a string-to-string rewrite, no DOM.
 *
 * The output is rebuilt, never copied: allowed tags are re-emitted with allowed attributes only
 * (values decoded, checked, re-escaped), every other `<` becomes `&lt;`, the contents of script-like
 * elements and comments are dropped, and open tags are closed at the end.
 */

/** Tags kept (attributes allowed per tag; `title` is allowed everywhere). */
const ALLOWED: Readonly<Record<string, readonly string[]>> = {
  a: ['href'], b: [], blockquote: [], br: [], code: [], em: [], h3: [], h4: [], h5: [], h6: [], i: [],
  li: [], ol: [], p: [], small: [], span: [], strong: [], sub: [], sup: [], u: [], ul: [],
};
const GLOBAL_ATTRIBUTES = ['title'];
const VOID = new Set(['br']);
/** Elements dropped with their contents. */
const DROP_CONTENT = new Set(['script', 'style', 'iframe', 'object', 'embed', 'template', 'noscript', 'textarea',
  'title', 'xmp', 'svg', 'math', 'select', 'frameset', 'noembed', 'noframes', 'plaintext']);
/** URL schemes a link may use (no scheme = relative, allowed). */
const SAFE_SCHEMES = new Set(['http', 'https', 'mailto']);

const TAG = /^<(\/?)([a-zA-Z][a-zA-Z0-9-]*)((?:\s+[^\s"'>/=]+(?:\s*=\s*(?:"[^"]*"|'[^']*'|[^\s"'=<>`]+))?)*)\s*(\/?)>/;
const ATTRIBUTE = /([^\s"'>/=]+)(?:\s*=\s*(?:"([^"]*)"|'([^']*)'|([^\s"'=<>`]+)))?/g;
const ENTITY = /^&(?:[a-zA-Z][a-zA-Z0-9]{1,31}|#[0-9]{1,7}|#[xX][0-9a-fA-F]{1,6});/;
const NAMED: Readonly<Record<string, string>> = {
  amp: '&', lt: '<', gt: '>', quot: '"', apos: "'", colon: ':', tab: '\t', newline: '\n', nbsp: '\u00a0',
  sol: '/', lpar: '(', rpar: ')', period: '.', comma: ',',
};

/** Escape text for an HTML attribute value or text node. */
export function escapeHtml(text: string): string {
  return text.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;').replace(/"/g, '&quot;')
    .replace(/'/g, '&#39;');
}

/** Decode the character references we know (numeric, and a few named); others stay as written. */
function decodeEntities(value: string): string {
  return value.replace(/&(#[xX][0-9a-fA-F]+|#[0-9]+|[a-zA-Z][a-zA-Z0-9]*);?/g, (whole, ref: string) => {
    if (ref.startsWith('#')) {
      const code = ref[1] === 'x' || ref[1] === 'X' ? parseInt(ref.slice(2), 16) : parseInt(ref.slice(1), 10);
      return code > 0 && code <= 0x10ffff ? String.fromCodePoint(code) : '';
    }
    return NAMED[ref.toLowerCase()] ?? whole;
  });
}

/** True when `url` (decoded) is relative or uses http, https or mailto. */
export function isSafeUrl(url: string): boolean {
  // eslint-disable-next-line no-control-regex
  const compact = url.replace(/[\u0000-\u0020\u007f-\u009f]/g, '');
  const scheme = /^([a-zA-Z][a-zA-Z0-9+.-]*):/.exec(compact);
  return scheme === null || SAFE_SCHEMES.has((scheme[1] ?? '').toLowerCase());
}

function attributesOf(tag: string, source: string): string {
  const allowed = [...(ALLOWED[tag] ?? []), ...GLOBAL_ATTRIBUTES];
  const out: string[] = [];
  const seen = new Set<string>();
  for (const m of source.matchAll(ATTRIBUTE)) {
    const name = (m[1] ?? '').toLowerCase();
    if (!allowed.includes(name) || seen.has(name)) {
      continue;
    }
    seen.add(name);
    const value = decodeEntities(m[2] ?? m[3] ?? m[4] ?? '');
    if (name === 'href' && !isSafeUrl(value)) {
      continue;
    }
    out.push(` ${name}="${escapeHtml(value)}"`);
  }
  if (tag === 'a' && out.some((a) => a.startsWith(' href='))) {
    out.push(' target="_blank" rel="noopener noreferrer"');
  }
  return out.join('');
}

/**
 * Rewrite `html` to the allow-list: `p br b strong i em u a[href] ul ol li span blockquote sub sup code
 * small h3–h6` (`title` on any of them); links only to http(s), mailto or relative URLs, opened in a
 * new tab without an opener.
 */
export function sanitizeHtml(html: string): string {
  let out = '';
  const open: string[] = [];
  let i = 0;
  while (i < html.length) {
    const c = html[i];
    if (c === '<') {
      const rest = html.slice(i);
      if (rest.startsWith('<!--')) {
        const end = html.indexOf('-->', i + 4);
        i = end < 0 ? html.length : end + 3;
        continue;
      }
      const m = TAG.exec(rest);
      if (!m) {
        out += '&lt;';
        i++;
        continue;
      }
      i += m[0].length;
      const closing = m[1] === '/';
      const tag = (m[2] ?? '').toLowerCase();
      if (DROP_CONTENT.has(tag)) {
        if (!closing && m[4] !== '/') {
          const close = new RegExp(`</${tag}\\s*>`, 'i').exec(html.slice(i));
          i = close ? i + close.index + close[0].length : html.length;
        }
        continue;
      }
      if (!(tag in ALLOWED)) {
        continue;
      }
      if (VOID.has(tag)) {
        out += closing ? '' : `<${tag}${attributesOf(tag, m[3] ?? '')}>`;
      } else if (closing) {
        const at = open.lastIndexOf(tag);
        if (at >= 0) {
          out += open.splice(at).reverse().map((t) => `</${t}>`).join('');
        }
      } else {
        out += `<${tag}${attributesOf(tag, m[3] ?? '')}>`;
        open.push(tag);
      }
    } else if (c === '&') {
      const entity = ENTITY.exec(html.slice(i));
      out += entity ? entity[0] : '&amp;';
      i += entity ? entity[0].length : 1;
    } else if (c === '>') {
      out += '&gt;';
      i++;
    } else {
      out += c;
      i++;
    }
  }
  return out + open.reverse().map((t) => `</${t}>`).join('');
}
