import { describe, expect, it, vi } from 'vitest';
import { ViewerNotices } from '../../../plugin/src/viewer/notices';
import { fakeViewer, type FakeViewer } from '../fake-viewer';

function notices(): { notices: ViewerNotices; raise: FakeViewer['raise']; onChange: () => void } {
  const fake = fakeViewer();
  const onChange = vi.fn();
  return { notices: new ViewerNotices(fake.viewer, { show: false, bottom: 12, onChange }), raise: fake.raise, onChange };
}

describe('ViewerNotices', () => {
  it('lists a lost context, failed tiles and errors, in that order', () => {
    const { notices: n, raise, onChange } = notices();
    expect(n.list()).toEqual([]);
    n.reportError(new Error('cannot open the lens layer hsh9: HTTP 404'));
    raise('tile-load-failed', { tile: { exists: false }, tiledImage: { getOpacity: () => 1 },
      message: '[lanterna] tile 2/0_0: HTTP 404 for http://h/iiif/a/0,0,256,256/128,128/0/default.png' });
    n.setContextLost(true);
    expect(n.list().map((x) => x.kind)).toEqual(['context-lost', 'tiles-failed', 'error']);
    const [lost, tiles, error] = n.list();
    expect(lost?.message).toMatch(/^Graphics context lost/);
    expect(tiles?.message).toBe('Some tiles could not be loaded (1); showing a coarser level there, retrying…');
    expect(tiles?.detail).toBe('tile 2/0_0: HTTP 404 for http://h/iiif/a/0,0,256,256/128,128/0/default.png');
    expect(error).toEqual({ kind: 'error', message: 'cannot open the lens layer hsh9: HTTP 404', detail: 'Error' });
    n.setContextLost(false);
    expect(n.list().map((x) => x.kind)).toEqual(['tiles-failed', 'error']);
    expect(onChange).toHaveBeenCalled();
    n.destroy();
  });

  it('keeps the latest three distinct errors until dismissed', () => {
    const { notices: n } = notices();
    for (const m of ['a', 'b', 'a', 'c', 'd']) {
      n.reportError(new Error(m));
    }
    n.reportError('plain text');
    expect(n.list().map((x) => x.message)).toEqual(['c', 'd', 'plain text']);
    n.dismissErrors();
    expect(n.list()).toEqual([]);
  });
});
