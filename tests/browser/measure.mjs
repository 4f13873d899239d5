#!/usr/bin/env node
// Measurement mode in headless Chromium: call the page's measureAt, and try the widget with input.
//
//   node tests/browser/measure.mjs SPEC.json
//
// SPEC = {"pages": [{"url": "…/viewer/?manifest=…&measure=1", "touch": true,
//                    "cases": [{"layer": "ptm", "light": [lu, lv], "params": {…}, "region": [x, y, w, h],
//                               "points": [[x, y], …], "gestures": [<page-actions.mjs steps>],
//                               "hover": [x, y]}]}],
//         "viewport": {"width": 400, "height": 300}, "out": "/abs/result.json", "timeoutMs": 60000}
//
// For each case: switch to `layer`, set the render parameters (`params`, optional), the light, fit the
// image-pixel `region` to the viewport and wait until it is drawn; measure at each point (CSS px of
// the viewer element) with `window.lanternaMeasure.measure`; then run the optional `gestures` and
// move the mouse to `hover`, and read the viewer's light and view and the widget (hidden, rect,
// caption, its canvas's pixel at the centre). `out` gets {pages: [{cases: [{measurements: [...],
// after: {...}}]}]}, each measurement as measureAt returns it with the plot data as a list.
// A page with "touch" has touch input (touch gestures), one without mouse input (hover).
// Exits non-zero on a page error or a console error.
import { readFileSync, writeFileSync } from 'node:fs';
import process from 'node:process';
import { chromium } from 'playwright-core';
import { CHROMIUM, CHROMIUM_ARGS, runGesture } from './page-actions.mjs';


async function prepare(page, c) {
  await page.evaluate(async (c) => {
    const l = window.lanterna;
    if (c.layer) {
      await l.setActiveLayer(c.layer);
    }
    l.resetRenderParams();
    if (c.params) {
      l.setRenderParams(c.params);
    }
    l.setLight(c.light?.[0] ?? 0, c.light?.[1] ?? 0);
    if (c.region) {
      l.showImageRegion(...c.region);
    }
    await l.whenFullyLoaded();
  }, c);
}

function measure(page, points) {
  return page.evaluate(async (points) => {
    const out = [];
    for (const [x, y] of points) {
      const m = await window.lanternaMeasure.measure(x, y);
      out.push(m && { ...m, plot: { width: m.plot.width, height: m.plot.height, data: Array.from(m.plot.data) } });
    }
    return out;
  }, points);
}

function state(page) {
  return page.evaluate(() => {
    const l = window.lanterna;
    const w = window.lanternaMeasure;
    const el = w.element;
    const r = el.getBoundingClientRect();
    const host = l.viewer.element.getBoundingClientRect();
    const canvas = el.querySelector('canvas');
    const px = canvas ? Array.from(canvas.getContext('2d').getImageData(canvas.width / 2, canvas.height / 2, 1, 1).data)
      : null;
    const center = l.viewer.viewport.getCenter(true);
    return {
      light: l.getLight(), mode: l.getMode(), enabled: w.isEnabled(),
      view: { center: [center.x, center.y], zoom: l.viewer.viewport.getZoom(true) },
      widget: { hidden: el.hidden, rect: [r.left - host.left, r.top - host.top, r.width, r.height],
        host: [host.width, host.height], caption: el.querySelector('.lanterna-measure-caption')?.textContent ?? null,
        centerPixel: px },
      current: w.current() && { imageX: w.current().imageX, imageY: w.current().imageY, kind: w.current().kind },
    };
  });
}

async function main() {
  const spec = JSON.parse(readFileSync(process.argv[2], 'utf8'));
  const timeout = spec.timeoutMs ?? 60000;
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, headless: true });
  const errors = [];
  const result = { pages: [] };
  try {
    for (const p of spec.pages) {
      // touch emulation turns mouse input into touches: a page has one or the other
      const context = await browser.newContext({ viewport: spec.viewport ?? { width: 400, height: 300 },
        deviceScaleFactor: 1, hasTouch: p.touch === true });
      const page = await context.newPage();
      page.setDefaultTimeout(timeout);
      page.on('pageerror', (err) => errors.push(`page error: ${err.message}`));
      page.on('console', (msg) => { if (msg.type() === 'error') {errors.push(`console error: ${msg.text()}`);} });
      const cdp = await context.newCDPSession(page);
      await page.goto(p.url, { waitUntil: 'load' });
      await page.waitForFunction(() => window.lanternaMeasure !== undefined);
      await page.evaluate(() => window.lanterna.ready);
      // the gestures and the hover are on the image: close the page's panel if it is open over it
      await page.evaluate(() => {
        const toggle = document.getElementById('panel-toggle');
        if (toggle?.getAttribute('aria-expanded') === 'true') {
          toggle.click();
        }
      });
      const box = await page.evaluate(() => {
        const r = window.lanterna.viewer.element.getBoundingClientRect();
        return { x: r.left, y: r.top };
      });
      const cases = [];
      for (const c of p.cases) {
        await prepare(page, c);
        const before = await state(page);
        const measurements = await measure(page, c.points ?? []);
        for (const g of c.gestures ?? []) {
          await runGesture(page, cdp, box, g, true);
        }
        if (c.hover) {
          await page.mouse.move(box.x + c.hover[0], box.y + c.hover[1]);
        }
        // let the last measurement the input asked for finish
        await page.evaluate(async () => { await window.lanternaMeasure.idle(); await window.lanterna.whenFullyLoaded(); });
        cases.push({ measurements, before, after: await state(page) });
      }
      result.pages.push({ cases });
      await context.close();
    }
  } finally {
    await browser.close();
  }
  writeFileSync(spec.out, JSON.stringify(result));
  if (errors.length > 0) {
    process.stderr.write(`measure.mjs: ${errors.join('\n')}\n`);
    process.exitCode = 1;
  }
}

main().catch((error) => {
  process.stderr.write(`measure.mjs: ${error?.stack ?? error}\n`);
  process.exitCode = 1;
});
