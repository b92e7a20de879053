#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Plots of docs/speech.md from the output of StudySpeechAlignment (needs python3-matplotlib).

    build/bin/StudySpeechAlignment --out build/speech-study
    python3 Testing/Benchmarks/plot_speech_study.py build/speech-study docs/images

speech_boundary_errors.png: cumulative distribution of the phoneme boundary error per route.
speech_librivox_alignment.png: a LibriVox reading of pocketsphinx-testdata (read in place),
its waveform with the aligned words and the viseme of every aligned phoneme.
"""
import csv
import sys
import wave
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LIBRIVOX = Path("/usr/share/pocketsphinx/test/data/librivox")


def boundary_errors(study: Path, images: Path) -> None:
    routes = {}
    with open(study / "boundary-errors.csv", newline="") as f:
        for row in csv.DictReader(f):
            routes.setdefault(row["route"], []).append(float(row["error_ms"]))
    labels = {"transcript": "transcript (eSpeak NG + DTW)", "linear": "linear stretch (baseline)",
              "recognition": "no transcript (PocketSphinx, English)"}
    fig, ax = plt.subplots(figsize=(7, 4))
    for route, errors in sorted(routes.items()):
        errors.sort()
        n = len(errors)
        ax.plot(errors, [(k + 1) / n for k in range(n)], label=f"{labels.get(route, route)} ({n} boundaries)")
    ax.axvline(20, color="grey", linestyle=":", linewidth=1)
    ax.set_xscale("symlog", linthresh=10)
    ax.set_xlim(0, 1000)
    ax.set_xlabel("phoneme boundary error (ms)")
    ax.set_ylabel("fraction of boundaries")
    ax.set_title("Timing against eSpeak NG truth (other voices, rates 130-220 wpm, noise)")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(images / "speech_boundary_errors.png", dpi=110)


def librivox(study: Path, images: Path, name: str) -> None:
    with wave.open(str(LIBRIVOX / f"{name}.wav")) as w:
        rate = w.getframerate()
        raw = w.readframes(w.getnframes())
    samples = [int.from_bytes(raw[i:i + 2], "little", signed=True) / 32768 for i in range(0, len(raw), 2)]
    times = [i / rate for i in range(len(samples))]
    with open(study / f"human-{name}-words.csv", newline="") as f:
        words = list(csv.DictReader(f))
    with open(study / f"human-{name}-phonemes.csv", newline="") as f:
        phonemes = list(csv.DictReader(f))
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 4.6), sharex=True,
                                      gridspec_kw={"height_ratios": [2, 1]})
    top.plot(times, samples, linewidth=0.4, color="#456")
    for k, w in enumerate(words):
        start, end = float(w["start"]), float(w["end"])
        top.axvspan(start, end, color="C1" if k % 2 else "C2", alpha=0.15)
        top.text((start + end) / 2, 0.9 * max(samples), w["word"], ha="center", va="top", fontsize=8)
    top.set_ylabel("waveform")
    top.set_title(f"LibriVox reading (pocketsphinx-testdata {name}): transcript aligned")
    visemes = sorted({p["viseme"] for p in phonemes})
    for p in phonemes:
        start, end = float(p["start"]), float(p["end"])
        y = visemes.index(p["viseme"])
        bottom.plot([start, end], [y, y], linewidth=5, solid_capstyle="butt")
        if end - start > 0.04 and p["phoneme"] != "_":
            bottom.text((start + end) / 2, y + 0.45, p["phoneme"], ha="center", fontsize=6)
    bottom.set_yticks(range(len(visemes)))
    bottom.set_yticklabels(visemes, fontsize=7)
    bottom.set_ylabel("viseme")
    bottom.set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(images / "speech_librivox_alignment.png", dpi=110)


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    study, images = Path(sys.argv[1]), Path(sys.argv[2])
    images.mkdir(parents=True, exist_ok=True)
    boundary_errors(study, images)
    librivox(study, images, "sense_and_sensibility_01_austen_64kb-0920")
    return 0


if __name__ == "__main__":
    sys.exit(main())
