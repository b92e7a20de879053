#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Drives a running MorphAvatar from Python, as a dialog system would (docs/dialog.md).

Start the avatar with a command socket, then send it commands:

    MorphAvatar --listen 127.0.0.1:5555 &
    python3 Examples/Python/dialog_client.py 127.0.0.1:5555 --mood happy \
        --say "Hello! How can I help you?" --gesture nod

Commands are JSON objects, one per line; the avatar answers with events, one JSON object
per line (accepted, started, ended, error), each echoing the command's id. Only the Python
standard library is needed. As a module:

    from dialog_client import AvatarClient
    with AvatarClient("127.0.0.1:5555") as avatar:
        said = avatar.send("say", text="Nice to meet you.")
        avatar.wait(said, "ended")
"""

import argparse
import itertools
import json
import socket
import sys
import time


class AvatarError(RuntimeError):
    """An error event (its reason and message) or a connection problem."""

    def __init__(self, message, event=None):
        super().__init__(message)
        self.event = event


class AvatarClient:
    """A connection to MorphAvatar's --listen address: "HOST:PORT" or "unix:PATH"."""

    def __init__(self, address, timeout=10.0):
        if address.startswith("unix:"):
            self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            self.sock.settimeout(timeout)
            self.sock.connect(address[5:])
        else:
            host, _, port = address.rpartition(":")
            self.sock = socket.create_connection((host.strip("[]") or "127.0.0.1", int(port)), timeout)
        self.buffer = b""
        self.pending = []  # events read while waiting for another one
        self.ids = (f"py{n}" for n in itertools.count(1))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self.sock.close()

    def send_line(self, line):
        """Sends raw bytes (a line without its newline is completed by the next call)."""
        self.sock.sendall(line if isinstance(line, bytes) else line.encode("utf-8"))

    def send(self, cmd, id=None, **fields):
        """Sends one command; returns its id (made up when not given)."""
        command = {"cmd": cmd, "id": id if id is not None else next(self.ids)}
        command.update(fields)
        self.send_line(json.dumps(command) + "\n")
        return command["id"]

    def next_event(self, timeout=10.0):
        """The next event (a dict); None when the avatar closed the connection."""
        if self.pending:
            return self.pending.pop(0)
        deadline = time.monotonic() + timeout
        while b"\n" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no event from the avatar within %.1f s" % timeout)
            self.sock.settimeout(left)
            chunk = self.sock.recv(65536)
            if not chunk:
                return None
            self.buffer += chunk
        line, self.buffer = self.buffer.split(b"\n", 1)
        return json.loads(line)

    def wait(self, id, event="ended", timeout=30.0):
        """Reads events until `event` of command `id` arrives and returns it; events of other
        commands are kept for next_event(). An error event of that command raises."""
        deadline = time.monotonic() + timeout
        kept = []
        try:
            while True:
                e = self.next_event(max(0.0, deadline - time.monotonic()))
                if e is None:
                    raise AvatarError("the avatar closed the connection")
                if e.get("id") == id and e.get("event") == "error":
                    raise AvatarError("%s: %s" % (e.get("reason"), e.get("message")), e)
                if e.get("id") == id and e.get("event") == event:
                    return e
                kept.append(e)
        finally:
            self.pending = kept + self.pending

    # Shorthands for the commands of docs/dialog.md.
    def say(self, text, voice=None, **kw):
        return self.send("say", text=text, **({"voice": voice} if voice else {}), **kw)

    def say_recording(self, audio, timings=None, text=None, timings_format=None, **kw):
        """External speech (docs/dialog.md): `audio` is the recording's bytes (sent inline,
        base64) or a file name in the avatar's --speech-dir; `timings` a file name there (str),
        the timing file's text (bytes) or its JSON (a list or dict), sent inline; `text` the
        transcript to align when there are no timings."""
        import base64
        fields = {}
        if isinstance(audio, (bytes, bytearray)):
            fields["audio_base64"] = base64.b64encode(audio).decode("ascii")
        else:
            fields["audio"] = audio
        if isinstance(timings, str):
            fields["timings"] = timings
        elif isinstance(timings, (bytes, bytearray)):
            fields["timings_inline"] = timings.decode("utf-8")
        elif timings is not None:
            fields["timings_inline"] = timings
        if timings_format:
            fields["timings_format"] = timings_format
        if text is not None:
            fields["text"] = text
        return self.send("say", **fields, **kw)

    def gesture(self, name, intensity=1.0, duration=None, **kw):
        extra = {"duration": duration} if duration else {}
        return self.send("gesture", name=name, intensity=intensity, **extra, **kw)

    def mood(self, name, intensity=1.0, **kw):
        return self.send("mood", name=name, intensity=intensity, **kw)

    def look_at(self, yaw, pitch, duration=None, **kw):
        extra = {"duration": duration} if duration else {}
        return self.send("look_at", yaw=yaw, pitch=pitch, **extra, **kw)

    def stop(self, **kw):
        return self.send("stop", **kw)

    def quit(self, **kw):
        return self.send("quit", **kw)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("address", help="the avatar's --listen address: HOST:PORT or unix:PATH")
    parser.add_argument("--say", action="append", default=[], help="a sentence to say (repeatable)")
    parser.add_argument("--voice", help="eSpeak NG voice of --say")
    parser.add_argument("--gesture", action="append", default=[], help="a gesture, e.g. nod (repeatable)")
    parser.add_argument("--mood", help="a mood, e.g. happy")
    parser.add_argument("--intensity", type=float, default=0.7, help="of the mood")
    parser.add_argument("--look", nargs=2, type=float, metavar=("YAW", "PITCH"), help="look at (degrees)")
    parser.add_argument("--quit", action="store_true", help="close the avatar at the end")
    args = parser.parse_args(argv)

    with AvatarClient(args.address) as avatar:
        ids = []
        if args.mood:
            ids.append(avatar.mood(args.mood, args.intensity))
        if args.look:
            ids.append(avatar.look_at(*args.look, duration=2.0))
        for name in args.gesture:
            ids.append(avatar.gesture(name))
        for text in args.say:
            ids.append(avatar.say(text, args.voice))
        # Print every event until each command has ended (or failed).
        open_ids = set(ids)
        while open_ids:
            e = avatar.next_event(timeout=60.0)
            if e is None:
                print("the avatar closed the connection", file=sys.stderr)
                return 1
            print(json.dumps(e))
            if e.get("event") in ("ended", "error"):
                open_ids.discard(e.get("id"))
        if args.quit:
            avatar.wait(avatar.quit(), "accepted")
    return 0


if __name__ == "__main__":
    sys.exit(main())
