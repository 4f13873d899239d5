import { describe, expect, it } from 'vitest';
import { bundleKey } from '../../../plugin/src/tiles/tile-key';

describe('bundleKey', () => {
  it('includes every plane URL in order', () => {
    const a = bundleKey(['http://h/a/0,0,256,256/256,256/0/default.png', 'http://h/b/0,0,256,256/256,256/0/default.png']);
    expect(a).toContain('/a/');
    expect(a).toContain('/b/');
    expect(a).not.toBe(bundleKey(['http://h/b/0,0,256,256/256,256/0/default.png', 'http://h/a/0,0,256,256/256,256/0/default.png']));
  });
  it('does not collide when URLs are regrouped', () => {
    expect(bundleKey(['ab', 'c'])).not.toBe(bundleKey(['a', 'bc']));
  });
});
