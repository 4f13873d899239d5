import { describe, expect, it } from 'vitest';
import { AnnotationSet } from '../../../plugin/src/annotations/annotation-set';
import type { PatchAnnotation } from '../../../plugin/src/iiif/annotation-page';

function patch(id: string, layer: string): PatchAnnotation {
  const [l, x, y, w, h, order] = id.split('_').map(Number) as [number, number, number, number, number, number];
  return { id, layer, level: l, x, y, w, h, order, short: id, long: '', motivation: 'commenting', author: '',
    created: '', modified: '', state: null, imageUrl: `${id}.png`, width: w, height: h };
}

describe('the annotation set', () => {
  it('lists each layer\'s patches in application order', () => {
    const set = new AnnotationSet();
    set.replace([patch('1_0_0_4_4_0_z', 'vis'), patch('0_0_0_4_4_5_b', 'vis'), patch('0_0_0_4_4_5_a', 'uv')]);
    expect(set.list('vis').map((p) => p.id)).toEqual(['0_0_0_4_4_5_b', '1_0_0_4_4_0_z']);
    expect(set.list('uv').map((p) => p.id)).toEqual(['0_0_0_4_4_5_a']);
    expect(set.list('none')).toEqual([]);
  });

  it('finds an id in the preferred layer first, then in any layer', () => {
    const set = new AnnotationSet();
    set.replace([patch('0_0_0_4_4_0_a', 'vis'), patch('0_0_0_4_4_0_a', 'uv'), patch('0_0_0_4_4_1_b', 'uv')]);
    expect(set.find('0_0_0_4_4_0_a', 'uv')?.layer).toBe('uv');
    expect(set.find('0_0_0_4_4_0_a', 'vis')?.layer).toBe('vis');
    expect(set.find('0_0_0_4_4_1_b', 'vis')?.layer).toBe('uv');
    expect(set.find('nope', 'vis')).toBeUndefined();
  });

  it('hides per layer, says when that changed anything, and forgets patches that are gone', () => {
    const set = new AnnotationSet();
    const a = patch('0_0_0_4_4_0_a', 'vis');
    const b = patch('0_0_0_4_4_1_b', 'vis');
    set.replace([a, b, patch('0_0_0_4_4_0_a', 'uv')]);
    expect(set.setHidden(a, true)).toBe(true);
    expect(set.setHidden(a, true)).toBe(false);
    expect(set.setHidden(b, true)).toBe(true);
    expect([...set.hidden('vis')].sort()).toEqual([a.id, b.id]);
    expect(set.hidden('uv').size).toBe(0);
    set.replace([a, patch('0_0_0_4_4_2_c', 'vis')]); // b was deleted by the rebuild
    expect([...set.hidden('vis')]).toEqual([a.id]);
    expect(set.setHidden(a, false)).toBe(true);
    expect(set.hidden('vis').size).toBe(0);
  });
});
