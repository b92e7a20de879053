// SPDX-License-Identifier: BSD-3-Clause
// The stream's WebSocket, off the page's main thread (docs/streaming.md): a page that draws
// slowly (software WebGL) holds its main thread for a whole draw, and sound that waits for
// it arrives late. Here PCM sound and stops go straight to the sound player (the
// AudioWorklet, through a MessagePort, in the order they came); frames, Opus packets and
// text go to the page.
let ws = null, player = null;

// `at`: when the message arrived, as an absolute time (performance.timeOrigin + now), so the
// page can tell how long it waited for the page's main thread (the study's timeline).
const stamp = () => performance.timeOrigin + performance.now();
function toPage(data, transfer) { postMessage(data, transfer || []); }

onmessage = (e) => {
  const m = e.data;
  if (m.type === 'open') {
    ws = new WebSocket(m.url);
    ws.binaryType = 'arraybuffer';
    ws.onopen = () => toPage({ type: 'open' });
    ws.onclose = () => toPage({ type: 'close' });
    ws.onmessage = (ev) => {
      if (typeof ev.data === 'string') { toPage({ type: 'text', data: ev.data, at: stamp() }); return; }
      const buffer = ev.data;
      if (buffer.byteLength < 1) return;
      const v = new DataView(buffer);
      const kind = v.getUint8(0);
      if (player && kind === 2 && buffer.byteLength >= 8 && v.getUint8(1) === 0) {
        // PCM 16: decoded here and handed to the player at once.
        const sample = v.getUint32(2, true), frames = v.getUint16(6, true);
        if (buffer.byteLength < 8 + 2 * frames) return;
        const pcm = new Float32Array(frames);
        for (let i = 0; i < frames; ++i) pcm[i] = v.getInt16(8 + 2 * i, true) / 32768;
        player.postMessage({ type: 'chunk', sample, data: pcm }, [pcm.buffer]);
        toPage({ type: 'audio', bytes: buffer.byteLength, sample, frames });
        return;
      }
      if (player && kind === 3 && buffer.byteLength >= 5) {
        player.postMessage({ type: 'stop', sample: v.getUint32(1, true) }); // before any later chunk
      }
      toPage({ type: 'binary', data: buffer, played: player !== null, at: stamp() }, [buffer]);
    };
  } else if (m.type === 'port') {
    player = m.port;
  } else if (m.type === 'send') {
    if (ws && ws.readyState === WebSocket.OPEN) ws.send(m.text);
  } else if (m.type === 'close') {
    if (ws) ws.close();
  }
};
