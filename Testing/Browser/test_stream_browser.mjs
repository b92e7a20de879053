// SPDX-License-Identifier: BSD-3-Clause
// The avatar stream in a real browser (docs/streaming.md): Debian's chromium driven by
// playwright-core against `MorphAvatar --serve`, at a phone-sized viewport.
//   1. the page connects, loads the avatar, shows frames on the sound's clock;
//   2. `say` opens the mouth: the mouth region of the picture changes by more than
//      MOUTH_PIXELS pixels; the negative control (?withhold: the same stream, weights not
//      applied) stays below it;
//   3. the weights three.js holds (morphTargetInfluences) are those of the frame shown;
//   4. `stop` silences sound and mouth within 100 ms;
//   5. bad messages get error events and the session goes on; an oversized one ends that
//      session only; a dropped connection ends its session on the server, which serves on.
// Exit 0: passed; 1: failed; 77: skipped (no chromium / playwright-core, unless CI=true; a
// build without speech synthesis).
// Env: MORPHAVATAR (the binary), NPM_TOOLS (.ci/npm-tools), CHROMIUM (/usr/bin/chromium),
// SCREENSHOT_DIR (optional: where the phone screenshot goes).
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

const SKIP = 77;
const ci = process.env.CI === 'true';
const chromiumPath = process.env.CHROMIUM || '/usr/bin/chromium';
const npmTools = resolve(process.env.NPM_TOOLS || '.ci/npm-tools');
function skip(why) {
  if (ci) { console.error(`FAIL (CI=true): ${why}`); process.exit(1); }
  console.log(`SKIP: ${why}`); process.exit(SKIP);
}
if (process.env.MORPHNODE_HAVE_SPEECH === '0') {
  console.log('SKIP: built without eSpeak NG (MORPHNODE_ENABLE_ESPEAK=OFF): the avatar cannot speak');
  process.exit(SKIP);
}
if (!existsSync(chromiumPath)) skip(`no chromium at ${chromiumPath} (Debian package chromium)`);
let chromium;
try {
  ({ chromium } = createRequire(join(npmTools, 'node_modules', 'x.js'))('playwright-core'));
} catch (e) {
  skip(`playwright-core is not in ${npmTools} (.ci/install-npm-tools.sh)`);
}
if (!existsSync(join(npmTools, 'node_modules', 'three', 'build', 'three.module.js'))) {
  skip(`three is not in ${npmTools} (.ci/install-npm-tools.sh)`);
}

let failures = 0;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures++;
}

// ---- the server --------------------------------------------------------------------------
const server = spawn(process.env.MORPHAVATAR, ['--serve', '127.0.0.1:0', '--exit-after', '120'],
  { stdio: ['ignore', 'pipe', 'pipe'] });
let serverLog = '';
const address = await new Promise((resolve, reject) => {
  const timer = setTimeout(() => reject(new Error(`no address from the server:\n${serverLog}`)), 30000);
  server.stderr.on('data', (d) => {
    serverLog += d;
    const m = /on (http:\/\/[0-9.]+:\d+)\//.exec(serverLog);
    if (m) { clearTimeout(timer); resolve(m[1]); }
  });
  server.on('exit', (code) => reject(new Error(`server exited (${code}):\n${serverLog}`)));
});
console.log(`server ${address}`);
const status = async () => (await fetch(`${address}/status`)).json();

const profile = mkdtempSync(join(tmpdir(), 'morphnode-chromium-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: chromiumPath,
  headless: true,
  args: ['--headless', '--no-sandbox', '--enable-unsafe-swiftshader', '--disable-gpu',
    '--disable-background-networking', '--disable-component-update', '--no-first-run',
    '--autoplay-policy=no-user-gesture-required'],
  viewport: { width: 390, height: 844 }, // a phone
  deviceScaleFactor: 1,
});

