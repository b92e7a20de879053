// SPDX-License-Identifier: BSD-3-Clause
// The avatar stream's sync at the page (docs/streaming.md): MorphAvatar --serve and one
// headless chromium page (phone viewport) for MINUTES minutes; a sentence every 6 s.
// Reported: the audio-visual offset of every frame shown (the frame's sample minus the
// sample the sound's clock says is heard, when the page draws it; EBU R37: sound at most
// 40 ms before (offset < -40) or 60 ms after (offset > +60) the picture), and the first
// mouth motion after `say` (page's wall clock from sending say to drawing the first frame
// whose mouth weight is above 10/255), split into the server's part (the say's `started`
// event's latency_ms: from its arrival to the first frame with its speech, synthesis
// included) and the rest (network, the page's jitter buffer, drawing). JITTER is the page's
// jitter parameter (auto: adaptive, or milliseconds). Not a test.
//   node study_stream_sync.mjs MORPHAVATAR NPM_TOOLS [MINUTES=5] [JITTER=auto]
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

const [morphAvatar, npmTools, minutesArg, jitterArg] = process.argv.slice(2);
const jitter = jitterArg || 'auto';
const minutes = Number(minutesArg || 5);
const { chromium } = createRequire(join(resolve(npmTools), 'node_modules', 'x.js'))('playwright-core');
const server = spawn(morphAvatar, ['--serve', '127.0.0.1:0', '--exit-after', String(minutes * 60 + 120)],
  { stdio: ['ignore', 'pipe', 'pipe'] });
let log = '';
const address = await new Promise((res, rej) => {
  server.stderr.on('data', (d) => { log += d; const m = /on (http:\/\/[0-9.]+:\d+)\//.exec(log); if (m) res(m[1]); });
  server.on('exit', () => rej(new Error(log)));
});
const profile = mkdtempSync(join(tmpdir(), 'morphnode-sync-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: '/usr/bin/chromium', headless: true, viewport: { width: 390, height: 844 },
  args: ['--headless', '--no-sandbox', '--enable-unsafe-swiftshader', '--disable-gpu',
    '--disable-background-networking', '--disable-component-update', '--no-first-run',
    '--autoplay-policy=no-user-gesture-required'],
});
const page = await context.newPage();
await page.goto(`${address}/?jitter=${jitter}`);
await page.waitForFunction(() => window.morphnode && window.morphnode.state.loaded && window.morphnode.state.shown);
const result = await page.evaluate(async (ms) => {
  const m = window.morphnode, s = m.state;
  const mouth = ['A', 'E', 'O', 'S', 'F', 'L'];
  const latencies = [], server = [];
  const sentences = ['Hello there, how are you today?', 'The weather is fine and the sun is out.',
    'I am a face made of a few morph targets.'];
  s.offsets = [];
  const t0 = performance.now();
  let k = 0;
  while (performance.now() - t0 < ms) {
    const sent = performance.now();
    const shownBefore = s.shown;
    const eventsBefore = s.events.length;
    m.say(sentences[k++ % sentences.length]);
    let first = null;
    while (performance.now() - sent < 6000) {
      await new Promise((r) => requestAnimationFrame(r));
      if (first === null && s.shown !== shownBefore &&
        s.shown.targets.some(([i, v]) => mouth.includes(s.header.targets[i]) && v > 10)) {
        first = performance.now() - sent;
      }
    }
    if (first !== null) latencies.push(first);
    const started = s.events.slice(Math.max(0, eventsBefore - 5)).reverse()
      .find((e) => e.event === 'started' && e.cmd === 'say' && typeof e.latency_ms === 'number');
    if (started) server.push(started.latency_ms);
    s.events.length = 0;
  }
  return { offsets: s.offsets, latencies, server, underruns: s.frameUnderruns, late: s.audioLate,
    rate: s.header.sampleRate, jitterMs: s.jitterMs, jitterChanges: s.jitterChanges };
}, minutes * 60000);
await context.close();
rmSync(profile, { recursive: true, force: true });
server.kill('SIGTERM');
const q = (a, p) => { const b = [...a].sort((x, y) => x - y); return b[Math.min(b.length - 1, Math.floor(p * b.length))]; };
const o = result.offsets;
// offset < 0: the picture shows an earlier moment than is heard, i.e. the sound leads.
const outside = o.filter((v) => v < -40 || v > 60).length;
console.log(`| minutes | jitter buffer at the end (ms; changes) | server part of first motion: median / p95 (ms) | frames shown | A/V offset median / p5 / p95 / min / max (ms) | outside EBU R37 | first mouth motion after say: median / p95 / max (ms, ${result.latencies.length} says) | frame underruns | late sound (ms) |`);
console.log('|---:|---|---|---:|---|---:|---|---:|---:|');
const sv = result.server.length ? `${q(result.server, 0.5).toFixed(0)} / ${q(result.server, 0.95).toFixed(0)}` : '-';
console.log(`| ${minutes} | ${result.jitterMs.toFixed(0)} (${jitter}; ${result.jitterChanges}) | ${sv} | ${o.length} | ${q(o, 0.5).toFixed(1)} / ${q(o, 0.05).toFixed(1)} / ${q(o, 0.95).toFixed(1)} / ${Math.min(...o).toFixed(1)} / ${Math.max(...o).toFixed(1)} | ${outside} (${(100 * outside / o.length).toFixed(2)} %) | ` +
  `${q(result.latencies, 0.5).toFixed(0)} / ${q(result.latencies, 0.95).toFixed(0)} / ${Math.max(...result.latencies).toFixed(0)} | ${result.underruns} | ${(1000 * result.late / result.rate).toFixed(0)} |`);
