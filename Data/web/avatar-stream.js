// SPDX-License-Identifier: BSD-3-Clause
// The MorphNode avatar stream's browser face (docs/streaming.md): three.js loads the avatar
// file the server prepared, the frames' weights go to every mesh's morph targets by name
// and their rotations to the named nodes, the speech plays in an AudioWorklet, and the
// sound's clock (the AudioContext runs at the stream's rate) decides which frame is shown.
// The page's figures: bytes per second, the audio-visual offset, underruns.
//
// URL parameters: token (remote servers), audio=opus (else pcm16), device=desktop|laptop|
// phone (the avatar prepared for that device: docs/streaming.md), jitter=MS (the jitter
// buffer, default 40: the frames' median margin is kept there, adapt()) or jitter=auto
// (adaptive: all but the latest 2 % of the last 10 s's margins at least 15 ms), withhold
// (the test's negative control: weights are not applied).
//
// The buffer moves only while no sound is queued, so a change never cuts or repeats speech;
// the picture follows the same clock. (On a page drawing in software on a loaded machine
// the adaptive rule grew to 250 ms and cost latency; the fixed 40 ms did better there:
// docs/streaming.md.)
import * as THREE from 'three';
import { GLTFLoader } from '/three/examples/jsm/loaders/GLTFLoader.js';

const params = new URLSearchParams(location.search);
const jitterParam = params.get('jitter') || '40';
const adaptive = jitterParam === 'auto';
const fixedJitterMs = Math.max(0, Math.min(1000, Number(jitterParam) || 40));
let jitterMs = adaptive ? 40 : fixedJitterMs;
const codec = params.get('audio') === 'opus' ? 'opus' : 'pcm16';
const withhold = params.has('withhold');
const still = params.has('still'); // rotations not applied (the tests' mouth pictures)

// ---- the scene ------------------------------------------------------------------------
/// The name of the WebGL renderer when it draws on the CPU (SwiftShader, llvmpipe, ...), else
/// null. Multisampling there made every draw cost twice as much: 80 ms instead of 43 ms a
/// draw at 390 x 844 in Chromium with SwiftShader, and the page's main thread waits for the
/// draw, so frames and the first mouth motion waited too (docs/streaming.md). A GPU
/// multisamples for next to nothing, so only software rendering goes without it
/// (`antialias=0|1` decides instead).
function softwareRenderer() {
  try {
    const probe = document.createElement('canvas').getContext('webgl2') ||
      document.createElement('canvas').getContext('webgl');
    if (!probe) return null;
    const info = probe.getExtension('WEBGL_debug_renderer_info');
    const name = String(probe.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : probe.RENDERER));
    const lose = probe.getExtension('WEBGL_lose_context');
    if (lose) lose.loseContext();
    return /swiftshader|llvmpipe|softpipe|software|microsoft basic render/i.test(name) ? name : null;
  } catch (e) {
    return null;
  }
}
const view = document.getElementById('view');
const figures = document.getElementById('figures');
const software = softwareRenderer();
const antialias = params.has('antialias') ? params.get('antialias') !== '0' : !software;
const renderer = new THREE.WebGLRenderer({ antialias, preserveDrawingBuffer: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x30343a);
const camera = new THREE.PerspectiveCamera(30, 1, 0.01, 100);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 2.0));
const key = new THREE.DirectionalLight(0xffffff, 2.0);
key.position.set(1, 1.5, 2);
scene.add(key);
function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();

