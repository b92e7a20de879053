#!/bin/bash
# Runs Java3D's Morph node (the paper's engine) on the ICT face for BenchMorph, which calls
# this script in the same invocation as its own timings and reads what it writes.
#
#   RunJava3DMorph.sh HARNESS_DIR FACE.glb OUT_DIR [FRAMES=500] [WARMUP=300]
#
# HARNESS_DIR holds the Java3D harness (run.sh, Morph14.java, glb2morph.py; see its
# README.md). Writes OUT_DIR/java3d.txt (the harness's report: the median time of
# Morph.setWeights per frame), OUT_DIR/face14.bin (the 14 geometries it blends) and
# OUT_DIR/weights.bin (the exact weights of every frame). Installs nothing.
# Exit status: 0 done; 77 skipped (no harness, Java, Java3D or xvfb-run; the reason on
# stderr); anything else: the harness failed.
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 HARNESS_DIR FACE.glb OUT_DIR [FRAMES] [WARMUP]" >&2
    exit 2
fi
harness=$1 face=$2 out=$3 frames=${4:-500} warmup=${5:-300}

skip() { echo "$1" >&2; exit 77; }
[ -f "$harness/run.sh" ] && [ -f "$harness/Morph14.java" ] || skip "no Java3D harness in $harness"
[ -f "$face" ] || skip "no face $face"
command -v java >/dev/null && command -v javac >/dev/null ||
    skip "no Java compiler (apt-get install default-jdk-headless)"
[ -f /usr/share/java/j3dcore.jar ] && [ -f /usr/lib/jni/libj3dcore-ogl.so ] ||
    skip "Java3D is not installed (apt-get install libjava3d-java libjava3d-jni)"
command -v xvfb-run >/dev/null || skip "no xvfb-run (apt-get install xvfb)"
[ -x /usr/bin/python3 ] || skip "no /usr/bin/python3 (the harness converts the face with it)"

mkdir -p "$out"
rm -f "$out/java3d.txt" "$out/weights.bin"
GLB="$face" J3D_TMP="$out" bash "$harness/run.sh" "$frames" "$warmup" --no-render \
    --dump-weights="$out/weights.bin" > "$out/java3d.txt.part" 2> "$out/java3d.err"
mv "$out/java3d.txt.part" "$out/java3d.txt"