async function open(query = '') {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e}`));
  await page.goto(`${address}/${query}`);
  await page.waitForFunction(() => window.morphnode && window.morphnode.state.loaded &&
    window.morphnode.state.shown !== null, null, { timeout: 30000 });
  return page;
}

/// The mouth region (the lower middle of the canvas) and the widest mouth weight of the
/// frame it shows, read in one task (the canvas holds the render of state.shown). `idle`
/// keeps the region as the reference; otherwise returns how many of its pixels differ from
/// the reference by more than 24 levels (counted in the page: no pixels cross the wire).
async function capture(page, idle) {
  return page.evaluate(([names, keep]) => {
    const s = window.morphnode.state;
    let open = 0;
    if (s.shown) for (const [k, v] of s.shown.targets) if (names.includes(s.header.targets[k])) open = Math.max(open, v);
    const src = document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    c.getContext('2d').drawImage(src, 0, 0);
    const x0 = Math.floor(c.width * 0.3), y0 = Math.floor(c.height * 0.5);
    const w = Math.floor(c.width * 0.4), h = Math.floor(c.height * 0.3);
    const px = c.getContext('2d').getImageData(x0, y0, w, h).data;
    if (keep) { window.__mouthReference = px; return { open, changed: 0 }; }
    const a = window.__mouthReference;
    let n = 0;
    for (let i = 0; i < a.length; i += 4) {
      if (Math.abs(a[i] - px[i]) + Math.abs(a[i + 1] - px[i + 1]) + Math.abs(a[i + 2] - px[i + 2]) > 24) n++;
    }
    return { open, changed: n };
  }, [['A', 'E', 'O', 'jawOpen'], idle]);
}
const mouthTargets = ['A', 'E', 'O', 'S', 'F', 'L', 'jawOpen'];
/// Says a sentence and returns the mouth's pixel change at the widest opening seen.
async function mouthChange(page) {
  await capture(page, true);
  await page.evaluate(() => window.morphnode.say('Ah, what a wonderful large apple, Anna.'));
  let best = 0, widest = 0;
  for (let i = 0; i < 40; ++i) {
    await page.waitForTimeout(50);
    const now = await capture(page, false);
    if (now.open > widest) {
      widest = now.open;
      best = now.changed;
    }
  }
  await page.evaluate(() => window.morphnode.stop());
  return { pixels: best, widest };
}

try {
  // 1 + 2: the mouth opens; the control does not.
  const page = await open();
  const st = await page.evaluate(() => ({ targets: window.morphnode.state.header.targets,
    rotations: window.morphnode.state.header.rotations, frames: window.morphnode.state.framesReceived }));
  check(st.targets.length > 0 && st.frames > 0, `connected: ${st.targets.length} targets, ${st.rotations.length} rotations, frames arriving`);
  const still = await open('?still');
  const spoken = await mouthChange(still);
  await still.close();
  const control = await open('?withhold&still');
  const withheld = await mouthChange(control);
  // With the head held still (?still), an open mouth changes ~20000 pixels of the region.
  const MOUTH_PIXELS = 3000;
  check(spoken.widest > 100 && spoken.pixels > MOUTH_PIXELS,
    `say opens the mouth: ${spoken.pixels} mouth pixels changed (weight ${spoken.widest}/255; > ${MOUTH_PIXELS})`);
  check(withheld.pixels < MOUTH_PIXELS,
    `negative control (weights withheld): ${withheld.pixels} mouth pixels changed (< ${MOUTH_PIXELS})`);
  await control.close();

  // 3: three.js holds the weights of the frame shown, for every target.
  await page.evaluate(() => window.morphnode.say('Hello there, how are you today?'));
  let worst = 0, compared = 0;
  for (let i = 0; i < 20; ++i) {
    await page.waitForTimeout(40);
    const r = await page.evaluate(() => {
      const s = window.morphnode.state;
      const inf = window.morphnode.influences();
      const want = new Array(inf.length).fill(0);
      for (const [k, w] of s.shown.targets) want[k] = w / 255;
      const sent = s.log.some((f) => f.sample === s.shown.sample);
      return { inf, want, sent };
    });
    for (let k = 0; k < r.want.length; ++k) {
      if (r.inf[k] !== null) { worst = Math.max(worst, Math.abs(r.inf[k] - r.want[k])); compared++; }
    }
    if (!r.sent) worst = Infinity;
  }
  check(compared > 0 && worst < 1e-6, `morphTargetInfluences equal the frames received (${compared} values, largest difference ${worst})`);

  // 4: stop silences sound and mouth within 100 ms (mid-sentence).
  await page.evaluate(() => window.morphnode.say('Ah, what a wonderful large apple, Anna. And a banana, too.'));
  await page.waitForFunction((names) => {
    const s = window.morphnode.state;
    return s.shown && s.shown.targets.some(([k, v]) => names.includes(s.header.targets[k]) && v > 60) &&
      window.morphnode.audioLevel() > 0.002;
  }, mouthTargets, { timeout: 5000 }).catch(() => {});
  const stop = await page.evaluate(async (names) => {
    const m = window.morphnode, s = m.state;
    const mouth = () => {
      let w = 0;
      if (s.shown) for (const [k, v] of s.shown.targets) if (names.includes(s.header.targets[k])) w = Math.max(w, v);
      return w;
    };
    const before = { level: m.audioLevel(), mouth: mouth() };
    const t0 = performance.now();
    s.stopArrived = null;
    m.stop();
    let silent = null, closed = null;
    while (performance.now() - t0 < 800) {
      await new Promise((r) => setTimeout(r, 5));
      if (s.stopArrived === null) continue;
      const t = performance.now() - s.stopArrived;
      if (silent === null && m.audioLevel() < 0.002) silent = t;
      if (closed === null && mouth() <= 0.25 * before.mouth) closed = t;
    }
    // The mouth on the stream's clock: the widest mouth weight at the stop's sample and in the
    // first frame 100 ms after it.
    const rate = s.header.sampleRate;
    // (at stop: the widest mouth of the half second before it, as a phoneme may be closed
    // at the very moment)
    const spoken = s.log.filter((f) => f.sample <= s.stopSample && f.sample > s.stopSample - 0.5 * rate);
    const later = s.log.find((f) => f.sample >= s.stopSample + 0.1 * rate);
    const widest = (f) => f ? Math.max(0, ...f.targets.filter(([k]) => names.includes(s.header.targets[k])).map(([, v]) => v)) : null;
    const mouthAt = spoken.length ? Math.max(...spoken.map(widest)) : null, mouthLater = widest(later);
    const worklet = s.soundStoppedAt !== undefined ? 1000 * (s.soundStoppedAt - s.stopArrivedAudio) : null;
    return { before, silent, closed, worklet, mouthAt, mouthLater, arrived: s.stopArrived - t0 };
  }, mouthTargets);
  check(stop.before.level > 0.002,
    `speaking before stop: sound level ${stop.before.level.toFixed(4)}, mouth ${stop.before.mouth}/255`);
  // Measured from the stop message's arrival at the page (the page's and the stream's part);
  // the way there (page -> server -> page) is printed beside it.
  console.log(`     (the stop message came back ${stop.arrived.toFixed(0)} ms after the page sent stop; ` +
    `meter silent ${stop.silent === null ? '-' : stop.silent.toFixed(0)} ms after it came)`);
  check(stop.worklet !== null && stop.worklet <= 100, `stop silences the sound ${stop.worklet === null ? '-' : stop.worklet.toFixed(0)} ms after it arrives (the worklet drops it; <= 100)`);
  // The mouth 100 ms after the stop on the stream's clock (the behaviour fades it out over
  // LiveBehavior::StopFade, 120 ms); the wall-clock time the page took is printed.
  check(stop.mouthAt !== null && stop.mouthLater !== null && stop.mouthLater <= Math.max(8, 0.25 * stop.mouthAt),
    `100 ms after stop the mouth weighs ${stop.mouthLater}/255 (widest in the 0.5 s before stop ${stop.mouthAt}; <= a quarter of it); ` +
    `the page showed a quarter ${stop.closed === null ? '-' : stop.closed.toFixed(0)} ms after the stop arrived`);

  // The phone-sized screenshot for docs/streaming.md.
  if (process.env.SCREENSHOT_DIR) {
    await page.evaluate(() => window.morphnode.say('Ah, hello! I am an avatar made of morph targets.'));
    await page.waitForFunction(() => {
      const s = window.morphnode.state;
      return s.shown && s.shown.targets.some(([k, v]) => ['A', 'O'].includes(s.header.targets[k]) && v > 150);
    }, null, { timeout: 4000, polling: 'raf' }).catch(() => {});
    await page.screenshot({ path: join(process.env.SCREENSHOT_DIR, 'streaming_phone.png') });
  }

  // 5: bad input harms nobody else; a dropped connection ends its session.
  const other = await open();
  const framesBefore = await page.evaluate(() => window.morphnode.state.framesReceived);
  const errors = await other.evaluate(async () => {
    const s = window.morphnode.state;
    window.morphnode.send({ cmd: 'quit' });
    window.morphnode.send({ cmd: 'dance' });
    window.morphnode.send({ cmd: 'say', text: 5 });
    for (let i = 0; i < 100 && s.events.filter((e) => e.event === 'error').length < 3; ++i) {
      await new Promise((r) => setTimeout(r, 30));
    }
    return s.events.filter((e) => e.event === 'error').map((e) => e.reason);
  });
  check(errors.length >= 3, `bad commands get error events (${errors.join(', ')}); the session goes on`);
  await other.evaluate(() => window.morphnode.send({ cmd: 'say', text: 'x'.repeat(70000) }));
  await other.waitForFunction(() => window.morphnode.state.closed, null, { timeout: 5000 })
    .then(() => check(true, 'an oversized message closes that session'))
    .catch(() => check(false, 'an oversized message closes that session'));
  await page.waitForTimeout(300);
  const framesAfter = await page.evaluate(() => window.morphnode.state.framesReceived);
  check(framesAfter > framesBefore + 5, `the other session goes on (${framesAfter - framesBefore} frames meanwhile)`);
  await other.close();
  const before = await status();
  await page.close();
  let after = before;
  for (let i = 0; i < 40 && after.sessions > 0; ++i) {
    await new Promise((r) => setTimeout(r, 50));
    after = await status();
  }
  check(before.sessions >= 1 && after.sessions === 0, `a dropped connection ends its session (sessions ${before.sessions} -> ${after.sessions})`);
  // Opus when the page asks: the page decodes it (WebCodecs) and plays it.
  const opus = await open('?audio=opus');
  const heard = await opus.evaluate(async () => {
    const m = window.morphnode;
    m.say('Hello there, this sound travels as Opus packets.');
    let level = 0;
    for (let i = 0; i < 60; ++i) {
      await new Promise((r) => setTimeout(r, 50));
      level = Math.max(level, m.audioLevel());
    }
    return { level, chunks: m.state.opusChunks || 0, codec: m.state.header.codec };
  });
  check(heard.codec === 'opus' && heard.chunks > 10 && heard.level > 0.002,
    `?audio=opus: ${heard.chunks} Opus packets decoded, sound level ${heard.level.toFixed(4)}`);
  await opus.close();
  const again = await open();
  check(await again.evaluate(() => window.morphnode.state.framesReceived > 0), 'the server serves a new session afterwards');
  // A phone's avatar: the page asks for the profile, the server sends the file prepared for
  // it (the level-of-detail ladder's level 1 when built with the reduction), the same targets.
  const triangles = (page) => page.evaluate(() => {
    const meshes = new Set();
    for (const b of window.morphnode.state.bindings) for (const x of b) meshes.add(x.mesh);
    let n = 0;
    for (const m of meshes) n += m.geometry.index ? m.geometry.index.count / 3 : m.geometry.attributes.position.count / 3;
    return { n, avatar: window.morphnode.state.header.avatar, targets: window.morphnode.state.header.targets.join(',') };
  });
  const phone = await open('?device=phone');
  const [full, small] = [await triangles(again), await triangles(phone)];
  const spoke = await phone.evaluate(async () => {
    const m = window.morphnode, s = m.state;
    const from = s.log.length;
    m.say('Hello from a phone.');
    for (let i = 0; i < 60; ++i) {
      await new Promise((r) => setTimeout(r, 50));
      if (s.log.slice(from).some((f) => f.targets.some(([k, v]) => ['A', 'E', 'O'].includes(s.header.targets[k]) && v > 100))) return true;
    }
    return false;
  });
  // (A build without the reduction serves the phone the full mesh; the server says which level.)
  const level = (/for a phone: .*\(level (\d+)\)/.exec(serverLog) || [])[1];
  check(small.avatar === '/avatar-phone.glb' && small.targets === full.targets && spoke &&
    (level === '0' ? small.n === full.n : level === '1' && small.n < 0.8 * full.n),
    `?device=phone: ${small.avatar}, level ${level}, ${small.n} triangles (full: ${full.n}), same targets, the mouth opens`);
  await phone.close();
  await again.close();
} catch (e) {
  console.log(`FAIL ${e.stack || e}`);
  failures++;
} finally {
  await context.close();
  rmSync(profile, { recursive: true, force: true });
  server.kill('SIGTERM');
  await new Promise((r) => server.on('exit', r));
  console.log(serverLog.trim().split('\n').slice(-1)[0]);
}
process.exit(failures ? 1 : 0);
