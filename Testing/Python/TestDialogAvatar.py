#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""MorphAvatar driven live over its command sockets (docs/dialog.md), by the example client
Examples/Python/dialog_client.py: a headless avatar (--offscreen, real time) listens on a
free loopback port and a Unix socket; every command gets accepted / started / ended events
with its id and consistent times, bad lines and unknown names get error events and the
avatar goes on, a client leaving mid-line runs nothing, a second client gets only its own
events, stop interrupts speech, quit ends the program (exit code 0).

Usage: TestDialogAvatar.py MORPHAVATAR_EXE   (under xvfb-run, like the other render tests)
"""

import json
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.environ.get("MORPHNODE_SOURCE_DIR", os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "Examples", "Python"))
from dialog_client import AvatarClient, AvatarError  # noqa: E402

EXE = None


def write_take(target):
    """The recording the external-speech tests hand over, as 16 kHz 16-bit WAV into a file
    name or a file object: 1.5 s of silence, a 220 Hz tone from 0.3 s to 1.3 s, silence."""
    import math
    import struct
    import wave
    with wave.open(target, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(16000)
        w.writeframes(b"".join(
            struct.pack("<h", int(8000 * math.sin(2 * math.pi * 220 * i / 16000))
                        if 0.3 * 16000 <= i < 1.3 * 16000 else 0) for i in range(24000)))


class DialogAvatarTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.unix = os.path.join(cls.tmp.name, "avatar.sock")
        cls.err = open(os.path.join(cls.tmp.name, "stderr.txt"), "w+")
        cls.proc = subprocess.Popen(
            [EXE, "--offscreen", "--listen", "127.0.0.1:0", "--listen", "unix:" + cls.unix,
             "--size", "160x160", "--fps", "30", "--quiet", "--exit-after", "240",
             "--speech-dir", cls.tmp.name],
            stdout=subprocess.DEVNULL, stderr=cls.err)
        cls.address = None
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and cls.proc.poll() is None:
            cls.err.seek(0)
            m = re.search(r"listening on (127\.0\.0\.1:\d+)", cls.err.read())
            if m and os.path.exists(cls.unix):
                cls.address = m.group(1)
                break
            time.sleep(0.1)
        if cls.address is None:
            cls.proc.kill()
            cls.err.seek(0)
            raise RuntimeError("MorphAvatar did not start listening:\n" + cls.err.read())
        cls.client = AvatarClient(cls.address, timeout=30)
        # Speech needs eSpeak NG (the minimal build has none): find out once.
        try:
            cls.client.wait(cls.client.say("Hi.", id="hi"), "ended", timeout=60)
            cls.speech = True
        except AvatarError as e:
            cls.speech = False
            cls.speech_error = str(e)

    @classmethod
    def tearDownClass(cls):
        if cls.proc.poll() is None:
            cls.proc.kill()
            cls.proc.wait()
        cls.client.close()
        cls.err.close()
        cls.tmp.cleanup()

    def need_speech(self):
        if not self.speech:
            self.skipTest("no speech synthesis: " + self.speech_error)

    def lifecycle(self, client, cid, timeout=60):
        """accepted, started, ended of one command, in that order, with consistent times."""
        accepted = client.wait(cid, "accepted", timeout)
        started = client.wait(cid, "started", timeout)
        ended = client.wait(cid, "ended", timeout)
        for e in (accepted, started, ended):
            self.assertEqual(e["id"], cid)
        self.assertLessEqual(accepted["start"], accepted["end"])
        self.assertGreaterEqual(started["time"], started["start"])
        self.assertGreaterEqual(ended["time"], ended["end"] - 1e-9)
        self.assertGreaterEqual(started["latency_ms"], 0.0)
        self.assertFalse(ended["interrupted"])
        return accepted, started, ended

    def test_1_every_command(self):
        c = self.client
        for cid in (c.gesture("nod", intensity=0.8), c.mood("happy", 0.6),
                    c.look_at(12, -4, duration=0.5), c.gesture("smile", duration=0.4)):
            accepted, _, _ = self.lifecycle(c, cid)
            self.assertIn(accepted["cmd"], ("gesture", "mood", "look_at"))
        self.need_speech()
        said = c.say("Hello! I am listening.")
        accepted, started, ended = self.lifecycle(c, said)
        self.assertEqual(accepted["cmd"], "say")
        self.assertGreater(accepted["end"] - accepted["start"], 0.5)  # a sentence takes time
        self.assertGreaterEqual(accepted["sound"], accepted["start"] - 0.5)

    def test_2_bad_lines_get_errors_and_nothing_else(self):
        c = self.client
        c.send_line(b"not json\n[1,2]\n{\"text\":\"x\"}\n{\"cmd\":\"fly\",\"id\":\"f\"}\n")
        c.send_line(b"{\"cmd\":\"gesture\",\"name\":\"nod\",\"intensity\":7,\"id\":\"g\"}\n")
        c.send_line(b"{\"cmd\":\"stop\",\"\x00\":1}\n" + b"x" * (1024 * 1024 + 10) + b"\n")
        reasons = []
        while len(reasons) < 7:
            e = c.next_event(timeout=30)
            if e["event"] == "error":  # (late events of earlier commands are not)
                reasons.append(e["reason"])
        self.assertEqual(reasons, ["malformed", "not_object", "missing_cmd", "unknown_cmd",
                                   "bad_field", "malformed", "too_long"])
        # A valid command with an unknown name is rejected by the behaviour.
        with self.assertRaises(AvatarError) as caught:
            c.wait(c.gesture("cartwheel"), "accepted")
        self.assertEqual(caught.exception.event["reason"], "rejected")
        # The connection still works.
        self.lifecycle(c, c.gesture("blink"))

    def test_3_client_leaving_mid_line(self):
        host, port = self.address.rsplit(":", 1)
        s = socket.create_connection((host, int(port)))
        s.sendall(b"{\"cmd\":\"quit\"")  # never finished
        s.close()
        time.sleep(0.3)
        self.assertIsNone(self.proc.poll(), "a half line must not quit the avatar")
        self.lifecycle(self.client, self.client.gesture("nod"))

    def test_4_two_clients_get_their_own_events(self):
        with AvatarClient("unix:" + self.unix) as other:
            mine = self.client.gesture("nod", id="mine")
            theirs = other.gesture("tilt", id="theirs")
            self.lifecycle(other, theirs)
            self.lifecycle(self.client, mine)
            # Nothing of the other's arrived here.
            self.assertFalse(any(e.get("id") == "theirs" for e in self.client.pending))
            self.assertFalse(any(e.get("id") == "mine" for e in other.pending))

    def test_5_stop_interrupts_speech(self):
        self.need_speech()
        c = self.client
        long_text = "This is a rather long sentence that takes several seconds to say, " \
                    "so that there is time to stop it in the middle."
        said = c.say(long_text)
        accepted = c.wait(said, "accepted", 60)
        c.wait(said, "started", 60)
        stop = c.stop()
        ended = c.wait(said, "ended", 30)
        self.assertTrue(ended["interrupted"])
        self.assertLess(ended["end"], accepted["end"])
        c.wait(stop, "ended", 30)

    def test_6_voices(self):
        self.need_speech()
        c = self.client
        self.lifecycle(c, c.say("Guten Tag.", voice="de"))
        # A voice eSpeak NG does not have is rejected at once, even behind other speech.
        c.say("This sentence keeps the mouth busy for a little while.")
        with self.assertRaises(AvatarError) as caught:
            c.wait(c.say("Hi", voice="xx-no-such-voice"), "accepted", 60)
        self.assertEqual(caught.exception.event["reason"], "rejected")

    def test_7_external_speech(self):
        """A dialog system with its own voice hands over a recording and its timings: the
        avatar speaks the recording (its sound starts where the recording's does) for the
        recording's length, with the mouth timed by Rhubarb cues or Azure viseme IDs."""
        c = self.client
        wav = os.path.join(self.tmp.name, "take.wav")
        write_take(wav)
        tsv = os.path.join(self.tmp.name, "take.tsv")
        with open(tsv, "w") as f:
            f.write("0.00\tX\n0.30\tA\n0.50\tD\n1.30\tX\n")
        azure = os.path.join(self.tmp.name, "take.visemes")
        with open(azure, "w") as f:
            json.dump([{"AudioOffset": 0, "VisemeId": 0}, {"AudioOffset": 3000000, "VisemeId": 21},
                       {"AudioOffset": 5000000, "VisemeId": 2}, {"AudioOffset": 13000000, "VisemeId": 0}], f)
        for timings, fmt in ((tsv, None), (azure, "azure-visemes")):
            fields = {"audio": wav, "timings": timings}
            if fmt:
                fields["timings_format"] = fmt
            said = c.send("say", **fields)
            accepted, started, ended = self.lifecycle(c, said)
            self.assertEqual(accepted["cmd"], "say")
            self.assertAlmostEqual(accepted["end"] - accepted["start"], 1.5, delta=0.15)
            # The sound starts 0.3 s into the utterance, where the cues close the lips.
            self.assertAlmostEqual(accepted["sound"] - accepted["start"], 0.3, delta=0.05)
        # Names relative to the speech folder work too.
        self.lifecycle(c, c.send("say", audio="take.wav", timings="take.tsv"))
        # A recording the folder does not have, or a file outside it: rejected.
        for audio in (os.path.join(self.tmp.name, "missing.wav"), "../" + os.path.basename(self.tmp.name) + "x/a.wav",
                      os.path.abspath(__file__), "/etc/hostname"):
            with self.assertRaises(AvatarError) as caught:
                c.wait(c.send("say", audio=audio, timings=tsv), "accepted", 30)
            self.assertEqual(caught.exception.event["reason"], "rejected")
            self.assertIn("speech folder", caught.exception.event["message"])

    def test_8_inline_external_speech(self):
        """External speech inline: the recording's bytes in base64 and its Polly speech marks
        in the command itself (no file, no --speech-dir needed). The avatar speaks it like a
        named recording: the utterance lasts the recording, its sound starts where the
        recording's does (0.3 s, where the marks close the lips). Bad base64, bytes that are
        no sound, an unreadable timing text and an oversized line each get an error and the
        session goes on."""
        import base64
        import io
        c = self.client
        data = io.BytesIO()
        write_take(data)
        audio = base64.b64encode(data.getvalue()).decode("ascii")
        marks = [{"time": 0, "type": "viseme", "value": "sil"}, {"time": 300, "type": "viseme", "value": "p"},
                 {"time": 450, "type": "viseme", "value": "a"}, {"time": 1300, "type": "viseme", "value": "sil"}]
        # As JSON (an array of marks), as Polly's text (one mark a line), and named.
        text = "".join(json.dumps(m) + "\n" for m in marks)
        for fields in ({"timings_inline": marks},
                       {"timings_inline": text, "timings_format": "speech-marks"}):
            said = c.send("say", audio_base64=audio, **fields)
            accepted, started, ended = self.lifecycle(c, said)
            self.assertEqual(accepted["cmd"], "say")
            self.assertAlmostEqual(accepted["end"] - accepted["start"], 1.5, delta=0.15)
            self.assertAlmostEqual(accepted["sound"] - accepted["start"], 0.3, delta=0.05)
        # Bad base64: the parser refuses it (bad_field, where it went wrong).
        with self.assertRaises(AvatarError) as caught:
            c.wait(c.send("say", audio_base64=audio[:100] + "*" + audio[101:], timings_inline=marks),
                   "accepted", 30)
        self.assertEqual(caught.exception.event["reason"], "bad_field")
        self.assertIn("'audio_base64' is not valid base64: '*' at character 100",
                      caught.exception.event["message"])
        # Valid base64 of bytes that are no sound file: rejected by the audio reader.
        with self.assertRaises(AvatarError) as caught:
            c.wait(c.send("say", audio_base64=base64.b64encode(b"RIFF but no WAVE" * 8).decode(),
                          timings_inline=marks), "accepted", 30)
        self.assertEqual(caught.exception.event["reason"], "rejected")
        self.assertIn("'audio_base64' cannot be read", caught.exception.event["message"])
        # Timings that are no timings.
        with self.assertRaises(AvatarError) as caught:
            c.wait(c.send("say", audio_base64=audio, timings_inline="no timings here"), "accepted", 30)
        self.assertEqual(caught.exception.event["reason"], "rejected")
        self.assertIn("inline timings", caught.exception.event["message"])
        # Beyond the line limit (1 MiB): too_long, the bytes dropped as they come.
        big = base64.b64encode(b"\0" * (800 * 1024)).decode()
        c.send_line(json.dumps({"cmd": "say", "id": "big", "audio_base64": big}) + "\n")
        e = c.next_event(timeout=30)
        while e["event"] != "error":  # (late events of earlier commands are not)
            e = c.next_event(timeout=30)
        self.assertEqual(e["reason"], "too_long")
        # The session goes on (the example client's helper sends the same command).
        accepted, _, _ = self.lifecycle(c, c.say_recording(data.getvalue(), text.encode()))
        self.assertAlmostEqual(accepted["sound"] - accepted["start"], 0.3, delta=0.05)

    def test_9_quit(self):
        c = self.client
        c.wait(c.quit(id="bye"), "accepted", 30)
        self.assertEqual(self.proc.wait(timeout=60), 0)


class DialogWindowTest(unittest.TestCase):
    """The window's loop (AvatarInteractive + the LiveFrame hook): commands on stdin, events
    on stdout and nothing else there, time running on past the default 5 s loop."""

    def test_window_commands_on_stdin(self):
        lines = b'{"cmd":"gesture","name":"nod","id":"w1"}\n{"cmd":"look_at","yaw":5,"pitch":0,"id":2}\n'
        proc = subprocess.Popen([EXE, "--commands-stdin", "--size", "160x160", "--exit-after", "6"],
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        proc.stdin.write(lines)
        proc.stdin.flush()
        out, err = proc.communicate(timeout=120)
        self.assertEqual(proc.returncode, 0, err.decode(errors="replace"))
        events = [json.loads(line) for line in out.decode().splitlines()]  # only JSON there
        kinds = [(e["id"], e["event"]) for e in events]
        for cid in ("w1", 2):
            self.assertEqual([k for i, k in kinds if i == cid], ["accepted", "started", "ended"], kinds)
        self.assertIn("rendered", err.decode())  # the --exit-after summary, on stderr
        # Time ran on: the last overlay shows t beyond the 5 s the default behaviour lasts.
        m = re.findall(r"t = ([0-9.]+) s", err.decode())
        self.assertTrue(m and float(m[-1]) > 5.5, err.decode())


class RecordedSessionTest(unittest.TestCase):
    """--video and --frames while live record the session: the frames at the frame rate and
    the sound as it was played, placed where the avatar said it would be (events' times)."""

    def test_live_session_is_recorded(self):
        import wave
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        wav = os.path.join(tmp.name, "take.wav")
        with wave.open(wav, "wb") as w:  # 1 s of a tone
            w.setnchannels(1)
            w.setsampwidth(2)
            w.setframerate(16000)
            w.writeframes(b"".join(int(8000 * __import__("math").sin(i / 10.0)).to_bytes(2, "little", signed=True)
                                   for i in range(16000)))
        with open(os.path.join(tmp.name, "take.tsv"), "w") as f:
            f.write("0.00\tA\n0.20\tD\n0.90\tX\n")
        proc = subprocess.Popen(
            [EXE, "--commands-stdin", "--speech-dir", tmp.name, "--size", "120x120", "--fps", "10",
             "--frames", os.path.join(tmp.name, "frames"), "--video", os.path.join(tmp.name, "session.ogv")],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        proc.stdin.write(b'{"cmd":"say","audio":"take.wav","timings":"take.tsv","id":"t"}\n')
        proc.stdin.flush()
        time.sleep(2.5)
        proc.stdin.write(b'{"cmd":"quit"}\n')
        proc.stdin.flush()
        out, err = proc.communicate(timeout=120)
        self.assertEqual(proc.returncode, 0, err.decode())
        events = [json.loads(line) for line in out.decode().splitlines()]  # stdout: events only
        accepted = next(e for e in events if e.get("id") == "t" and e["event"] == "accepted")
        quit_time = next(e for e in events if e.get("cmd") == "quit")["time"]
        frames = sorted(os.listdir(os.path.join(tmp.name, "frames")))
        self.assertAlmostEqual(len(frames), int(quit_time * 10) + 1, delta=2)
        with wave.open(os.path.join(tmp.name, "session.wav")) as w:
            rate = w.getframerate()
            samples = w.readframes(w.getnframes())
        values = [int.from_bytes(samples[i:i + 2], "little", signed=True) for i in range(0, len(samples), 2)]

        def loud(t0, t1):
            part = values[int(t0 * rate):int(t1 * rate)]
            return max((abs(v) for v in part), default=0) > 1000

        # The recording sounds from the time the avatar announced, not before.
        self.assertFalse(loud(0.0, max(0.0, accepted["sound"] - 0.05)))
        self.assertTrue(loud(accepted["sound"] + 0.05, accepted["sound"] + 0.9))
        self.assertIn("session.wav", err.decode())


if __name__ == "__main__":
    EXE = sys.argv.pop(1)
    unittest.main(verbosity=2)
