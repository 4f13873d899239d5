import { describe, expect, it } from 'vitest';
import { AnnotationPageError } from '../../../plugin/src/iiif/errors';
import { applicationOrder, parseAnnotationPage, referencedPages } from '../../../plugin/src/iiif/annotation-page';
import { manifestWithAnnotations, overlayAnnotation, overlayPage } from '../fixtures';

const DS = 'http://127.0.0.1:8000/datasets/ushabti';
const PAGE = `${DS}/annotations/ptm.json`;

/** One patch annotation as docs/annotations.md ("Individual annotations") writes it. */
function patchAnnotation(id: string, extra: { short?: string; long?: string; author?: string; tagging?: boolean;
  state?: unknown; layer?: string } = {}): Record<string, unknown> {
  const [level, x, y, w, h, order] = id.split('_').map(Number) as [number, number, number, number, number, number];
  const layer = extra.layer ?? 'ptm';
  const annoId = `${DS}/annotations/${layer}/${id}.json`;
  const purpose = extra.tagging ? 'tagging' : 'commenting';
  const body: Record<string, unknown>[] = [{
    id: `${DS}/annotations/${layer}/${id}.png`, type: 'Image', format: 'image/png',
    width: Math.ceil((x + w) / 2 ** level) - Math.floor(x / 2 ** level),
    height: Math.ceil((y + h) / 2 ** level) - Math.floor(y / 2 ** level),
    service: [{ id: `${annoId}#lanterna`, type: 'LanternaPatch', profile: 'urn:lanterna:patch:1', layer, level,
      order, x, y, w, h, state: extra.state ?? null }],
  }];
  if (extra.short) {
    body.push({ type: 'TextualBody', value: extra.short, format: 'text/plain', purpose });
  }
  if (extra.long) {
    body.push({ type: 'TextualBody', value: extra.long, format: 'text/html', purpose: 'describing' });
  }
  return {
    id: annoId, type: 'Annotation', motivation: ['highlighting', purpose], body,
    target: { type: 'SpecificResource', source: { id: `${DS}/canvas/1`, type: 'Canvas' },
      selector: { type: 'FragmentSelector', value: `xywh=${x},${y},${w},${h}` } },
    ...(extra.author ? { creator: { type: 'Person', name: extra.author } } : {}),
    created: '2026-01-02T03:04:05Z', modified: '2026-01-03T00:00:00Z',
  };
}

function page(items: unknown[]): Record<string, unknown> {
  return { '@context': 'http://iiif.io/api/presentation/3/context.json', id: PAGE, type: 'AnnotationPage', items };
}

const STATE = { layer: 'ptm', mode: 'specular', params: { specExponent: 40 }, light: [0.5, -0.25] };

describe('the referenced annotation pages of a manifest', () => {
  it('lists the pages without items, after the embedded overlay pages', () => {
    const m = manifestWithAnnotations([overlayPage('ptm', [overlayAnnotation('ptm', 0, 's', 'l')]),
      { id: PAGE, type: 'AnnotationPage', label: { en: ['Notes: ptm'] } }, { id: 'x', type: 'Other' }, 'junk']);
    expect(referencedPages(m)).toEqual([PAGE]);
    expect(referencedPages(manifestWithAnnotations([]))).toEqual([]);
  });
});

