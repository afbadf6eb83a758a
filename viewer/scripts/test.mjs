// Headless browser test of the built viewer (run by scripts/test.sh):
// serves dist/ and the fixture .glb on 127.0.0.1, drives Debian's chromium
// through playwright-core, and checks what a person would see. Pixels are
// decoded by the browser itself (screenshot PNG -> <img> -> 2D canvas), so no
// image library is needed. The fixture is first checked with Khronos'
// glTF-Validator. Prints `viewer: N passed, M failed`; exit code 1
// on any failure.
import { spawn } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import validator from 'gltf-validator';
import { chromium } from 'playwright-core';
import { frameIndexAt } from '../src/timeline.js';
import { startServer } from './serve.mjs';

const here = resolve(fileURLToPath(import.meta.url), '../..');
const outDir = resolve(process.env.VIEWER_TEST_OUT ?? join(here, '../out/viewer-test'));
const fixture = process.env.VIEWER_FIXTURE ?? join(outDir, 'fixture.glb');
const results = [];
let liveSend = null;

async function check(name, fn) {
  const t0 = Date.now();
  try {
    await fn();
    results.push([name, null]);
    console.log(`ok   - ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    results.push([name, e]);
    console.log(`FAIL - ${name}: ${e.message ?? e}`);
  }
}

function assert(cond, msg) {
  if (!cond) throw new Error(msg);
}

/** Pixel statistics of a PNG, decoded in the page. */
async function stats(page, png, other = null) {
  return page.evaluate(
    async ([a, b]) => {
      const decode = async (b64) => {
        const img = new Image();
        img.src = `data:image/png;base64,${b64}`;
        await img.decode();
        const c = document.createElement('canvas');
        c.width = img.width;
        c.height = img.height;
        const g = c.getContext('2d');
        g.drawImage(img, 0, 0);
        return g.getImageData(0, 0, c.width, c.height).data;
      };
      const p = await decode(a);
      const colors = new Set();
      let reddish = 0;
      let bluish = 0;
      let greenish = 0;
      let greenTint = 0; // pale, lit green (tumble's palette on a bright ground)
      for (let i = 0; i < p.length; i += 4) {
        const [r, g, bl] = [p[i], p[i + 1], p[i + 2]];
        colors.add(((r >> 3) << 10) | ((g >> 3) << 5) | (bl >> 3));
        if (r > g + 50 && r > bl + 50) reddish++;
        if (bl > r + 50 && bl > g + 20) bluish++;
        if (g > r + 40 && g > bl + 30) greenish++;
        if (g > r + 15 && g > bl + 15) greenTint++;
      }
      let changed = -1;
      if (b) {
        const q = await decode(b);
        changed = 0;
        for (let i = 0; i < p.length; i += 4) {
          const d = Math.abs(p[i] - q[i]) + Math.abs(p[i + 1] - q[i + 1]) + Math.abs(p[i + 2] - q[i + 2]);
          if (d > 24) changed++;
        }
      }
      return { pixels: p.length / 4, colors: colors.size, reddish, bluish, greenish, greenTint, changed };
    },
    [png.toString('base64'), other ? other.toString('base64') : null],
  );
}

/** Screenshot of the 3D view above the control panel. */
async function shot(page) {
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  return page.screenshot({ clip: { x: 0, y: 40, width: 960, height: 400 } });
}

function liveScene() {
  // A unit-ish box and a tetrahedron, streamed as the live format expects.
  const box = {
    name: 'box',
    color: [0.2, 0.45, 0.95, 1],
    is_static: false,
    vertices: [-0.3, -0.3, -0.3, 0.3, -0.3, -0.3, 0.3, 0.3, -0.3, -0.3, 0.3, -0.3, -0.3, -0.3, 0.3, 0.3, -0.3, 0.3, 0.3, 0.3, 0.3, -0.3, 0.3, 0.3],
    triangles: [0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7],
  };
  const tet = {
    name: 'tet',
    color: [0.95, 0.3, 0.2, 1],
    is_static: false,
    vertices: [0.4, 0, 0, -0.2, 0.35, 0, -0.2, -0.35, 0, 0, 0, 0.5],
    triangles: [0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3],
  };
  // A hinge on the box's edge, along its y axis: drawn on the box.
  const joints = [{ name: 'edge', kind: 'hinge', body: 0, anchor: [0.3, 0, 0.3], axis: [0, 1, 0] }];
  return { type: 'scene', bodies: [box, tet], joints };
}

/** Starts `tumble view ARGS` and resolves to { url, stop } once it prints its URL. */
function startTumbleView(args) {
  const bin = process.env.TUMBLE_BIN;
  if (!bin) throw new Error('TUMBLE_BIN is not set (scripts/test.sh sets it)');
  const child = spawn(bin, ['view', '--no-open', '--port', '0', '--viewer-dir', join(here, 'dist'), ...args], {
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  let stderr = '';
  child.stderr.on('data', (d) => (stderr += d));
  const stop = () => {
    child.kill();
  };
  return new Promise((ok, fail) => {
    let out = '';
    const timer = setTimeout(() => fail(new Error(`tumble view printed no URL: ${stderr}`)), 30000);
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/http:\/\/127\.0\.0\.1:\d+\/\S*/);
      if (m) {
        clearTimeout(timer);
        ok({ url: m[0], stop });
      }
    });
    child.on('exit', (code) => {
      clearTimeout(timer);
      fail(new Error(`tumble view exited with ${code}: ${stderr}`));
    });
  });
}

const server = await startServer({
  root: join(here, 'dist'),
  fixtureDir: resolve(fixture, '..'),
  onLive: (send) => (liveSend = send),
});
const base = `http://127.0.0.1:${server.port}`;
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
mkdirSync(outDir, { recursive: true });

try {
  await check('frame lookup matches a linear scan', async () => {
    // Oracle: the last index whose time is <= t, found by scanning.
    let seed = 12345;
    const rand = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
    for (let trial = 0; trial < 200; trial++) {
      const times = [];
      let t = rand();
      for (let i = 0, n = 1 + Math.floor(rand() * 40); i < n; i++) times.push((t += 0.001 + rand()));
      for (let q = 0; q < 50; q++) {
        const x = rand() * (t + 2) - 1;
        let want = 0;
        times.forEach((ti, i) => ti <= x && (want = i));
        const got = frameIndexAt(times, x);
        assert(got === want, `t=${x} in ${times.length} frames: got ${got}, want ${want}`);
      }
      assert(frameIndexAt(times, times[times.length - 1]) === times.length - 1, 'last frame');
    }
  });

  await check('fixture is valid glTF 2.0 (Khronos glTF-Validator)', async () => {
    const report = await validator.validateBytes(new Uint8Array(readFileSync(fixture)));
    const { numErrors, numWarnings, messages } = report.issues;
    const first = messages.slice(0, 3).map((m) => `${m.code} at ${m.pointer}: ${m.message}`);
    assert(numErrors === 0 && numWarnings === 0, `${numErrors} errors, ${numWarnings} warnings: ${first.join('; ')}`);
    assert(report.info.animationCount === 1, `expected 1 animation, validator saw ${report.info.animationCount}`);
  });

  const page = await browser.newPage({ viewport: { width: 960, height: 640 } });
  const problems = [];
  page.on('console', (m) => m.type() === 'error' && problems.push(`console: ${m.text()}`));
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  page.on('requestfailed', (r) => problems.push(`request failed: ${r.url()}`));
  const fixtureName = fixture.split('/').pop();

  await check('loads the fixture without console errors', async () => {
    await page.goto(`${base}/index.html?file=/fixture/${fixtureName}&paused=1`);
    await page.waitForFunction(() => window.tumbleViewer?.status === 'ready' || window.tumbleViewer?.status === 'error', null, {
      timeout: 20000,
    });
    const v = await page.evaluate(() => ({ ...window.tumbleViewer, statusText: window.tumbleViewer.statusText }));
    assert(v.status === 'ready', `status ${v.status}: ${v.statusText}`);
    assert(v.bodies === 4, `expected 4 bodies, got ${v.bodies}`);
    assert(v.frames > 10 && v.duration > 1, `expected a multi-second recording, got ${v.frames} frames / ${v.duration} s`);
    assert(problems.length === 0, problems.join('; '));
  });

  let first = null;
  await check('renders non-blank frames showing the bodies', async () => {
    await page.evaluate(() => window.tumbleViewer.seek(0.3));
    first = await shot(page);
    const s = await stats(page, first);
    assert(s.colors > 50, `only ${s.colors} distinct colours: blank frame?`);
    // Ball (orange-red), slider (blue) and torus (green) must all be visible.
    assert(s.reddish > 200 && s.bluish > 200 && s.greenish > 200, `body colours missing: ${JSON.stringify(s)}`);
    writeFileSync(join(outDir, 'viewer.png'), await page.screenshot());
  });

  await check('the picture changes as time advances', async () => {
    await page.evaluate(() => window.tumbleViewer.seek(1.5));
    const later = await shot(page);
    const s = await stats(page, first, later);
    assert(s.changed > 0.002 * s.pixels, `only ${s.changed} of ${s.pixels} pixels changed between t=0.3 s and t=1.5 s`);
    writeFileSync(join(outDir, 'viewer-t1.5.png'), await page.screenshot());
    // Playback moves the clock on its own.
    const t0 = await page.evaluate(() => window.tumbleViewer.time);
    await page.evaluate(() => window.tumbleViewer.setPlaying(true));
    await page.waitForTimeout(600);
    const t1 = await page.evaluate(() => window.tumbleViewer.time);
    await page.evaluate(() => window.tumbleViewer.setPlaying(false));
    assert(Math.abs(t1 - t0) > 0.2, `playing for 0.6 s moved the clock from ${t0} to ${t1}`);
  });

  await check('OBB overlay toggle draws boxes', async () => {
    await page.evaluate(() => window.tumbleViewer.seek(0.3));
    const label = await page.textContent('#obb-label');
    assert(/\(\d+\)/.test(label), `OBB label says ${label}`);
    const off = await shot(page);
    await page.check('#show-obb');
    const on = await shot(page);
    await page.uncheck('#show-obb');
    const s = await stats(page, off, on);
    assert(s.changed > 200, `toggling OBB boxes changed only ${s.changed} pixels`);
    assert(problems.length === 0, problems.join('; '));
  });
  // A hidden page still renders with software GL; close it so that it does
  // not slow the live-mode page down.
  await page.close();

  await check('live mode draws bodies streamed over a WebSocket', async () => {
    const live = await browser.newPage({ viewport: { width: 960, height: 640 } });
    const liveProblems = [];
    live.on('console', (m) => m.type() === 'error' && liveProblems.push(`console: ${m.text()}`));
    live.on('pageerror', (e) => liveProblems.push(`pageerror: ${e.message}`));
    liveSend = null;
    await live.goto(`${base}/index.html?live=ws://127.0.0.1:${server.port}/live`);
    for (let i = 0; i < 100 && !liveSend; i++) await live.waitForTimeout(50);
    assert(liveSend, 'the page did not open the WebSocket');
    liveSend(JSON.stringify(liveScene()));
    const n = 40;
    for (let f = 0; f < n; f++) {
      const t = f / 30;
      liveSend(
        JSON.stringify({
          type: 'frame',
          t,
          poses: [
            [0, 0, 0.8 + 0.3 * Math.sin(3 * t), 0, 0, Math.sin(t / 2), Math.cos(t / 2)],
            [0.9, 0.2, 0.6, 0, 0, 0, 1],
          ],
          kinetic_energy: 0.5 * (0.9 * Math.cos(3 * t)) ** 2,
          potential_energy: 9.81 * (0.8 + 0.3 * Math.sin(3 * t)),
          contacts: f > 20 ? [[0.9, 0.2, 0.0, 0, 0, 1, 0]] : [],
        }),
      );
    }
    await live.waitForFunction((k) => window.tumbleViewer?.frames === k, n, { timeout: 10000 });
    // The view moves to the newest frame on its next animation frame, which a
    // loaded machine's software GL can take a while to run: wait for it (a view
    // that does not follow still fails below, at the timeout).
    await live
      .waitForFunction((t) => Math.abs(window.tumbleViewer.time - t) < 1e-9, (n - 1) / 30, { timeout: 10000 })
      .catch(() => {});
    const v = await live.evaluate(() => ({ bodies: window.tumbleViewer.bodies, time: window.tumbleViewer.time }));
    assert(v.bodies === 2, `expected 2 live bodies, got ${v.bodies}`);
    assert(Math.abs(v.time - (n - 1) / 30) < 1e-9, `live view should follow the newest frame, at ${v.time}`);
    // The hinge marker moves with the box: at the box's newest pose applied to the anchor
    // (turned by t about z, lifted to 0.8 + 0.3 sin 3t).
    await live.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const anchors = await live.evaluate(() => window.tumbleViewer.jointAnchors);
    const t = (n - 1) / 30;
    const want = [0.3 * Math.cos(t), 0.3 * Math.sin(t), 0.8 + 0.3 * Math.sin(3 * t) + 0.3];
    assert(anchors.length === 1, `expected 1 joint marker, got ${anchors.length}`);
    const off = Math.hypot(...anchors[0].map((x, k) => x - want[k]));
    assert(off < 1e-5, `the joint marker is ${off} m from the box's anchor: ${anchors[0]} vs ${want}`);
    const s = await stats(live, await shot(live));
    assert(s.bluish > 100 && s.reddish > 100, `live bodies not visible: ${JSON.stringify(s)}`);
    writeFileSync(join(outDir, 'viewer-live.png'), await live.screenshot());
    assert(liveProblems.length === 0, liveProblems.join('; '));
    await live.close();
  });
  await check('tumble view plays a recording in the page', async () => {
    const glb = process.env.TUMBLE_RECORDING;
    assert(glb, 'TUMBLE_RECORDING is not set (scripts/test.sh sets it)');
    const { url, stop } = await startTumbleView([glb]);
    const page2 = await browser.newPage({ viewport: { width: 960, height: 640 } });
    const errs = [];
    page2.on('console', (m) => m.type() === 'error' && errs.push(`console: ${m.text()}`));
    page2.on('pageerror', (e) => errs.push(`pageerror: ${e.message}`));
    try {
      await page2.goto(`${url}&paused=1`);
      await page2.waitForFunction(() => ['ready', 'error'].includes(window.tumbleViewer?.status), null, { timeout: 20000 });
      const v = await page2.evaluate(() => ({ status: window.tumbleViewer.status, bodies: window.tumbleViewer.bodies, duration: window.tumbleViewer.duration }));
      assert(v.status === 'ready' && v.bodies === 3, `status ${v.status}, ${v.bodies} bodies`);
      assert(v.duration > 5.9, `duration ${v.duration}`);
      // t = 2.5 s: torus B (green) has hit torus A (blue) and drags it along.
      await page2.evaluate(() => window.tumbleViewer.seek(2.5));
      const a = await shot(page2);
      writeFileSync(join(outDir, 'viewer-tori-pass.png'), await page2.screenshot());
      const s = await stats(page2, a);
      assert(s.colors > 50 && s.bluish > 200 && s.greenTint > 200, `tori not visible: ${JSON.stringify(s)}`);
      await page2.evaluate(() => window.tumbleViewer.seek(0.2));
      const s2 = await stats(page2, a, await shot(page2));
      assert(s2.changed > 0.002 * s2.pixels, `only ${s2.changed} pixels changed between t=2.5 and t=0.2`);
      assert(errs.length === 0, errs.join('; '));
    } finally {
      await page2.close();
      stop();
    }
  });

  await check('tumble view steps a scene live in the page', async () => {
    const sceneFile = process.env.TUMBLE_LIVE_SCENE;
    assert(sceneFile, 'TUMBLE_LIVE_SCENE is not set (scripts/test.sh sets it)');
    const { url, stop } = await startTumbleView([sceneFile]);
    assert(url.includes('?live=ws://'), `not a live URL: ${url}`);
    const page3 = await browser.newPage({ viewport: { width: 960, height: 640 } });
    const errs = [];
    page3.on('console', (m) => m.type() === 'error' && errs.push(`console: ${m.text()}`));
    page3.on('pageerror', (e) => errs.push(`pageerror: ${e.message}`));
    try {
      await page3.goto(url);
      await page3.waitForFunction(() => window.tumbleViewer?.frames > 30, null, { timeout: 30000 });
      const v = await page3.evaluate(() => ({ bodies: window.tumbleViewer.bodies, t: window.tumbleViewer.time }));
      assert(v.bodies === 3, `expected 3 live bodies, got ${v.bodies}`);
      const a = await shot(page3);
      writeFileSync(join(outDir, 'viewer-tumble-live.png'), await page3.screenshot());
      const s = await stats(page3, a);
      assert(s.colors > 50 && s.bluish > 200 && s.greenTint > 200, `live tori not visible: ${JSON.stringify(s)}`);
      // The simulation keeps streaming: more frames, later time, a changed picture.
      const f0 = await page3.evaluate(() => window.tumbleViewer.frames);
      await page3.waitForFunction((k) => window.tumbleViewer.frames > k + 30, f0, { timeout: 30000 });
      const t1 = await page3.evaluate(() => window.tumbleViewer.time);
      assert(t1 > v.t, `live time did not advance: ${v.t} -> ${t1}`);
      const s2 = await stats(page3, a, await shot(page3));
      assert(s2.changed > 0.001 * s2.pixels, `live picture did not change (${s2.changed} pixels)`);
      writeFileSync(join(outDir, 'viewer-tumble-live.png'), await page3.screenshot());
      assert(errs.length === 0, errs.join('; '));
    } finally {
      await page3.close();
      stop();
    }
  });

  await check('tower game: a click throws a ball that knocks the tower down', async () => {
    const sceneFile = process.env.TUMBLE_GAME_SCENE;
    assert(sceneFile, 'TUMBLE_GAME_SCENE is not set (scripts/test.sh sets it)');
    const { url, stop } = await startTumbleView([sceneFile]);
    const page4 = await browser.newPage({ viewport: { width: 960, height: 640 } });
    const errs = [];
    page4.on('console', (m) => m.type() === 'error' && errs.push(`console: ${m.text()}`));
    page4.on('pageerror', (e) => errs.push(`pageerror: ${e.message}`));
    try {
      await page4.goto(url);
      await page4.waitForFunction(() => window.tumbleViewer?.frames > 20, null, { timeout: 30000 });
      const before = await page4.evaluate(() => ({ bodies: window.tumbleViewer.bodies, poses: window.tumbleViewer.lastPoses }));
      assert(before.bodies === 17, `expected the ground and 16 blocks, got ${before.bodies}`);
      const a = await shot(page4);
      // The camera frames the tower: a click in the middle of the view aims at it.
      await page4.mouse.click(480, 300);
      await page4.waitForFunction(() => window.tumbleViewer.thrown === 1 && window.tumbleViewer.bodies === 18, null, {
        timeout: 10000,
      });
      const t0 = await page4.evaluate(() => window.tumbleViewer.time);
      await page4.waitForFunction((t) => window.tumbleViewer.time > t + 2.5, t0, { timeout: 30000 });
      const after = await page4.evaluate(() => window.tumbleViewer.lastPoses);
      assert(after.length === 18, `the newest frame has ${after.length} poses, expected 18 with the ball`);
      // Blocks are bodies 1..16; the ball is the last one.
      let moved = 0;
      let fallen = 0;
      for (let b = 1; b <= 16; b++) {
        const d = Math.hypot(...[0, 1, 2].map((i) => after[b][i] - before.poses[b][i]));
        if (d > 0.1) moved++;
        if (after[b][2] < before.poses[b][2] - 0.25) fallen++;
      }
      assert(moved >= 4 && fallen >= 2, `only ${moved} blocks moved more than 0.1 m and ${fallen} fell`);
      const s = await stats(page4, a, await shot(page4));
      assert(s.changed > 0.01 * s.pixels, `the picture hardly changed (${s.changed} pixels)`);
      writeFileSync(join(outDir, 'viewer-tower-game.png'), await page4.screenshot());
      assert(errs.length === 0, errs.join('; '));
    } finally {
      await page4.close();
      stop();
    }
  });
} finally {
  await browser.close();
  await server.close();
}

const failed = results.filter(([, e]) => e).length;
console.log(`screenshots: ${outDir}/viewer.png, viewer-t1.5.png, viewer-live.png, viewer-tori-pass.png, viewer-tumble-live.png, viewer-tower-game.png`);
console.log(`viewer: ${results.length - failed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
