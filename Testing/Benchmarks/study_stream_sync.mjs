// SPDX-License-Identifier: BSD-3-Clause
// The avatar stream's sync at the page (docs/streaming.md): MorphAvatar --serve and one
// headless chromium page (phone viewport) for MINUTES minutes; a sentence every 6 s.
// Reported:
// - the audio-visual offset of every frame drawn: the frame's sample minus the sample the
//   sound's clock says is heard when the page draws it (negative: the picture shows an
//   earlier moment than is heard, i.e. the sound leads). EBU R37 allows the sound at most
//   40 ms before the picture (offset >= -40) and at most 60 ms after it (offset <= +60).
//   Each frame outside is explained: the frame the sound's clock asked for had not reached
//   the page's main thread yet (late from the server, or held up in the page), or another
//   cause;
// - the first mouth motion after `say` (page's wall clock from sending say to the end of
//   the draw of the first frame whose mouth weight is above 10/255) and where that time goes,
//   per step (medians over the says): the round trip of a command (`accepted` back), the
//   server's part (the `started` event's latency_ms: from the say's arrival to the frame
//   its speech starts at: waiting for the synthesis pool, synthesizing the first chunk, the
//   frame clock), the speech's own onset (from its start to the first frame with the mouth
//   open), the way to the page (the open frame's arrival at the page's socket worker, less
//   the above), the handover to the page's main thread, the jitter buffer (until the
//   sound's clock reaches the frame), the wait for the next animation frame, the draw.
// JITTER is the page's jitter parameter (milliseconds, the default 40, or auto). The load
// average of the machine (os.loadavg) is printed: the page draws in software (SwiftShader)
// and shares the CPU. Not a test.
//   node study_stream_sync.mjs MORPHAVATAR NPM_TOOLS [MINUTES=5] [JITTER=40] [QUERY]
// QUERY: more page parameters (e.g. "device=phone").
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { mkdtempSync, rmSync } from 'node:fs';
import { loadavg, tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

const [morphAvatar, npmTools, minutesArg, jitterArg, queryArg] = process.argv.slice(2);
const jitter = jitterArg || '40';
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
await page.goto(`${address}/?jitter=${jitter}${queryArg ? `&${queryArg}` : ''}`);
await page.waitForFunction(() => window.morphnode && window.morphnode.state.loaded && window.morphnode.state.shown);
const loadBefore = loadavg();
const result = await page.evaluate(async (ms) => {
  const m = window.morphnode, s = m.state;
  const rate = s.header.sampleRate, frameSamples = rate / s.header.fps;
  const mouth = ['A', 'E', 'O', 'S', 'F', 'L'];
  const isOpen = (f) => f.targets.some(([i, v]) => mouth.includes(s.header.targets[i]) && v > 10);
  const says = [], draws = [], outliers = [];
  const sentences = ['Hello there, how are you today?', 'The weather is fine and the sun is out.',
    'I am a face made of a few morph targets.'];
  const t0 = performance.now();
  let k = 0, lastDraw = null;
  while (performance.now() - t0 < ms) {
    const sent = performance.now();
    const shownBefore = s.shown;
    s.events.length = 0;
    m.say(sentences[k++ % sentences.length]);
    let first = null;
    while (performance.now() - sent < 6000) {
      await new Promise((r) => requestAnimationFrame(r));
      // (This runs after the page's own draw of the same animation frame.)
      if (first === null && s.shown !== shownBefore && s.shown.sample !== undefined && isOpen(s.shown)) {
        first = performance.now() - sent;
      }
    }
    // The draws of these 6 s: offsets, and why a frame fell outside R37.
    const recent = s.draws.filter((d) => d.began >= sent && d.sample !== null);
    for (const d of recent) {
      const offset = (d.sample - d.position) / rate * 1000;
      draws.push({ offset, interval: lastDraw === null ? null : d.began - lastDraw });
      lastDraw = d.began;
      if (offset < -40 || offset > 60) {
        // The frame the heard position asked for (the nearest on the frame grid).
        const wanted = Math.round(d.position / frameSamples) * frameSamples;
        const w = s.log.find((f) => Math.abs(f.sample - wanted) < 0.5);
        outliers.push({ offset, interval: draws[draws.length - 1].interval,
          wantedLateMs: w ? w.received - d.began : null, // > 0: not on the main thread at the draw
          wantedWaitMs: w ? w.received - w.arrived : null, // the handover to the main thread
          drawMs: d.ended - d.began });
      }
    }
    // Where the first mouth motion's time went.
    const accepted = s.events.find((e) => e.event === 'accepted' && e.cmd === 'say');
    const started = s.events.find((e) => e.event === 'started' && e.cmd === 'say');
    const say = { first, roundTrip: accepted ? accepted.arrived - sent : null,
      server: started && typeof started.latency_ms === 'number' ? started.latency_ms : null };
    if (started) {
      const startSample = Math.round(started.start * rate);
      // The first draw at or after the speech's start showing an open mouth (a page drawing
      // slower than the frame rate skips frames).
      const bySample = new Map(s.log.map((f) => [f.sample, f]));
      const d = s.draws.find((x) => x.began >= sent && x.sample !== null && x.sample >= startSample - 0.5 &&
        bySample.has(x.sample) && isOpen(bySample.get(x.sample)));
      const open = d && bySample.get(d.sample);
      if (open && d) {
        const half = frameSamples / 2;
        const due = d.began - (d.position - (open.sample - half)) / rate * 1000; // the clock reached it
        Object.assign(say, {
          onset: (open.sample - startSample) / rate * 1000,
          arrived: open.arrived - sent, handover: open.received - open.arrived,
          buffer: due - open.received, drawWait: d.began - due, draw: d.ended - d.began,
          drawn: d.ended - sent });
      }
    }
    says.push(say);
  }
  const ctx = { antialias: s.antialias, renderer: s.renderer };
  return { says, draws, outliers, underruns: s.frameUnderruns, late: s.audioLate, rate,
    jitterMs: s.jitterMs, jitterChanges: s.jitterChanges, ctx };
}, minutes * 60000);
const loadAfter = loadavg();
await context.close();
rmSync(profile, { recursive: true, force: true });
server.kill('SIGTERM');

const q = (a, p) => { const b = a.filter((v) => v !== null && v !== undefined).sort((x, y) => x - y); return b.length ? b[Math.min(b.length - 1, Math.floor(p * b.length))] : NaN; };
const f0 = (v) => (Number.isFinite(v) ? v.toFixed(0) : '-');
const o = result.draws.map((d) => d.offset);
const outside = result.outliers.length;
const says = result.says;
const col = (name) => says.map((x) => x[name]);
const intervals = result.draws.map((d) => d.interval);
console.log(`load average before ${loadBefore.map((v) => v.toFixed(1)).join(' ')}, after ${loadAfter.map((v) => v.toFixed(1)).join(' ')}; ` +
  `draws ${o.length} in ${minutes} min (${(o.length / minutes / 60).toFixed(1)} per s; interval median ${f0(q(intervals, 0.5))} ms, p95 ${f0(q(intervals, 0.95))} ms)`);
console.log(`WebGL renderer: ${result.ctx.renderer || 'a GPU'}; multisampling ${result.ctx.antialias ? 'on' : 'off'}`);
console.log('');
console.log('| minutes | jitter buffer at the end (ms; changes) | frames drawn | A/V offset median / p5 / p95 / min / max (ms) | outside EBU R37 | first mouth motion after say: median / p95 / max (ms) | frame underruns | late sound (ms) |');
console.log('|---:|---|---:|---|---:|---|---:|---:|');
console.log(`| ${minutes} | ${result.jitterMs.toFixed(0)} (${jitter}; ${result.jitterChanges}) | ${o.length} | ` +
  `${q(o, 0.5).toFixed(1)} / ${q(o, 0.05).toFixed(1)} / ${q(o, 0.95).toFixed(1)} / ${Math.min(...o).toFixed(1)} / ${Math.max(...o).toFixed(1)} | ` +
  `${outside} (${(100 * outside / o.length).toFixed(2)} %) | ` +
  `${f0(q(col('drawn'), 0.5))} / ${f0(q(col('drawn'), 0.95))} / ${f0(Math.max(...col('drawn').filter((v) => v != null)))} (${col('drawn').filter((v) => v != null).length} of ${says.length} says) | ` +
  `${result.underruns} | ${(1000 * result.late / result.rate).toFixed(0)} |`);
console.log('');
console.log('Where the first mouth motion goes (ms; median / p95 over the says):');
console.log('');
console.log('| command round trip | server: arrival to speech start | speech onset to the open mouth | open frame at the page (from say) | handover to the main thread | jitter buffer | wait for the animation frame | draw | total to the end of the draw | (the study\'s own check, next animation frame) |');
console.log('|---|---|---|---|---|---|---|---|---|---|');
const mp = (name) => `${f0(q(col(name), 0.5))} / ${f0(q(col(name), 0.95))}`;
console.log(`| ${mp('roundTrip')} | ${mp('server')} | ${mp('onset')} | ${mp('arrived')} | ${mp('handover')} | ${mp('buffer')} | ${mp('drawWait')} | ${mp('draw')} | ${mp('drawn')} | ${mp('first')} |`);
if (outside) {
  const late = result.outliers.filter((x) => x.wantedLateMs !== null && x.wantedLateMs > 0);
  const missing = result.outliers.filter((x) => x.wantedLateMs === null);
  console.log('');
  console.log(`Outside R37: ${outside} draws; the wanted frame never came (not sent) in ${missing.length}; ` +
    `it had not reached the main thread at the draw in ${late.length} ` +
    `(it came ${f0(q(late.map((x) => x.wantedLateMs), 0.5))} ms later, median; its handover from the socket's worker took ${f0(q(late.map((x) => x.wantedWaitMs), 0.5))} ms); ` +
    `draw interval before them median ${f0(q(result.outliers.map((x) => x.interval), 0.5))} ms.`);
  for (const x of result.outliers.slice(0, 20)) {
    console.log(`  offset ${x.offset.toFixed(1)} ms, interval ${f0(x.interval)} ms, wanted frame received ${f0(x.wantedLateMs)} ms after the draw began (handover ${f0(x.wantedWaitMs)}), draw ${f0(x.drawMs)} ms`);
  }
}
