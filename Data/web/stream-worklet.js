// SPDX-License-Identifier: BSD-3-Clause
// The stream's sound player (an AudioWorklet, docs/streaming.md). The AudioContext runs at
// the stream's sample rate, so one output frame is one sample of the stream's clock:
// stream sample = currentFrame + offset. The main thread sets the offset once (the jitter
// buffer) and moves it on a stop; chunks are written where their samples fall.
class StreamPlayer extends AudioWorkletProcessor {
  constructor() {
    super();
    this.offset = null;   // stream sample - currentFrame; null until the first frame
    this.chunks = [];     // { sample, data: Float32Array }, sorted by sample
    this.late = 0;        // samples that arrived after they were due
    this.played = 0;      // audible samples played
    this.margin = null;   // the least margin of the chunks since the last report
    const receive = (e) => {
      const m = e.data;
      if (m.type === 'port') { m.port.onmessage = receive; return; } // the Opus worker's
      if (m.type === 'offset') {
        this.offset = m.offset;
      } else if (m.type === 'chunk') {
        if (this.offset !== null) {
          // How early it came (samples before its first sample is due; < 0: late).
          const margin = m.sample - (currentFrame + this.offset);
          this.margin = this.margin === null ? margin : Math.min(this.margin, margin);
        }
        this.chunks.push({ sample: m.sample, data: m.data });
        this.chunks.sort((a, b) => a.sample - b.sample);
      } else if (m.type === 'stop') {
        // Everything queued is void at once; the clock jumps to the stop's sample if
        // that is ahead of what plays now.
        this.chunks = [];
        this.port.postMessage({ type: 'stopped', frame: currentFrame });
        if (this.offset !== null) {
          const now = currentFrame + this.offset;
          if (m.sample > now) this.offset += m.sample - now;
        }
      }
    };
    this.port.onmessage = receive;
    this.lastReport = 0;
  }
  process(inputs, outputs) {
    const out = outputs[0][0];
    out.fill(0);
    if (this.offset === null) return true;
    const start = currentFrame + this.offset;
    const end = start + out.length;
    let keep = 0;
    for (const c of this.chunks) {
      const cEnd = c.sample + c.data.length;
      if (cEnd <= start) { // played, or came after its time had passed
        if (!c.counted) this.late += c.data.length;
        continue;
      }
      if (c.sample >= end) { this.chunks[keep++] = c; continue; } // not yet due
      if (c.sample < start && !c.counted) {
        this.late += Math.min(start, cEnd) - c.sample; // came too late for its start
        c.counted = true;
      }
      const from = Math.max(start, c.sample), to = Math.min(end, cEnd);
      for (let s = from; s < to; ++s) {
        const v = c.data[s - c.sample];
        out[s - start] += v;
        if (v > 0.01 || v < -0.01) this.played++;
      }
      c.counted = true;
      this.chunks[keep++] = c;
    }
    this.chunks.length = keep;
    if (currentFrame - this.lastReport >= 1024) {
      this.lastReport = currentFrame;
      let peak = 0;
      for (const v of out) peak = Math.max(peak, Math.abs(v));
      this.port.postMessage({ type: 'report', frame: currentFrame, position: start,
        queued: this.chunks.reduce((n, c) => n + c.data.length, 0), late: this.late,
        played: this.played, peak, margin: this.margin });
      this.margin = null;
    }
    return true;
  }
}
registerProcessor('stream-player', StreamPlayer);
