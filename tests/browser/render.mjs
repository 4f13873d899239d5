#!/usr/bin/env node
// Render shots of the Lanterna viewer page in headless Chromium and save the read-back pixels.
//
//   node tests/browser/render.mjs SPEC.json
//
// SPEC = {"url": "…/viewer/?manifest=…", "viewport": {"width": 640, "height": 480},
//         "shots": [{"light": [lu, lv], "region": [x, y, w, h], "out": "/abs/shot.rgba",
//                    "layer": "ptm", "mode": "specular", "params": {"specExponent": 40}}],
//         "screenshot": "/abs/optional.png", "timeoutMs": 60000}
//
// For each shot: switch to `layer` (a layer id), set the render `mode`, and set the render
// parameters to the defaults overridden by `params` (each optional: when absent the current layer,
// mode and parameters stay), then set the light,
// fit the image-pixel region to the viewport, wait until every tile is loaded and drawn, read the frame back (RGBA, rows top-down) and write the raw bytes to `out`
// and {width, height} to `out + ".json"`. One JSON line per shot goes to stdout. Exits non-zero on
// a page error, a console error, or a step taking longer than timeoutMs (default 60 s).
import { readFileSync, writeFileSync } from 'node:fs';
import process from 'node:process';
import { chromium } from 'playwright-core';

const CHROMIUM = process.env.LANTERNA_CHROMIUM ?? '/usr/bin/chromium';
const ARGS = [
  '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
  '--disable-sync', '--no-first-run', '--disable-quic',
];

class RenderError extends Error {}

function fail(message) {
  process.stderr.write(`render.mjs: ${message}\n`);
  process.exitCode = 1;
}

function readSpec(path) {
  if (!path) {
    throw new RenderError('usage: node tests/browser/render.mjs SPEC.json');
  }
  const spec = JSON.parse(readFileSync(path, 'utf8'));
  if (typeof spec.url !== 'string' || !Array.isArray(spec.shots)) {
    throw new RenderError(`${path}: needs "url" and "shots"`);
  }
  for (const [i, s] of spec.shots.entries()) {
    if (!Array.isArray(s.light) || s.light.length !== 2 || !Array.isArray(s.region) || s.region.length !== 4
      || typeof s.out !== 'string') {
      throw new RenderError(`${path}: shot ${i} needs light [lu, lv], region [x, y, w, h] and out`);
    }
    if ((s.layer !== undefined && typeof s.layer !== 'string') || (s.mode !== undefined && typeof s.mode !== 'string')
      || (s.params !== undefined && (typeof s.params !== 'object' || s.params === null || Array.isArray(s.params)))) {
      throw new RenderError(`${path}: shot ${i}: layer and mode must be strings, params an object`);
    }
  }
  return spec;
}

/** Reject after `ms` with a clear message, unless `promise` settles first. */
function withTimeout(promise, ms, what) {
  let timer;
  const timeout = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new RenderError(`timed out after ${ms / 1000} s: ${what}`)), ms);
  });
  return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
}

async function main() {
  const spec = readSpec(process.argv[2]);
  const timeoutMs = spec.timeoutMs ?? 60000;
  const viewport = { width: spec.viewport?.width ?? 640, height: spec.viewport?.height ?? 480 };
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: ARGS, headless: true });
  const pageErrors = [];
  let failure = null;
  try {
    const context = await browser.newContext({ viewport, deviceScaleFactor: 1 });
    const page = await context.newPage();
    page.on('pageerror', (err) => pageErrors.push(`page error: ${err.message}`));
    page.on('console', (msg) => {
      if (msg.type() === 'error') {
        pageErrors.push(`console error: ${msg.text()}`);
      }
    });
    const check = () => {
      if (pageErrors.length > 0) {
        throw new RenderError(pageErrors.join('\n'));
      }
    };
    await withTimeout(page.goto(spec.url, { waitUntil: 'load' }), timeoutMs, `loading ${spec.url}`);
    await withTimeout(page.waitForFunction(() => window.lanterna !== undefined), timeoutMs,
      'waiting for window.lanterna');
    await withTimeout(page.evaluate(() => window.lanterna.ready), timeoutMs, 'waiting for lanterna.ready');
    check();
    for (const shot of spec.shots) {
      const result = await withTimeout(page.evaluate(async ({ light, region, layer, mode, params }) => {
        const l = window.lanterna;
        if (layer !== undefined) {
          await l.setActiveLayer(layer);
        }
        if (mode !== undefined) {
          l.setRenderMode(mode);
        }
        if (params !== undefined) {
          l.resetRenderParams();
          l.setRenderParams(params);
        }
        l.setLight(light[0], light[1]);
        l.showImageRegion(region[0], region[1], region[2], region[3]);
        await l.whenFullyLoaded();
        const { width, height, data } = l.readPixels();
        let binary = '';
        const chunk = 0x8000;
        for (let i = 0; i < data.length; i += chunk) {
          binary += String.fromCharCode.apply(null, data.subarray(i, i + chunk));
        }
        return { width, height, base64: btoa(binary), layer: l.getActiveLayer(), mode: l.getRenderMode() };
      }, shot), timeoutMs, `shot ${JSON.stringify(shot)}`);
      check();
      const bytes = Buffer.from(result.base64, 'base64');
      if (bytes.length !== result.width * result.height * 4) {
        throw new RenderError(`shot ${shot.out}: got ${bytes.length} bytes for ${result.width}×${result.height}`);
      }
      writeFileSync(shot.out, bytes);
      writeFileSync(`${shot.out}.json`, JSON.stringify({ width: result.width, height: result.height }));
      process.stdout.write(`${JSON.stringify({
        out: shot.out, width: result.width, height: result.height, light: shot.light, region: shot.region,
        layer: result.layer, mode: result.mode,
      })}\n`);
    }
    if (spec.screenshot) {
      await withTimeout(page.screenshot({ path: spec.screenshot }), timeoutMs, 'screenshot');
    }
    check();
  } catch (error) {
    failure = error;
  } finally {
    await browser.close();
  }
  if (failure) {
    throw failure;
  }
}

main().catch((error) => {
  fail(error instanceof RenderError ? error.message : (error?.stack ?? String(error)));
});
