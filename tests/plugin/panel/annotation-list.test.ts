import { describe, expect, it } from 'vitest';
import type { PatchAnnotation } from '../../../plugin/src/iiif/annotation-page';
import { annotationMeta, annotationTitle } from '../../../plugin/src/panel/annotation-list';

const PATCH: PatchAnnotation = {
  id: '2_0_0_64_64_0_patch', layer: 'vis', level: 2, x: 0, y: 0, w: 64, h: 64, order: 0, short: '  Gilding ',
  long: '', motivation: 'commenting', author: 'Ada', created: '', modified: '', state: null, imageUrl: 'p.png',
  width: 16, height: 16,
};

describe('a row of the annotation list', () => {
  it('shows the short text, else the patch id', () => {
    expect(annotationTitle(PATCH)).toBe('Gilding');
    expect(annotationTitle({ ...PATCH, short: ' ' })).toBe('2_0_0_64_64_0_patch');
  });

  it('shows the level and the author, if any', () => {
    expect(annotationMeta(PATCH)).toBe('Level 2 · Ada');
    expect(annotationMeta({ ...PATCH, author: '' })).toBe('Level 2');
  });
});
