import { describe, expect, it } from 'vitest';
import { authoringUrls, saveErrorText } from '../../../plugin/src/panel/authoring-url';

describe('authoringUrls', () => {
  it('finds the API beside a served dataset manifest', () => {
    expect(authoringUrls('http://h:8000/datasets/demo/manifest.json')).toEqual({
      name: 'demo', api: 'http://h:8000/api/', presets: 'http://h:8000/api/datasets/demo/presets',
    });
    expect(authoringUrls('https://h/lanterna/datasets/a%20b/manifest.json?x=1')?.presets)
      .toBe('https://h/lanterna/api/datasets/a%20b/presets');
  });

  it('gives null for another manifest URL', () => {
    expect(authoringUrls('http://h/objects/demo/manifest.json')).toBeNull();
    expect(authoringUrls('http://h/datasets/demo/other.json')).toBeNull();
  });
});

describe('saveErrorText', () => {
  it('shows the server\'s one-line error, else what the status means', () => {
    expect(saveErrorText(400, '{"error": "presets.json: base[0].layer: no layer \'x\'"}'))
      .toBe('Not saved (400): presets.json: base[0].layer: no layer \'x\'');
    expect(saveErrorText(401, '')).toBe('Not saved (401): the token was not accepted');
    expect(saveErrorText(500, 'oops\nmore')).toBe('Not saved (500): HTTP 500');
  });
});
