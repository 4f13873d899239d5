import { describe, expect, it } from 'vitest';
import { lanternaCanvas } from '../../../plugin/src/mirador/lanterna-canvas';
import { manifest, relightBlock } from '../fixtures';

const URL = 'http://example.org/ushabti/manifest.json';

function canvasIdOf(doc: Record<string, unknown>): string {
  return ((doc.items as Record<string, unknown>[])[0] as { id: string }).id;
}

describe('which Mirador canvases Lanterna relights', () => {
  it('takes the first painting canvas with a LanternaRelight service, with its layers', () => {
    const doc = manifest();
    const got = lanternaCanvas(URL, doc, canvasIdOf(doc));
    expect(got).not.toBeNull();
    expect(got?.manifestUrl).toBe(URL);
    expect(got?.canvasId).toBe(canvasIdOf(doc));
    expect([got?.width, got?.height]).toEqual([512, 1024]);
    expect(got?.layers.map((l) => l.id)).toEqual(['ptm']);
    expect(got?.layers[0]?.imageId).toMatch(/ptm_color\/full\/max\/0\/default\.jpg$/);
  });

  it('leaves other canvases, plain images and non-manifests to Mirador', () => {
    const doc = manifest();
    expect(lanternaCanvas(URL, doc, 'http://example.org/another-canvas')).toBeNull();
    const plain = manifest({ id: 'http://example.org/a.jpg', type: 'Image',
      service: [{ id: 'http://example.org/iiif/a', type: 'ImageService3', profile: 'level0' }] });
    expect(lanternaCanvas(URL, plain, canvasIdOf(plain))).toBeNull();
    expect(lanternaCanvas(URL, { type: 'Collection' }, undefined)).toBeNull();
    expect(lanternaCanvas(URL, null, undefined)).toBeNull();
  });

  it('still claims a canvas whose relight block is broken (our viewer then says why)', () => {
    const broken = { ...relightBlock(), planes: 'none' };
    const doc = manifest({ id: 'http://example.org/a.jpg', type: 'Image', service: [broken] });
    const got = lanternaCanvas(URL, doc, canvasIdOf(doc));
    expect(got?.layers).toEqual([]);
  });
});