// ---- the state the tests read (window.morphnode) ----------------------------------------
const state = {
  header: null, connected: false, closed: false, loaded: false,
  bindings: [],          // per stream target: [{ mesh, index }]
  rotationNodes: [],     // per rotation: an Object3D or null
  rotations: [],         // current quaternion per rotation (as decoded)
  frames: [],            // queued frames, by sample
  log: [],               // the last frames received (for tests): { sample, targets }
  shown: null,           // the frame shown last
  bytes: 0, weightBytes: 0, audioBytes: 0, framesReceived: 0,
  frameUnderruns: 0, audioLate: 0, offsetMs: 0, offsets: [], stops: 0,
  offset: null,          // stream sample = ctx frame + offset
  events: [],
  jitterMs: jitterMs,    // the jitter buffer now
  jitterChanges: 0,
  margins: [],           // adaptive buffer: [arrival ms, margin ms] of recent frames
  soundEnd: 0,           // the stream sample where the queued sound ends
  renderer: software,    // the software renderer's name, or null (a GPU)
  antialias,             // multisampling on
  draws: [],             // the last draws: { sample, position, raf, began, ended }
};
window.morphnode = {
  state,
  send: (cmd) => socket.postMessage({ type: 'send', text: JSON.stringify(cmd) }),
  say: (text) => socket.postMessage({ type: 'send', text: JSON.stringify({ cmd: 'say', text }) }),
  stop: () => socket.postMessage({ type: 'send', text: JSON.stringify({ cmd: 'stop' }) }),
  position: () => position(),
  // The influence a mesh applies for a stream target, read back from three.js.
  influences: () => state.header ? state.header.targets.map((name, k) =>
    state.bindings[k].length ? state.bindings[k][0].mesh.morphTargetInfluences[state.bindings[k][0].index] : null) : [],
  audioLevel: () => { analyser.getFloatTimeDomainData(levelBuffer);
    let s = 0; for (const v of levelBuffer) s += v * v; return Math.sqrt(s / levelBuffer.length); },
  close: () => socket.postMessage({ type: 'close' }),
};

// ---- sound: an AudioContext at the stream's rate, the worklet, a level meter -------------
let audio = null, player = null, analyser = null, levelBuffer = null, opusDecoder = null;
async function startAudio(rate) {
  audio = new AudioContext({ sampleRate: rate, latencyHint: 'interactive' });
  await audio.audioWorklet.addModule('/stream-worklet.js');
  player = new AudioWorkletNode(audio, 'stream-player', { outputChannelCount: [1] });
  analyser = audio.createAnalyser();
  analyser.fftSize = 256;
  levelBuffer = new Float32Array(analyser.fftSize);
  player.connect(analyser);
  analyser.connect(audio.destination);
  // PCM sound and stops come to the player straight from the socket's worker.
  const direct = new MessageChannel();
  player.port.postMessage({ type: 'port', port: direct.port1 }, [direct.port1]);
  socket.postMessage({ type: 'port', port: direct.port2 }, [direct.port2]);
  player.port.onmessage = (e) => {
    if (e.data.type === 'report') {
      state.audioLate = e.data.late;
      // How early the sound arrived (the worklet's least margin since its last report).
      if (e.data.margin !== null && state.offset !== null) {
        state.margins.push([performance.now(), e.data.margin / audio.sampleRate * 1000]);
      }
    }
    // The audio clock's time when the worklet dropped the sound (its next quantum is silent).
    if (e.data.type === 'stopped') state.soundStoppedAt = e.data.frame / audio.sampleRate;
  };
  document.body.addEventListener('click', () => audio.resume(), { once: true });
  if (audio.state !== 'running') audio.resume().catch(() => {});
  if (codec === 'opus') {
    // Decoded in a worker that feeds the worklet directly.
    const channel = new MessageChannel();
    player.port.postMessage({ type: 'port', port: channel.port1 }, [channel.port1]);
    opusDecoder = new Worker('/opus-worker.js');
    opusDecoder.onmessage = (e) => {
      if (e.data.type === 'decoded') state.opusChunks = (state.opusChunks || 0) + 1;
      else console.warn('opus', e.data.message);
    };
    opusDecoder.postMessage({ type: 'init', port: channel.port2, rate }, [channel.port2]);
  }
}
/// The stream sample heard now. The sound device's output timestamp says which context time
/// left the speaker at which moment (performance clock); carried forward to now it is what
/// is heard, with the output latency in it. currentTime alone moves in the device's steps
/// (here 5 to 10 ms, and not at all while the page's thread is held up) and runs ahead of
/// the speaker by baseLatency + outputLatency (here 10 + 32 ms), which it is then given.
function position() {
  if (!audio || state.offset === null) return null;
  let heard = audio.currentTime - (audio.outputLatency || 0) - (audio.baseLatency || 0);
  const stamp = audio.state === 'running' && audio.getOutputTimestamp ? audio.getOutputTimestamp() : null;
  if (stamp && stamp.contextTime > 0 && stamp.performanceTime > 0) {
    // (Never ahead of what the context has made: a stale stamp is carried no further.)
    heard = Math.min(stamp.contextTime + (performance.now() - stamp.performanceTime) / 1000, audio.currentTime);
  }
  return heard * audio.sampleRate + state.offset;
}

