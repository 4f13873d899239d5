import { describe, expect, it } from 'vitest';
import { isNewBuild, parseStatus, shownText, waitForBuild, type BuildStatus } from '../../../plugin/src/annotate/build-status';

const doc = (state: string, build: number, error: string | null = null): unknown => ({
  layer: 'ptm', state, served: { build, fingerprint: build ? `f${build}` : null }, patches: 3, error,
});

describe('parseStatus', () => {
  it('reads the status document of the authoring API', () => {
    expect(parseStatus(doc('building', 4))).toEqual({
      layer: 'ptm', state: 'building', build: 4, fingerprint: 'f4', patches: 3, error: null,
    });
  });

  it('refuses a document without a state or a build', () => {
    expect(() => parseStatus([])).toThrow(/state/);
    expect(() => parseStatus(null)).toThrow(/not a JSON object/);
    expect(() => parseStatus({ state: 'done' })).toThrow(/served\.build/);
    expect(() => parseStatus({ ...(doc('done', 1) as object), state: 'later' })).toThrow(/state/);
  });
});

describe('waitForBuild', () => {
  const run = async (seq: unknown[], build: number): Promise<{ result: BuildStatus | null; reads: number;
    seen: string[] }> => {
    let reads = 0;
    const seen: string[] = [];
    const result = await waitForBuild(build, {
      read: () => Promise.resolve(parseStatus(seq[Math.min(reads++, seq.length - 1)])),
      sleep: () => Promise.resolve(), onStatus: (s) => seen.push(`${s.state}:${s.build}`),
    });
    return { result, reads, seen };
  };

  it('polls until another build is served and the state is done', async () => {
    const { result, reads, seen } = await run([doc('queued', 2), doc('building', 2), doc('building', 3),
      doc('done', 3)], 2);
    expect(result?.build).toBe(3);
    expect(reads).toBe(4);
    expect(seen).toEqual(['queued:2', 'building:2', 'building:3', 'done:3']);
    expect(isNewBuild(parseStatus(doc('done', 2)), 2)).toBe(false);
  });

  it('keeps polling while the old build is still served as done (the rebuild not started yet)', async () => {
    const { result, reads } = await run([doc('done', 0), doc('done', 0), doc('done', 1)], 0);
    expect([result?.build, reads]).toEqual([1, 3]);
  });

  it('rejects with the rebuild\'s error when it failed', async () => {
    await expect(run([doc('building', 1), doc('done', 1, 'levels: disk full')], 1))
      .rejects.toThrow('the overlay was not rebuilt: levels: disk full');
  });

  it('stops when cancelled', async () => {
    let reads = 0;
    const result = await waitForBuild(0, {
      read: () => { reads++; return Promise.resolve(parseStatus(doc('building', 0))); },
      sleep: () => Promise.resolve(), cancelled: () => reads >= 2,
    });
    expect([result, reads]).toEqual([null, 2]);
  });
});

describe('shownText', () => {
  it('says the patch is shown, or which way to zoom to see its level', () => {
    expect(shownText('1_0_0_8_8_0_patch', 3, 1, 1)).toBe('Uploaded 1_0_0_8_8_0_patch: build 3 of the overlay is shown.');
    expect(shownText('p', 2, 1, 0)).toBe('Uploaded p: build 2 of the overlay is served; zoom out to see level 1.');
    expect(shownText('p', 2, 1, 2)).toContain('zoom in to see level 1');
  });
});
