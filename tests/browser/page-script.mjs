#!/usr/bin/env node
// Drive a viewer page in headless Chromium through a list of steps and save what they return.
//
//   node tests/browser/page-script.mjs SPEC.json
//
// SPEC = {"url": "…", "viewport": {"width": 1280, "height": 800}, "mobile": false, "timeoutMs": 60000,
//         "routes": [...] (as tests/browser/render.mjs: answer matching URLs with a fault or a fake),
//         "allowConsoleErrors": ["regex"], "result": "/abs/result.json", "steps": [...]}
// Steps, run in order; each step's value goes to result.json's "values" (null when it has none):
//   {"eval": "async () => …"}  a function run in the page; its (JSON) return value
//   {"waitFor": "() => …"}  wait until the function returns a truthy value
//   {"click": "CSS selector"} / {"tap": "CSS selector"}  a mouse click / a touch tap (mobile) on it
//   {"hover": "CSS selector"}  move the mouse over it
//   {"fill": "CSS selector", "value": "…"}  type into an input
//   {"select": "CSS selector", "value": "…"}  choose an option of a <select>
//   {"files": "CSS selector", "path": "/abs/file"}  set the files of an <input type=file>
//   {"drop": "/abs/file", "selector": "CSS selector"}  drop the file on that element (a DataTransfer)
//   {"download": "CSS selector", "path": "/abs/out"}  click it and save the download it starts
//   {"key": "Tab"}  press a key
//   {"gesture": {…}, "on": "CSS selector"}  a gesture of page-actions.mjs (mouse, touch, pen…), x and y in
//       CSS px of that element (default the viewer element); with "fraction": true, in fractions of its size
//       (one-pointer gestures)
//   {"screenshot": "/abs/out.png"}
// After the last step the page is left to settle (lanterna.whenFullyLoaded, so that no request is cut
// off) unless spec "settle" is false.
// result.json also holds "requests" (method, URL, headers and body of every request whose URL
// matches spec "record", a regex), "consoleErrors" and "pageErrors". Exits non-zero on a page error,
// a console error not allowed, or a step taking longer than timeoutMs.
import { readFileSync, writeFileSync } from 'node:fs';
import { basename } from 'node:path';
import process from 'node:process';
import { chromium } from 'playwright-core';
import { CHROMIUM, CHROMIUM_ARGS, installRoutes, runGesture, watchErrors, withTimeout } from './page-actions.mjs';


async function runStep(page, step, timeoutMs, cdp) {
  if (step.eval !== undefined) {
    return page.evaluate(`(${step.eval})()`);
  }
  if (step.waitFor !== undefined) {
    await page.waitForFunction(`(${step.waitFor})()`, null, { timeout: timeoutMs });
    return null;
  }
  if (step.click !== undefined) {
    await page.click(step.click);
  } else if (step.tap !== undefined) {
    await page.tap(step.tap);
  } else if (step.hover !== undefined) {
    await page.hover(step.hover);
  } else if (step.fill !== undefined) {
    await page.fill(step.fill, step.value ?? '');
  } else if (step.select !== undefined) {
    await page.selectOption(step.select, step.value);
  } else if (step.files !== undefined) {
    await page.setInputFiles(step.files, step.path);
  } else if (step.drop !== undefined) {
    const text = readFileSync(step.drop, 'utf8');
    const transfer = await page.evaluateHandle(({ text, name }) => {
      const dt = new DataTransfer();
      dt.items.add(new File([text], name, { type: 'application/json' }));
      return dt;
    }, { text, name: basename(step.drop) });
    const target = step.selector ?? 'body';
    await page.dispatchEvent(target, 'dragover', { dataTransfer: transfer });
    await page.dispatchEvent(target, 'drop', { dataTransfer: transfer });
  } else if (step.download !== undefined) {
    const [download] = await Promise.all([page.waitForEvent('download'), page.click(step.download)]);
    await download.saveAs(step.path);
    return download.suggestedFilename();
  } else if (step.gesture !== undefined) {
    const box = await page.evaluate((sel) => {
      const r = (sel ? document.querySelector(sel) : window.lanterna.viewer.element).getBoundingClientRect();
      return { x: r.left, y: r.top, width: r.width, height: r.height };
    }, step.on ?? null);
    // "fraction": true gives x and y as fractions of the element's size
    const scale = ([x, y]) => [x * box.width, y * box.height];
    const g = step.fraction ? {
      ...step.gesture, from: scale(step.gesture.from), to: scale(step.gesture.to ?? step.gesture.from),
    } : step.gesture;
    await runGesture(page, cdp, box, g, false);
  } else if (step.key !== undefined) {
    await page.keyboard.press(step.key);
  } else if (step.screenshot !== undefined) {
    await page.screenshot({ path: step.screenshot });
  } else {
    throw new Error(`unknown step ${JSON.stringify(step)}`);
  }
  await page.evaluate(() => new Promise((r) => { requestAnimationFrame(() => r()); }));
  return null;
}

async function main() {
  const spec = JSON.parse(readFileSync(process.argv[2], 'utf8'));
  const timeoutMs = spec.timeoutMs ?? 60000;
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, headless: true });
  const pageErrors = [];
  const consoleErrors = [];
  const requests = [];
  const values = [];
  const allowed = (spec.allowConsoleErrors ?? []).map((p) => new RegExp(p));
  const record = spec.record ? new RegExp(spec.record) : null;
  let failure = null;
  try {
    const context = await browser.newContext({
      viewport: spec.viewport ?? { width: 1280, height: 800 }, deviceScaleFactor: 1, acceptDownloads: true,
      ...(spec.mobile ? { hasTouch: true, isMobile: true } : {}),
      ...((spec.steps ?? []).some((st) => st.gesture?.type === 'touch') ? { hasTouch: true } : {}),
    });
    const page = await context.newPage();
    const cdp = await context.newCDPSession(page);
    watchErrors(page, allowed, pageErrors, consoleErrors);
    page.on('request', (req) => {
      if (record?.test(req.url())) {
        requests.push({ method: req.method(), url: req.url(), headers: req.headers(), body: req.postData() });
      }
    });
    await installRoutes(page, spec.routes ?? []);
    await withTimeout(page.goto(spec.url, { waitUntil: 'load' }), timeoutMs, `loading ${spec.url}`);
    for (const step of spec.steps ?? []) {
      values.push(await withTimeout(runStep(page, step, timeoutMs, cdp), timeoutMs, JSON.stringify(step).slice(0, 200)));
      if (pageErrors.length > 0) {
        throw new Error(pageErrors.join('\n'));
      }
    }
    if (spec.settle !== false) {
      await withTimeout(page.evaluate(() => window.lanterna?.whenFullyLoaded?.()), timeoutMs, 'settling');
    }
  } catch (error) {
    failure = error;
  } finally {
    if (spec.result) {
      writeFileSync(spec.result, JSON.stringify({ values, requests, consoleErrors, pageErrors }));
    }
    await browser.close();
  }
  if (failure) {
    throw failure;
  }
}

main().catch((error) => {
  process.stderr.write(`page-script.mjs: ${error?.stack ?? String(error)}\n`);
  process.exitCode = 1;
});