// ---- the avatar --------------------------------------------------------------------------
async function loadAvatar(header) {
  const gltf = await new GLTFLoader().loadAsync(header.avatar);
  scene.add(gltf.scene);
  const meshes = [];
  gltf.scene.traverse((o) => { if (o.isMesh && o.morphTargetDictionary) meshes.push(o); });
  state.bindings = header.targets.map((name) => meshes
    .filter((m) => name in m.morphTargetDictionary)
    .map((m) => ({ mesh: m, index: m.morphTargetDictionary[name] })));
  state.rotationNodes = header.rotations.map((name) =>
    gltf.scene.getObjectByName(THREE.PropertyBinding.sanitizeNodeName(name)) || null);
  // Frame the face.
  const box = new THREE.Box3().setFromObject(gltf.scene);
  const size = box.getSize(new THREE.Vector3()), center = box.getCenter(new THREE.Vector3());
  const distance = 1.15 * Math.max(size.y, size.x / Math.max(camera.aspect, 0.3)) / (2 * Math.tan(Math.PI * camera.fov / 360));
  camera.position.set(center.x, center.y, center.z + size.z / 2 + distance);
  camera.near = distance / 50; camera.far = distance * 10;
  camera.lookAt(center);
  camera.updateProjectionMatrix();
  state.loaded = true;
}

function applyFrame(frame) {
  if (!withhold) {
    for (const binding of state.bindings) for (const b of binding) b.mesh.morphTargetInfluences[b.index] = 0;
    for (const [k, w] of frame.targets) for (const b of state.bindings[k]) b.mesh.morphTargetInfluences[b.index] = w / 255;
  }
  if (!still) frame.rotations.forEach((q, r) => {
    const node = state.rotationNodes[r];
    if (node && q) node.quaternion.set(q[0], q[1], q[2], q[3]);
  });
  state.shown = frame;
}

// ---- the stream --------------------------------------------------------------------------
function decode(buffer) {
  const v = new DataView(buffer);
  const type = v.getUint8(0);
  if (type === 1) {
    const sample = v.getUint32(1, true), n = v.getUint8(5);
    const targets = [];
    let p = 6;
    for (let i = 0; i < n; ++i, p += 2) targets.push([v.getUint8(p), v.getUint8(p + 1)]);
    const mask = v.getUint8(p++);
    for (let r = 0; r < 8; ++r) {
      if (!(mask & (1 << r))) continue;
      const x = v.getInt16(p, true) / 32767, y = v.getInt16(p + 2, true) / 32767, z = v.getInt16(p + 4, true) / 32767;
      p += 6;
      state.rotations[r] = [x, y, z, Math.sqrt(Math.max(0, 1 - x * x - y * y - z * z))];
    }
    return { type, sample, targets, rotations: state.rotations.slice() };
  }
  if (type === 2) {
    return { type, codec: v.getUint8(1), sample: v.getUint32(2, true), frames: v.getUint16(6, true),
      payload: new Uint8Array(buffer, 8) };
  }
  if (type === 3) return { type, sample: v.getUint32(1, true) };
  return null;
}

function onFrame(f) {
  state.framesReceived++;
  if (state.offset === null && audio && audio.state === 'running' && audio.currentTime > 0) {
    // The jitter buffer: this frame is shown jitterMs from now, on the sound's clock (once it
    // runs: a clock that has not started would put the picture behind by its start-up).
    state.offset = f.sample - audio.currentTime * audio.sampleRate - jitterMs / 1000 * audio.sampleRate;
    state.offset = Math.round(state.offset);
    player.port.postMessage({ type: 'offset', offset: state.offset });
  }
  state.newestSample = f.sample;
  state.frames.push(f);
  state.log.push({ sample: f.sample, targets: f.targets, arrived: f.arrived, received: f.received });
  if (state.log.length > 900) state.log.splice(0, state.log.length - 600);
}

