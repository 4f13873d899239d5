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
// mode and parameters stay), show or hide the annotation `overlays` (optional bool), then set the light,
// fit the image-pixel region to the viewport, apply `lens` (optional, the argument of setLens), run the
// optional synthetic input `gestures`, wait until every tile is loaded and drawn, read the frame back
// (RGBA, rows top-down) and write the raw bytes to `out` and {width, height, overlayState, lens,
// light, view: {center, zoom}, hypertext, requests} to `out + ".json"` (`hypertext`: the widget's
// short line; `requests`: the URLs the page requested during the shot). One JSON line per shot goes to stdout. Exits non-zero on a page error, a console
// error, or a step taking longer than timeoutMs (default 60 s).
//
// Gesture steps (x, y in CSS px of the viewer element; `steps` intermediate moves, default 8):
//   {"type": "touch", "from": [[x, y], ...], "to": [[x, y], ...], "steps": 8}  (1 or 2 fingers, CDP)
//   {"type": "mouse", "from": [x, y], "to": [x, y], "steps": 8, "button": "left"}  (press, drag, release)
//   {"type": "pen", "from": [x, y], "to": [x, y], "steps": 8}  (a pen drag, CDP pointerType "pen")
//   {"type": "wheel", "at": [x, y], "deltaY": -100}
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
    if ((s.overlays !== undefined && typeof s.overlays !== 'boolean')
      || (s.lens !== undefined && (typeof s.lens !== 'object' || s.lens === null || Array.isArray(s.lens)))
      || (s.gestures !== undefined && !Array.isArray(s.gestures))) {
      throw new RenderError(`${path}: shot ${i}: overlays must be a boolean, lens an object, gestures a list`);
    }
    for (const g of s.gestures ?? []) {
      if (!['touch', 'mouse', 'pen', 'wheel'].includes(g?.type)) {
        throw new RenderError(`${path}: shot ${i}: gesture type must be touch, mouse, pen or wheel, got ${JSON.stringify(g)}`);
      }
    }
  }
  return spec;
}

function lerp(a, b, t) {
  return a + (b - a) * t;
}

/** Run one synthetic input step; (x, y) are CSS px of the viewer element at `origin`. */
async function runGesture(page, cdp, origin, g) {
  const steps = g.steps ?? 8;
  const at = ([x, y]) => ({ x: origin.x + x, y: origin.y + y });
  if (g.type === 'touch') {
    const to = g.to ?? g.from;
    const points = (t) => g.from.map((p, id) => {
      const q = to[id] ?? p;
      return { ...at([lerp(p[0], q[0], t), lerp(p[1], q[1], t)]), id };
    });
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: points(0) });
    for (let k = 1; k <= steps; k++) {
      await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: points(k / steps) });
      await page.evaluate(() => new Promise((r) => { requestAnimationFrame(() => r()); }));
    }
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  } else if (g.type === 'pen') {
    const from = at(g.from);
    const to = at(g.to ?? g.from);
    const pen = (type, p, buttons) => cdp.send('Input.dispatchMouseEvent', {
      type, x: p.x, y: p.y, button: 'left', buttons, clickCount: 1, pointerType: 'pen',
    });
    await pen('mousePressed', from, 1);
    for (let k = 1; k <= steps; k++) {
      await pen('mouseMoved', { x: lerp(from.x, to.x, k / steps), y: lerp(from.y, to.y, k / steps) }, 1);
      await page.evaluate(() => new Promise((r) => { requestAnimationFrame(() => r()); }));
    }
    await pen('mouseReleased', to, 0);
  } else if (g.type === 'mouse') {
    const from = at(g.from);
    const to = at(g.to ?? g.from);
    await page.mouse.move(from.x, from.y);
    await page.mouse.down({ button: g.button ?? 'left' });
    for (let k = 1; k <= steps; k++) {
      await page.mouse.move(lerp(from.x, to.x, k / steps), lerp(from.y, to.y, k / steps));
      await page.evaluate(() => new Promise((r) => { requestAnimationFrame(() => r()); }));
    }
    await page.mouse.up({ button: g.button ?? 'left' });
  } else {
    const p = at(g.at);
    await page.mouse.move(p.x, p.y);
    await page.mouse.wheel(0, g.deltaY ?? -100);
  }
  await page.evaluate(() => new Promise((r) => { requestAnimationFrame(() => r()); }));
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
    const uses = (type) => spec.shots.some((s) => (s.gestures ?? []).some((g) => g.type === type));
    const touch = uses('touch');
    const context = await browser.newContext({ viewport, deviceScaleFactor: 1, ...(touch ? { hasTouch: true } : {}) });
    const page = await context.newPage();
    const cdp = touch || uses('pen') ? await context.newCDPSession(page) : null;
    let requests = [];
    page.on('request', (req) => { requests.push(req.url()); });
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
      requests = [];
      await withTimeout(page.evaluate(async ({ light, region, layer, mode, params, overlays, lens }) => {
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
        if (overlays !== undefined) {
          l.setOverlaysVisible(overlays);
        }
        l.setLight(light[0], light[1]);
        l.showImageRegion(region[0], region[1], region[2], region[3]);
        if (lens !== undefined) {
          await l.setLens(lens);
        }
      }, shot), timeoutMs, `shot setup ${JSON.stringify(shot)}`);
      check();
      if (shot.gestures?.length) {
        await withTimeout(page.evaluate(() => window.lanterna.whenFullyLoaded()), timeoutMs, 'loading before gestures');
        const box = await page.evaluate(() => {
          const r = window.lanterna.viewer.element.getBoundingClientRect();
          return { x: r.left, y: r.top };
        });
        for (const g of shot.gestures) {
          await withTimeout(runGesture(page, cdp, box, g), timeoutMs, `gesture ${JSON.stringify(g)}`);
        }
        check();
      }
      const result = await withTimeout(page.evaluate(async () => {
        const l = window.lanterna;
        await l.whenFullyLoaded();
        const { width, height, data } = l.readPixels();
        let binary = '';
        const chunk = 0x8000;
        for (let i = 0; i < data.length; i += chunk) {
          binary += String.fromCharCode.apply(null, data.subarray(i, i + chunk));
        }
        const center = l.viewer.viewport.getCenter(true);
        return {
          width, height, base64: btoa(binary), layer: l.getActiveLayer(), mode: l.getRenderMode(),
          overlayState: l.getOverlayState?.() ?? null, lens: l.getLens?.() ?? null, light: l.getLight(),
          view: { center: [center.x, center.y], zoom: l.viewer.viewport.getZoom(true) },
          hypertext: document.querySelector('.lanterna-hypertext-short')?.textContent ?? null,
        };
      }), timeoutMs, `shot ${JSON.stringify(shot)}`);
      check();
      const bytes = Buffer.from(result.base64, 'base64');
      if (bytes.length !== result.width * result.height * 4) {
        throw new RenderError(`shot ${shot.out}: got ${bytes.length} bytes for ${result.width}×${result.height}`);
      }
      writeFileSync(shot.out, bytes);
      writeFileSync(`${shot.out}.json`, JSON.stringify({
        width: result.width, height: result.height, overlayState: result.overlayState, lens: result.lens,
        light: result.light, view: result.view, hypertext: result.hypertext, requests,
      }));
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
