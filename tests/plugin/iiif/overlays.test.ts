import { describe, expect, it } from 'vitest';
import { OverlayError } from '../../../plugin/src/iiif/errors';
import { parseManifest } from '../../../plugin/src/iiif/manifest';
import { overlayAt, parseOverlays } from '../../../plugin/src/iiif/overlays';
import { manifestWithAnnotations, overlayAnnotation, overlayPage } from '../fixtures';

const BASE = 'http://127.0.0.1:8000/datasets/ushabti';

function canvasOf(pages: unknown[]): unknown {
  return (manifestWithAnnotations(pages).items as unknown[])[0];
}

describe('overlay levels from canvas.annotations', () => {
  it('reads every level of a layer, ascending, with texts, service and size', () => {
    const m = manifestWithAnnotations([overlayPage('ptm', [
      overlayAnnotation('ptm', 2, 'Whole figure', '<p>The <b>ushabti</b>.</p>'),
      overlayAnnotation('ptm', 0, 'Glyphs', '<p>Detail.</p>'),
    ])]);
    const info = parseManifest(m);
    const levels = info.layers[0]?.overlays ?? [];
    expect(levels.map((l) => l.level)).toEqual([0, 2]);
    expect(levels[1]).toEqual({
      layer: 'ptm', level: 2, short: 'Whole figure', long: '<p>The <b>ushabti</b>.</p>',
      serviceId: `${BASE}/iiif/ptm_ov2`, width: 128, height: 256, embedded: null,
    });
    expect(overlayAt(levels, 2)?.short).toBe('Whole figure');
    expect(overlayAt(levels, 1)).toBeNull();
  });

  it('gives layers without an overlay an empty list, and manifests without annotations too', () => {
    expect(parseManifest(manifestWithAnnotations([])).layers[0]?.overlays).toEqual([]);
    expect(parseOverlays({ items: [] }, ['ptm']).size).toBe(0);
    expect(parseOverlays(null, ['ptm']).size).toBe(0);
  });

  it('ignores other supplementing content and annotations of other motivations', () => {
    const other = { id: 'x', type: 'Annotation', motivation: 'painting', body: overlayAnnotation('ptm', 1, 's', 'l').body };
    const plain = { id: 'y', type: 'Annotation', motivation: 'supplementing', body: [{ id: 'z.png', type: 'Image' }] };
    const text = { id: 'w', type: 'Annotation', motivation: 'supplementing', body: { type: 'TextualBody', value: 'hi' } };
    const m = parseOverlays(canvasOf([overlayPage('ptm', [other, plain, text]), 'not a page']), ['ptm']);
    expect(m.size).toBe(0);
  });

  it('reads the current encoding (commenting, the drawing\'s region, a short TextualBody) as the earlier one', () => {
    const earlier = overlayAnnotation('ptm', 1, 'Glyphs', '<p>Detail.</p>');
    const body = earlier.body as Record<string, unknown>[];
    const current = {
      ...earlier,
      motivation: 'commenting',
      target: { ...(earlier.target as Record<string, unknown>),
        selector: { type: 'FragmentSelector', conformsTo: 'http://www.w3.org/TR/media-frags/', value: 'xywh=40,96,200,310' } },
      body: [body[0], { type: 'TextualBody', format: 'text/plain', purpose: 'commenting', value: 'Glyphs' }, body[1]],
    };
    const read = (anno: unknown): unknown => parseOverlays(canvasOf([overlayPage('ptm', [anno])]), ['ptm']).get('ptm');
    expect(read(current)).toEqual(read(earlier));
    expect((read(current) as { short: string; long: string }[])[0]).toMatchObject({ short: 'Glyphs', long: '<p>Detail.</p>' });
    expect(read({ ...current, motivation: ['highlighting', 'commenting'] })).toEqual(read(earlier));
  });

  it('takes the long text from the describing TextualBody, not the short one, when the block has none', () => {
    const anno = overlayAnnotation('ptm', 1, 's', '<p>from the body</p>');
    const body = anno.body as Record<string, unknown>[];
    body.splice(1, 0, { type: 'TextualBody', format: 'text/plain', purpose: 'commenting', value: 's' });
    const service = (body[0]?.service as Record<string, unknown>[])[1];
    if (service) {
      delete service.long;
    }
    const m = parseOverlays(canvasOf([overlayPage('ptm', [{ ...anno, motivation: 'commenting' }])]), ['ptm']);
    expect(m.get('ptm')?.[0]?.long).toBe('<p>from the body</p>');
  });

  it('takes the long text from the TextualBody when the block has none', () => {
    const anno = overlayAnnotation('ptm', 1, 's', '<p>from the body</p>');
    const body = anno.body as Record<string, unknown>[];
    const service = (body[0]?.service as Record<string, unknown>[])[1];
    if (service) {
      delete service.long;
    }
    const m = parseOverlays(canvasOf([overlayPage('ptm', [anno])]), ['ptm']);
    expect(m.get('ptm')?.[0]?.long).toBe('<p>from the body</p>');
  });

  it.each([
    ['no layer', (b: Record<string, unknown>) => { delete b.layer; }, /needs a "layer"/],
    ['level not an integer', (b: Record<string, unknown>) => { b.level = 1.5; }, /integer ≥ 0/],
    ['negative level', (b: Record<string, unknown>) => { b.level = -1; }, /integer ≥ 0/],
    ['unknown layer', (b: Record<string, unknown>) => { b.layer = 'hsh'; }, /no layer "hsh"/],
  ])('rejects a block with %s', (_name, edit, message) => {
    const anno = overlayAnnotation('ptm', 1, 's', 'l');
    const block = ((anno.body as Record<string, unknown>[])[0]?.service as Record<string, unknown>[])[1];
    if (block) {
      edit(block);
    }
    expect(() => parseOverlays(canvasOf([overlayPage('ptm', [anno])]), ['ptm'])).toThrow(OverlayError);
    expect(() => parseOverlays(canvasOf([overlayPage('ptm', [anno])]), ['ptm'])).toThrow(message);
  });

  it('rejects a level image without a service or a size, and a level given twice', () => {
    const noService = overlayAnnotation('ptm', 1, 's', 'l');
    const image = (noService.body as Record<string, unknown>[])[0] ?? {};
    image.service = [(image.service as unknown[])[1]];
    expect(() => parseOverlays(canvasOf([overlayPage('ptm', [noService])]), ['ptm'])).toThrow(/no IIIF image service/);
    const noSize = overlayAnnotation('ptm', 1, 's', 'l');
    delete ((noSize.body as Record<string, unknown>[])[0] ?? {}).width;
    expect(() => parseOverlays(canvasOf([overlayPage('ptm', [noSize])]), ['ptm'])).toThrow(/positive width/);
    const twice = [overlayAnnotation('ptm', 1, 'a', 'b'), overlayAnnotation('ptm', 1, 'c', 'd')];
    expect(() => parseManifest(manifestWithAnnotations([overlayPage('ptm', twice)]))).toThrow(/two overlays for level 1/);
  });
});
