// SPDX-License-Identifier: BSD-3-Clause
// Opus decoding for the stream's page (docs/streaming.md), off the main thread: packets come
// from the page, WebCodecs decodes them here, and the sound goes straight to the player
// worklet through a MessagePort, so a busy main thread (rendering) never delays it.
let decoder = null, port = null, rate = 24000;
onmessage = (e) => {
  const m = e.data;
  if (m.type === 'init') {
    port = m.port;
    rate = m.rate;
    decoder = new AudioDecoder({
      output: (data) => {
        const decoded = new Float32Array(data.numberOfFrames);
        data.copyTo(decoded, { planeIndex: 0, format: 'f32-planar' });
        // Decoders may give 48 kHz whatever the stream's rate: back to the stream's clock
        // (linear interpolation; speech has little above 8 kHz).
        let pcm = decoded;
        if (data.sampleRate !== rate) {
          const n = Math.round(decoded.length * rate / data.sampleRate);
          pcm = new Float32Array(n);
          for (let i = 0; i < n; ++i) {
            const x = i * data.sampleRate / rate, k = Math.floor(x), f = x - k;
            pcm[i] = (decoded[k] || 0) * (1 - f) + (decoded[k + 1] || 0) * f;
          }
        }
        // WebCodecs timestamps are microseconds (the decoder counts them on): to samples.
        const sample = Math.round(data.timestamp * rate / 1e6);
        data.close();
        port.postMessage({ type: 'chunk', sample, data: pcm }, [pcm.buffer]);
        postMessage({ type: 'decoded', sample });
      },
      error: (err) => postMessage({ type: 'error', message: String(err) }),
    });
    decoder.configure({ codec: 'opus', sampleRate: rate, numberOfChannels: 1 });
  } else if (m.type === 'packet' && decoder) {
    decoder.decode(new EncodedAudioChunk({ type: 'key', timestamp: m.sample * 1e6 / rate, data: m.payload }));
  }
};