describe('patches from an annotation page', () => {
  it('reads every field of a patch annotation', () => {
    const [p] = parseAnnotationPage(page([patchAnnotation('1_10_20_301_99_3_red-wash', {
      short: 'Red wash', long: '<p>A wash.</p>', author: 'Ada', state: STATE })]), PAGE, ['ptm']);
    expect(p).toEqual({
      id: '1_10_20_301_99_3_red-wash', layer: 'ptm', level: 1, x: 10, y: 20, w: 301, h: 99, order: 3,
      short: 'Red wash', long: '<p>A wash.</p>', motivation: 'commenting', author: 'Ada',
      created: '2026-01-02T03:04:05Z', modified: '2026-01-03T00:00:00Z',
      state: { layer: 'ptm', mode: 'specular', params: { specExponent: 40 }, light: [0.5, -0.25] },
      imageUrl: `${DS}/annotations/ptm/1_10_20_301_99_3_red-wash.png`, width: 151, height: 50,
    });
  });

  it('gives empty texts, no author and a null state when the annotation has none, and reads tagging', () => {
    const [p] = parseAnnotationPage(page([patchAnnotation('0_0_0_8_8_0')]), PAGE, ['ptm']);
    expect([p?.short, p?.long, p?.author, p?.state, p?.motivation]).toEqual(['', '', '', null, 'commenting']);
    const [t] = parseAnnotationPage(page([patchAnnotation('0_0_0_8_8_0_tag', { short: 'gold', tagging: true })]),
      PAGE, ['ptm']);
    expect([t?.short, t?.motivation]).toEqual(['gold', 'tagging']);
  });

  it('sorts by level, then order, then the file name as the tiler does', () => {
    const ids = ['1_0_0_8_8_0_a', '0_0_0_8_8_2_b', '0_0_0_8_8_-1_z', '0_0_0_8_8_2_a', '0_0_0_8_8_2_A'];
    const got = parseAnnotationPage(page(ids.map((id) => patchAnnotation(id))), PAGE, ['ptm']).map((p) => p.id);
    expect(got).toEqual(['0_0_0_8_8_-1_z', '0_0_0_8_8_2_A', '0_0_0_8_8_2_a', '0_0_0_8_8_2_b', '1_0_0_8_8_0_a']);
    const [a, b] = parseAnnotationPage(page([patchAnnotation('0_0_0_8_8_2_a'), patchAnnotation('0_0_0_8_8_2_b')]),
      PAGE, ['ptm']);
    expect(a && b ? applicationOrder(a, b) : 0).toBeLessThan(0);
  });

  it('skips annotations that are not Lanterna patches (a note someone added elsewhere)', () => {
    const note = { id: 'n', type: 'Annotation', motivation: 'commenting',
      body: { type: 'TextualBody', value: 'nice' }, target: `${DS}/canvas/1#xywh=0,0,5,5` };
    const image = { id: 'i', type: 'Annotation', motivation: 'painting', body: { id: 'x.png', type: 'Image' } };
    const got = parseAnnotationPage(page([note, image, 'junk', patchAnnotation('0_0_0_8_8_0')]), PAGE, ['ptm']);
    expect(got.map((p) => p.id)).toEqual(['0_0_0_8_8_0']);
    expect(parseAnnotationPage(page([]), PAGE, ['ptm'])).toEqual([]);
  });

  it('decodes an id written with URL escapes', () => {
    const anno = patchAnnotation('0_0_0_8_8_0_a');
    anno.id = `${DS}/annotations/ptm/0_0_0_8_8_0_caf%C3%A9.json`;
    expect(parseAnnotationPage(page([anno]), PAGE, ['ptm'])[0]?.id).toBe('0_0_0_8_8_0_café');
  });

  const bad: [string, (a: Record<string, unknown>) => void, RegExp][] = [
    ['a negative level', (a) => { block(a).level = -1; }, /item 0 \(.*0_0_0_8_8_0\.json\): "level" must be an integer ≥ 0/],
    ['an empty width', (a) => { block(a).w = 0; }, /"w" must be an integer ≥ 1, got 0/],
    ['a fractional x', (a) => { block(a).x = 1.5; }, /"x" must be an integer/],
    ['no layer', (a) => { delete block(a).layer; }, /LanternaPatch block needs a "layer"/],
    ['no image size', (a) => { delete image(a).width; }, /patch image needs an "id" and a positive "width"/],
    ['a state without a light', (a) => { block(a).state = { layer: 'ptm', mode: 'color', params: {} }; },
      /"state" "light" must be \[lu, lv\]/],
    ['a state with a text parameter', (a) => { block(a).state = { ...STATE, params: { gamma: 'x' } }; },
      /"state" "params.gamma" must be a number/],
    ['an unknown layer', (a) => { block(a).layer = 'uv'; }, /no layer "uv" \(layers: ptm\)/],
  ];
  it.each(bad)('names the page and the item for %s', (_what, spoil, message) => {
    const anno = patchAnnotation('0_0_0_8_8_0');
    spoil(anno);
    expect(() => parseAnnotationPage(page([anno]), PAGE, ['ptm'])).toThrow(AnnotationPageError);
    expect(() => parseAnnotationPage(page([anno]), PAGE, ['ptm'])).toThrow(new RegExp(`^annotation page ${PAGE}: `));
    expect(() => parseAnnotationPage(page([anno]), PAGE, ['ptm'])).toThrow(message);
  });

  it('refuses a document that is not a page, and a patch given twice', () => {
    expect(() => parseAnnotationPage({ type: 'Manifest' }, PAGE, ['ptm'])).toThrow(/not an AnnotationPage/);
    const twice = page([patchAnnotation('0_0_0_8_8_0'), patchAnnotation('0_0_0_8_8_0')]);
    expect(() => parseAnnotationPage(twice, PAGE, ['ptm'])).toThrow(/item 1 .*: patch 0_0_0_8_8_0 is given twice/);
  });
});

function image(anno: Record<string, unknown>): Record<string, unknown> {
  return (anno.body as Record<string, unknown>[])[0] ?? {};
}

function block(anno: Record<string, unknown>): Record<string, unknown> {
  return (image(anno).service as Record<string, unknown>[])[0] ?? {};
}
