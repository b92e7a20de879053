#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Latency of the live avatar's say command (docs/dialog.md): from the command's arrival to
the first mouth motion on the screen and to the first sound, over N say commands of varied
length, sent one at a time to a headless MorphAvatar (real-time loop, offscreen rendering)
by the example client (Examples/Python/dialog_client.py).

- mouth: the avatar's `latency_ms` of the `started` event: wall-clock time from the arrival
  of the command's last byte to the end of rendering the first frame whose time is at or
  after the utterance's first mouth motion (`start`);
- sound: when the avatar's clock reaches the first audible sample (`sound`), from the same
  arrival: latency_ms + (sound - time of that frame). The avatar plays the sound and its
  clock is the sound's (give or take the device's 23 ms buffer); on a machine without a
  sound device (SDL's dummy driver) the clock is the steady one;
- round trip: the client's wall time from sending the line to reading `started`;
- accepted: the client's wall time from sending the line to reading `accepted` (the command
  parsed and scheduled: for a say, the synthesis of its first chunk).

Each say is stopped once started (so none waits behind another) and the next one is sent
after a pause. Figures: median and 95th percentile, all and per text length.

  xvfb-run -a python3 Testing/Benchmarks/study_dialog_latency.py build/bin/MorphAvatar \
      [--commands 100] [--markdown FILE] [--quick]
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Examples", "Python"))
from dialog_client import AvatarClient  # noqa: E402

SENTENCES = [
    "Yes.",
    "Hello there!",
    "How can I help you today?",
    "The train to Berlin leaves at half past nine from platform four.",
    "I am sorry, I did not quite understand that. Could you say it again, please?",
    "Morph targets store a face's expressions as offsets from a neutral shape; blending "
    "them with weights gives every mouth shape, blink and smile the avatar shows.",
    "Let me explain how this works. First, the text is turned into phonemes and sound. "
    "Then each phoneme becomes a mouth shape, and the shapes are blended over time so that "
    "the lips move smoothly. Finally the face is drawn, many times a second.",
]


def percentile(values, p):
    s = sorted(values)
    k = (len(s) - 1) * p / 100.0
    f = int(k)
    c = min(f + 1, len(s) - 1)
    return s[f] + (s[c] - s[f]) * (k - f)


def summary(values):
    return "%.0f / %.0f / %.0f" % (statistics.median(values), percentile(values, 95), max(values))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("exe", help="MorphAvatar")
    parser.add_argument("--commands", type=int, default=100)
    parser.add_argument("--quick", action="store_true", help="5 commands (CI smoke run)")
    parser.add_argument("--size", default="640x640")
    parser.add_argument("--fps", default="30")
    parser.add_argument("--markdown", help="write the table here")
    parser.add_argument("--face", help="MorphAvatar --face (default: the default head)")
    args = parser.parse_args()
    n = 5 if args.quick else args.commands

    tmp = tempfile.TemporaryDirectory()
    err_path = os.path.join(tmp.name, "stderr.txt")
    with open(err_path, "w") as err:
        proc = subprocess.Popen([args.exe, "--offscreen", "--listen", "127.0.0.1:0", "--size",
                                 args.size, "--fps", args.fps, "--quiet"] +
                                (["--face", args.face] if args.face else []),
                                stdout=subprocess.DEVNULL, stderr=err)
    address = None
    deadline = time.monotonic() + 120
    while address is None and time.monotonic() < deadline and proc.poll() is None:
        m = re.search(r"listening on (\S+)", open(err_path).read())
        address = m.group(1) if m else None
        time.sleep(0.05)
    if address is None:
        proc.kill()
        sys.exit("MorphAvatar did not start listening:\n" + open(err_path).read())

    rows = []
    try:
        with AvatarClient(address, timeout=60) as avatar:
            avatar.wait(avatar.say("Ready.", id="warm-up"), "ended", 60)  # eSpeak and GL warm
            for i in range(n):
                text = SENTENCES[i % len(SENTENCES)]
                sent = time.monotonic()
                said = avatar.say(text, id="s%d" % i)
                accepted = avatar.wait(said, "accepted", 60)
                scheduled = (time.monotonic() - sent) * 1000.0
                started = avatar.wait(said, "started", 60)
                round_trip = (time.monotonic() - sent) * 1000.0
                mouth = started["latency_ms"]
                sound = mouth + (accepted["sound"] - started["time"]) * 1000.0
                rows.append((len(text), mouth, sound, round_trip, scheduled))
                avatar.wait(avatar.stop(), "ended", 60)
                avatar.wait(said, "ended", 60)
                time.sleep(0.25)
            avatar.wait(avatar.quit(), "accepted", 60)
        proc.wait(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()

    lines = ["| say commands | characters | first mouth motion (ms): median / p95 / max | first sound (ms) | round trip (ms) | accepted (ms) |",
             "|---|---|---|---|---|---|"]

    def add(label, subset):
        if subset:
            lines.append("| %s | %d-%d | %s | %s | %s | %s |" % (
                label, min(r[0] for r in subset), max(r[0] for r in subset),
                summary([r[1] for r in subset]), summary([r[2] for r in subset]),
                summary([r[3] for r in subset]), summary([r[4] for r in subset])))

    add("all %d" % len(rows), rows)
    add("short (< 40 characters)", [r for r in rows if r[0] < 40])
    add("medium (40-99)", [r for r in rows if 40 <= r[0] < 100])
    add("long (>= 100)", [r for r in rows if r[0] >= 100])
    table = "\n".join(lines)
    print(table)
    if args.markdown:
        with open(args.markdown, "w") as out:
            out.write(table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
