#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Hostile input to the programs (issue 29), each case generated here (no large files in the
repository): the program ends with a clear error naming the input, the exit code says so,
the output path is untouched (no partial file, no replaced link), and the peak memory of the
child (getrusage RUSAGE_CHILDREN through os.wait4) stays under a ceiling. The full disk is a
small RLIMIT_FSIZE in the child with SIGXFSZ ignored: writes fail with EFBIG, no privileges
and no device node written (CI runs as root).

Usage: TestHostileInput.py BIN_DIR   (the folder of MorphAvatar, MorphLipSync, MakeSpeechTrack)
"""

import os
import resource
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest

BIN = None
SOURCE = os.environ.get("MORPHNODE_SOURCE_DIR",
                        os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
# MakeSpeechTrack binds the ARKit rig: an ARKit face (ICT-FaceKit, MORPHNODE_FACEKIT_DIR).
FACEKIT = os.environ.get("MORPHNODE_FACEKIT_DIR", "")
FACE = os.path.join(FACEKIT, "ict_face_dec70_sparse53.glb")
MB = 1024 * 1024


def run(args, fsize=None, timeout=120, env=None):
    """Runs a program; returns (exit code, stderr + stdout, peak RSS in MiB, seconds)."""
    def limits():
        if fsize is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
    start = time.monotonic()
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            preexec_fn=limits, env=env)
    deadline = start + timeout
    output = b""
    os.set_blocking(proc.stdout.fileno(), False)
    while True:
        try:
            chunk = proc.stdout.read()
            if chunk:
                output += chunk
        except (BlockingIOError, TypeError):
            pass
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            break
        if time.monotonic() > deadline:
            proc.kill()
            pid, status, usage = os.wait4(proc.pid, 0)
            raise AssertionError("%s did not end in %d s" % (args[0], timeout))
        time.sleep(0.02)
    rest = proc.stdout.read()
    if rest:
        output += rest
    code = os.waitstatus_to_exitcode(status)
    proc.returncode = code  # reaped by wait4 (for its rusage), not by Popen
    proc.stdout.close()
    return code, output.decode("utf-8", "replace"), usage.ru_maxrss / 1024.0, time.monotonic() - start


def wav_header(rate, channels, data_bytes):
    """A 16-bit PCM WAV header whose data chunk claims data_bytes."""
    block = 2 * channels
    return (b"RIFF" + struct.pack("<I", 36 + data_bytes) + b"WAVE" + b"fmt " +
            struct.pack("<IHHIIHH", 16, 1, channels, rate, rate * block, block, 16) +
            b"data" + struct.pack("<I", data_bytes))


class HostileInputTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.dir, name)

    def exe(self, name):
        p = os.path.join(BIN, name)
        if not os.path.exists(p):
            self.skipTest(name + " is not built")
        if name == "MakeSpeechTrack" and not os.path.exists(FACE):
            if os.environ.get("CI") == "true":
                self.fail("ICT-FaceKit missing: " + FACE)
            self.skipTest("no ICT-FaceKit face (MORPHNODE_FACEKIT_DIR): " + FACE)
        return p

    def assertRefused(self, result, *needles, ceiling_mb=400):
        code, text, rss, seconds = result
        self.assertNotEqual(code, 0, text)
        self.assertNotIn(code, (-6, -11, 134, 139), "crashed: " + text)  # abort, segfault
        for n in needles:
            self.assertIn(n, text)
        self.assertNotIn("terminate called", text)
        self.assertLess(rss, ceiling_mb, "peak RSS %.0f MiB" % rss)
        print("  %s -> exit %d, %.0f MiB, %.2f s: %s" %
              (needles[0] if needles else "", code, rss, seconds, text.strip().splitlines()[-1][:160]))

    def assertNoPartFiles(self):
        self.assertEqual([f for f in os.listdir(self.dir) if f.endswith(".part")], [])

    # --- whole-file reads before any size check (issue point 7) ------------------------

    def test_text_from_dev_zero_and_a_fifo(self):
        exe = self.exe("MakeSpeechTrack")
        out = self.path("track.csv")
        os.symlink("/dev/zero", self.path("zero.txt"))
        self.assertRefused(run([exe, "--face", FACE, "--out", out, "--text", self.path("zero.txt")]),
                           "zero.txt", "is a device")
        os.mkfifo(self.path("x.txt"))
        self.assertRefused(run([exe, "--face", FACE, "--out", out, "--text", self.path("x.txt")], timeout=30),
                           "x.txt", "is a FIFO")
        self.assertFalse(os.path.exists(out))

    def test_face_fifo_and_sparse_file(self):
        exe = self.exe("MakeSpeechTrack")
        out = self.path("track.csv")
        os.mkfifo(self.path("x.glb"))
        self.assertRefused(run([exe, "--face", self.path("x.glb"), "--out", out], timeout=30),
                           "x.glb", "is a FIFO")
        with open(self.path("big.glb"), "wb") as f:
            f.truncate(5 << 30)  # 5 GiB, sparse: no disk space used
        self.assertRefused(run([exe, "--face", self.path("big.glb"), "--out", out], timeout=60),
                           "big.glb", "has 5368709120 bytes")
        self.assertFalse(os.path.exists(out))

    # --- audio bombs (issue point 2) ------------------------------------------------------

    def test_one_hertz_wav(self):
        exe = self.exe("MorphLipSync")
        bomb = self.path("bomb.wav")
        samples = 56000
        with open(bomb, "wb") as f:
            f.write(wav_header(1, 1, 2 * samples) + b"\x10\x00" * samples)  # 113 KB at 1 Hz
        out = self.path("cues.tsv")
        self.assertRefused(run([exe, bomb, "--text", "hello", "-o", out, "-q"]),
                           "bomb.wav", "a sample rate of 1 Hz is outside")
        self.assertFalse(os.path.exists(out))

    def test_ten_hours_of_silence(self):
        exe = self.exe("MorphLipSync")
        bomb = self.path("long.wav")
        data = 10 * 3600 * 16000 * 2  # 10 h of 16 kHz mono silence: a sparse 1.15 GB file
        with open(bomb, "wb") as f:
            f.write(wav_header(16000, 1, data))
            f.truncate(44 + data)
        self.assertRefused(run([exe, bomb, "--text", "hello", "-q"]), "long.wav", "too long")

    # --- write errors and output paths (issue points 3 and 5) ----------------------------

    def test_full_disk_keeps_the_old_file(self):
        exe = self.exe("MakeSpeechTrack")
        text = self.path("say.txt")
        with open(text, "w") as f:
            f.write("Hello there. This is a short test of a full disk.\n")
        out = self.path("track.csv")
        with open(out, "w") as f:
            f.write("old\n")
        code, output, rss, _ = run([exe, "--face", FACE, "--out", out, "--text", text], fsize=4096)
        if "eSpeak" in output and "not" in output and code != 0 and "File too large" not in output:
            self.skipTest("no speech synthesis in this build: " + output.strip()[-120:])
        self.assertRefused((code, output, rss, 0), "track.csv", "File too large")
        with open(out) as f:
            self.assertEqual(f.read(), "old\n")
        self.assertNoPartFiles()

    def test_output_through_a_link_is_refused(self):
        exe = self.exe("MakeSpeechTrack")
        victim = self.path("victim.txt")
        with open(victim, "w") as f:
            f.write("keep\n")
        link = self.path("out.csv")
        os.symlink(victim, link)
        text = self.path("say.txt")
        with open(text, "w") as f:
            f.write("Hello.\n")
        self.assertRefused(run([exe, "--face", FACE, "--out", link, "--text", text]),
                           "out.csv", "is a symbolic link")
        self.assertTrue(os.path.islink(link))
        with open(victim) as f:
            self.assertEqual(f.read(), "keep\n")
        self.assertNoPartFiles()

    def test_gltf_onto_a_link_and_a_directory(self):
        exe = self.exe("MorphAvatar")
        victim = self.path("victim.glb")
        with open(victim, "wb") as f:
            f.write(b"keep")
        os.symlink(victim, self.path("out.glb"))
        os.mkdir(self.path("dir.glb"))
        for target, needle in ((self.path("out.glb"), "is a symbolic link"), (self.path("dir.glb"), "is a directory")):
            self.assertRefused(run([exe, "--gltf", target, "--duration", "1", "--quiet"], timeout=300),
                               needle)
        with open(victim, "rb") as f:
            self.assertEqual(f.read(), b"keep")
        self.assertTrue(os.path.isdir(self.path("dir.glb")))
        self.assertNoPartFiles()

    # --- glTF memory amplification (issue point 4) ---------------------------------------

    def test_thousand_instances(self):
        exe = self.exe("MorphAvatar")
        if not os.path.exists(FACE):
            self.skipTest("no ICT-FaceKit face")
        import json
        with open(FACE, "rb") as f:
            glb = f.read()
        magic, version, _ = struct.unpack_from("<III", glb, 0)
        jlen, jtype = struct.unpack_from("<II", glb, 12)
        doc = json.loads(glb[20:20 + jlen])
        rest = glb[20 + jlen:]
        mesh = next(n["mesh"] for n in doc["nodes"] if "mesh" in n)
        first = len(doc["nodes"])
        doc["nodes"] += [{"mesh": mesh, "translation": [0.01 * k, 0, 0]} for k in range(1000)]
        doc["scenes"][doc.get("scene", 0)]["nodes"] += list(range(first, first + 1000))
        j = json.dumps(doc, separators=(",", ":")).encode()
        j += b" " * ((4 - len(j) % 4) % 4)
        bomb = self.path("instances.glb")  # about 1 MB: 1,000 nodes sharing one mesh
        with open(bomb, "wb") as f:
            f.write(struct.pack("<III", magic, version, 20 + len(j) + len(rest)) +
                    struct.pack("<II", len(j), jtype) + j + rest)
        out = self.path("instances-out.glb")
        self.assertRefused(run([exe, "--face", bomb, "--rig", os.path.join(SOURCE, "Data", "rigs", "arkit.json"),
                                "--gltf", out, "--duration", "1", "--quiet"], timeout=300),
                           "more than the limit")
        self.assertFalse(os.path.exists(out))

    def test_zero_accessor_without_buffer_view(self):
        """267 bytes of glTF declaring 45 million zero points (an accessor without bufferView
        is zero-filled): refused from the estimate, before anything is decoded."""
        exe = self.exe("MorphAvatar")
        import json
        doc = {"asset": {"version": "2.0"},
               "accessors": [{"componentType": 5126, "count": 45000000, "type": "VEC3",
                              "min": [0, 0, 0], "max": [0, 0, 0]}],
               "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
               "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
        face = self.path("zeros.gltf")
        with open(face, "w") as f:
            json.dump(doc, f)
        out = self.path("zeros-out.glb")
        self.assertRefused(run([exe, "--face", face, "--gltf", out, "--duration", "1", "--quiet"], timeout=300),
                           "more than the limit")
        self.assertFalse(os.path.exists(out))

    # --- a timeline whose cost passes the budget (issue point 6) --------------------------

    def test_day_long_timeline(self):
        exe = self.exe("MorphAvatar")
        cues = self.path("late.tsv")
        with open(cues, "w") as f:
            f.write("0.00\tX\n86399.00\tA\n")  # 30 bytes: a cue just inside 24 h
        out = self.path("late.glb")
        self.assertRefused(run([exe, "--timings", cues, "--gltf", out, "--quiet"], timeout=300),
                           "more than", ceiling_mb=800)
        self.assertFalse(os.path.exists(out), "a glTF file was left")
        self.assertNoPartFiles()

    # --- commands that cannot hurt (issue point 1) ---------------------------------------

    def test_script_with_a_denormal_duration(self):
        exe = self.exe("MorphAvatar")
        script = self.path("bad.txt")
        with open(script, "w") as f:
            f.write("at 1 gesture nod duration 1e-320\n")
        self.assertRefused(run([exe, "--script", script, "--gltf", self.path("s.glb"), "--quiet"], timeout=300),
                           "duration", "outside [0.01, 86400]")
        self.assertFalse(os.path.exists(self.path("s.glb")))

    def test_script_phonemes_from_dev_zero(self):
        exe = self.exe("MorphAvatar")
        script = self.path("zero.txt")
        with open(script, "w") as f:
            f.write("at 0 phonemes /dev/zero\n")
        self.assertRefused(run([exe, "--script", script, "--gltf", self.path("z.glb"), "--quiet"], timeout=300),
                           "/dev/zero", "is a device")


if __name__ == "__main__":
    BIN = sys.argv.pop(1)
    unittest.main()