/// The jitter buffer (see the top of the file). The margins of the last 10 s are kept: at
/// every draw, how far the newest frame at hand is ahead of the heard position (the frame
/// for now must be there when the page draws), and how early the sound came to the player
/// (reported by the worklet); the clock is moved so that they are what the buffer asks:
/// adaptive, all but the latest 2 % at least 15 ms early (the buffer then is the typical
/// margin, at most 250 ms); fixed, the median margin equal to the buffer. Moving it also
/// undoes what the clock lost before it ran (the context starting late) and a stop's jump.
/// Only while no sound is queued.
function adapt(now) {
  const t = performance.now();
  while (state.margins.length && t - state.margins[0][0] > 10000) state.margins.shift();
  if (state.margins.length < 30) return;
  const sorted = state.margins.map((m) => m[1]).sort((a, b) => a - b);
  const low = sorted[Math.floor(0.02 * sorted.length)], median = sorted[sorted.length >> 1];
  // shift > 0: the heard position jumps ahead (less buffer); < 0: it falls back.
  let shift = adaptive ? Math.min(low - 15, median - 20) : median - fixedJitterMs;
  if (adaptive && median - shift > 250) shift = median - 250;
  state.jitterMs = jitterMs = median;
  // Less buffer only by 20 ms or more (no dithering); more at once; never while speaking.
  if ((shift > 0 ? shift < 20 : shift > -10) || now < state.soundEnd) return;
  // After a stop's jump the buffer comes back a second later: the mouth closes first.
  if (shift < 0 && performance.now() - (state.stopArrived || -1e9) < 1000) return;
  state.offset += Math.round(shift / 1000 * audio.sampleRate);
  player.port.postMessage({ type: 'offset', offset: state.offset });
  for (const m of state.margins) m[1] -= shift;
  state.jitterMs = jitterMs = median - shift;
  state.jitterChanges++;
}

function onAudio(a) {
  state.soundEnd = Math.max(state.soundEnd, a.sample + a.frames);
  if (a.codec === 0) {
    // (PCM goes from the socket's worker to the player directly: stream-socket.js.)
  } else if (opusDecoder) {
    const payload = a.payload.slice();
    opusDecoder.postMessage({ type: 'packet', sample: a.sample, payload }, [payload.buffer]);
  }
}

function onStop(s) {
  state.stops++;
  state.stopArrived = performance.now();
  state.stopArrivedAudio = audio.currentTime;
  state.stopSample = s.sample;
  // (The worker told the player first, in order with the sound: stream-socket.js.)
  // The same jump on the picture's side: what was queued before the stop is skipped.
  // The buffer is gone after the jump; adapt() restores it once silent (the stop's sample on).
  const now = position();
  if (now !== null && s.sample > now) {
    const jump = s.sample - now;
    state.offset += jump;
    for (const m of state.margins) m[1] -= jump / audio.sampleRate * 1000;
  }
  state.soundEnd = s.sample;
  state.frames = state.frames.filter((f) => f.sample >= s.sample);
}

