import { describe, expect, it } from 'vitest';
import { escapeHtml, isSafeUrl, sanitizeHtml } from '../../../plugin/src/ui/sanitize-html';

describe('sanitizeHtml', () => {
  it.each([
    ['plain text', 'plain text'],
    ['<p>A <b>bold</b> and <em>em</em> text.</p>', '<p>A <b>bold</b> and <em>em</em> text.</p>'],
    ['<P CLASS="x" Title="t">x</P>', '<p title="t">x</p>'],
    ['line<br>break<br/>', 'line<br>break<br>'],
    ['<ul><li>one<li>two</ul>', '<ul><li>one<li>two</li></li></ul>'],
    ['<p>unclosed <i>tags', '<p>unclosed <i>tags</i></p>'],
    ['stray </b> close', 'stray  close'],
    ['1 < 2 > 0 & so', '1 &lt; 2 &gt; 0 &amp; so'],
    ['&amp; &eacute; &#233; &#xE9;', '&amp; &eacute; &#233; &#xE9;'],
    ['<div>kept text, dropped tag</div>', 'kept text, dropped tag'],
    ['<script>alert(1)</script>after', 'after'],
    ['<SCRIPT src=x></SCRIPT >after', 'after'],
    ['<style>p{}</style><p>x</p>', '<p>x</p>'],
    ['<script>never closed', ''],
    ['<!-- comment -->x<!-- unclosed', 'x'],
    ['<img src=x onerror=alert(1)>', ''],
    ['<p onclick="alert(1)" style="color:red">x</p>', '<p>x</p>'],
    ['<svg><script>alert(1)</script></svg>y', 'y'],
    ['<iframe src="https://e.org"></iframe>z', 'z'],
    ['<a href="https://example.org/a?b=1&amp;c=2">link</a>',
      '<a href="https://example.org/a?b=1&amp;c=2" target="_blank" rel="noopener noreferrer">link</a>'],
    ['<a href="notes.html#x">rel</a>', '<a href="notes.html#x" target="_blank" rel="noopener noreferrer">rel</a>'],
    ['<a href="javascript:alert(1)">x</a>', '<a>x</a>'],
    ['<a href="JaVaScRiPt:alert(1)">x</a>', '<a>x</a>'],
    ['<a href="java\tscript:alert(1)">x</a>', '<a>x</a>'],
    ['<a href="jav&#x61;script:alert(1)">x</a>', '<a>x</a>'],
    ['<a href="javascript&colon;alert(1)">x</a>', '<a>x</a>'],
    ['<a href=" data:text/html,x">x</a>', '<a>x</a>'],
    ['<a href="x" href="javascript:1">x</a>', '<a href="x" target="_blank" rel="noopener noreferrer">x</a>'],
    ['<a title=\'a "q" <b>\'>x</a>', '<a title="a &quot;q&quot; &lt;b&gt;">x</a>'],
    ['<p title="x" onmouseover=alert(1)>x</p>', '<p title="x">x</p>'],
    ['<<b>>', '&lt;<b>&gt;</b>'],
    ['<p\n>x</p >', '<p>x</p>'],
    ['</p><p>', '<p></p>'],
    ['<b x="></b><script>alert(1)</script>">y</b>', '<b>y</b>'],
  ])('%j → %j', (input, expected) => {
    expect(sanitizeHtml(input)).toBe(expected);
  });

  it('never lets a tag other than the allow-list or an event handler through', () => {
    const nasty = '<p><img src=x onerror=alert(1)><a href="javascript:x" onclick="y">z</a><form><input>'
      + '<object data=x></object><embed src=x><math><mi>x</mi></math><base href=x><meta http-equiv=refresh>';
    const out = sanitizeHtml(nasty);
    expect(out).not.toMatch(/<(img|form|input|object|embed|math|base|meta)/i);
    expect(out).not.toMatch(/on[a-z]+=/i);
    expect(out).not.toMatch(/javascript/i);
  });
});

describe('URL and text helpers', () => {
  it.each([
    ['https://e.org', true], ['http://e.org', true], ['mailto:a@b.c', true], ['page.html', true], ['#x', true],
    ['/abs/path:1', true], ['javascript:x', false], ['vbscript:x', false], ['data:x', false], [' java script:x', false],
  ])('isSafeUrl(%j) = %s', (url, safe) => {
    expect(isSafeUrl(url)).toBe(safe);
  });

  it('escapes the five special characters', () => {
    expect(escapeHtml('<a href="x">&\'')).toBe('&lt;a href=&quot;x&quot;&gt;&amp;&#39;');
  });
});
