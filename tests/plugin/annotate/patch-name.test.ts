import { describe, expect, it } from 'vitest';
import { infoSlug, nextOrder, patchFileName, SLUG_MAX } from '../../../plugin/src/annotate/patch-name';

describe('infoSlug', () => {
  it('keeps ASCII letters, digits and dashes, as the server does', () => {
    expect(infoSlug('Crack, upper left!')).toBe('Crack-upper-left');
    // other than ASCII is dropped, not transliterated; a dash is kept beside the run it ends
    expect(infoSlug('  --Retouche à l\'encre  ')).toBe('Retouche-l-encre');
    expect(infoSlug('a - b')).toBe('a---b');
    expect(infoSlug('Λ 12_b')).toBe('12-b');
  });

  it('is "patch" for an empty or all-symbol text, and at most 40 characters with no trailing dash', () => {
    expect(infoSlug('')).toBe('patch');
    expect(infoSlug('!!! ???')).toBe('patch');
    const long = infoSlug('a'.repeat(39) + ' bcdef');
    expect(long.length).toBeLessThanOrEqual(SLUG_MAX);
    expect(long).toBe('a'.repeat(39));
    expect(infoSlug('x'.repeat(100))).toHaveLength(SLUG_MAX);
  });
});

describe('patchFileName', () => {
  it('is L_X_Y_W_H_O_INFO.png', () => {
    expect(patchFileName({ level: 2, x: 8, y: 0, w: 104, h: 56 }, 3, 'Rosette')).toBe('2_8_0_104_56_3_Rosette.png');
    expect(patchFileName({ level: 0, x: 0, y: 0, w: 1, h: 1 }, 0, '')).toBe('0_0_0_1_1_0_patch.png');
  });

  it('parses back with the tiler\'s name pattern', () => {
    const name = patchFileName({ level: 1, x: 10, y: 20, w: 30, h: 40 }, 12, 'a b');
    const m = /^(-?\d+)_(-?\d+)_(-?\d+)_(\d+)_(\d+)_(-?\d+)(?:_(.*))?\.png$/i.exec(name);
    expect(m?.slice(1)).toEqual(['1', '10', '20', '30', '40', '12', 'a-b']);
  });
});

describe('nextOrder', () => {
  it('is one more than the largest order, 0 for the first patch', () => {
    expect(nextOrder([])).toBe(0);
    expect(nextOrder([0, 5, 2])).toBe(6);
    expect(nextOrder([-3])).toBe(-2);
  });
});