const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/stream?audio=${codec}` +
  (params.get('token') ? `&token=${encodeURIComponent(params.get('token'))}` : '') +
  (params.get('seed') ? `&seed=${encodeURIComponent(params.get('seed'))}` : '') +
  (params.get('device') ? `&device=${encodeURIComponent(params.get('device'))}` : '');
const socket = new Worker('/stream-socket.js');
socket.onmessage = async (e) => {
  const w = e.data;
  if (w.type === 'open') { state.connected = true; return; }
  if (w.type === 'close') { state.closed = true; state.connected = false; if (audio) audio.suspend(); return; }
  if (w.type === 'audio') {
    state.bytes += w.bytes; state.audioBytes += w.bytes;
    state.soundEnd = Math.max(state.soundEnd, w.sample + w.frames);
    return;
  }
  if (w.type === 'text') {
    state.bytes += w.data.length;
    const m = JSON.parse(w.data);
    if (m.type === 'header') {
      state.header = m;
      await startAudio(m.sampleRate);
      await loadAvatar(m);
    } else {
      m.arrived = w.at - performance.timeOrigin;
      state.events.push(m);
      if (state.events.length > 200) state.events.shift();
    }
    return;
  }
  state.bytes += w.data.byteLength;
  if (!player) return;
  const m = decode(w.data);
  if (!m) return;
  if (m.type === 1) {
    state.weightBytes += w.data.byteLength;
    m.arrived = w.at - performance.timeOrigin; // at the socket's worker (page time)
    m.received = performance.now();            // on the page's main thread
    onFrame(m);
  }
  else if (m.type === 2) { state.audioBytes += w.data.byteLength; onAudio(m); }
  else if (m.type === 3) onStop(m);
};
socket.postMessage({ type: 'open', url });

// ---- the loop: the frame the sound's clock asks for ------------------------------------
let lastFigures = performance.now(), lastBytes = 0, lastWeightBytes = 0, rate = 0, weightRate = 0;
function tick(rafTime) {
  requestAnimationFrame(tick);
  const began = performance.now();
  const now = position();
  let drawn = null;
  if (state.loaded && now !== null) {
    if (state.newestSample !== undefined) {
      state.margins.push([performance.now(), (state.newestSample - now) / audio.sampleRate * 1000]);
      adapt(now);
    }
    // The frame nearest to what is heard (a frame is due from half a frame before its sample).
    const half = 0.5 * audio.sampleRate / state.header.fps;
    let next = null;
    while (state.frames.length && state.frames[0].sample <= now + half) next = state.frames.shift();
    if (next) {
      applyFrame(next);
      drawn = next;
      const offset = (next.sample - now) / audio.sampleRate * 1000; // picture minus sound
      state.offsetMs = offset;
      state.offsets.push(offset);
      if (state.offsets.length > 10000) state.offsets.splice(0, 5000);
    } else if (state.shown && now - state.shown.sample > 2 * audio.sampleRate / state.header.fps) {
      state.frameUnderruns++; // the frame for now has not come
    }
  }
  renderer.render(scene, camera);
  const t = performance.now();
  // The draws' timeline (the sync study reads it): the frame's sample, the position heard
  // when it was chosen, the animation frame's time, when this draw began and ended.
  state.draws.push({ sample: drawn ? drawn.sample : null, position: now, raf: rafTime, began, ended: t });
  if (state.draws.length > 3000) state.draws.splice(0, 1000);
  if (t - lastFigures >= 1000) {
    const s = (t - lastFigures) / 1000;
    rate = (state.bytes - lastBytes) / s; weightRate = (state.weightBytes - lastWeightBytes) / s;
    lastBytes = state.bytes; lastWeightBytes = state.weightBytes; lastFigures = t;
    figures.textContent =
      `${state.closed ? 'disconnected' : state.connected ? 'connected' : 'connecting...'}` +
      `\n${(rate / 1024).toFixed(1)} KB/s, weights ${weightRate.toFixed(0)} B/s` +
      `\nA/V offset ${state.offsetMs.toFixed(0)} ms (jitter buffer ${jitterMs.toFixed(0)} ms${adaptive ? ', adaptive' : ''})` +
      `\nunderruns: frames ${state.frameUnderruns}, sound ${(state.audioLate / (audio ? audio.sampleRate : 1) * 1000).toFixed(0)} ms` +
      (withhold ? '\nweights withheld' : '');
  }
}
requestAnimationFrame(tick);

// ---- controls ----------------------------------------------------------------------------
document.getElementById('say').onclick = () => { if (audio) audio.resume(); window.morphnode.say(document.getElementById('text').value); };
document.getElementById('stop').onclick = () => window.morphnode.stop();
document.getElementById('happy').onclick = () => window.morphnode.send({ cmd: 'mood', name: 'happy', intensity: 0.8 });
document.getElementById('look').onclick = () => window.morphnode.send({ cmd: 'look_at', yaw: 25, pitch: 0, duration: 2 });
