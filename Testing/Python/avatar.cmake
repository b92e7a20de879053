# The morph_avatar.py example (Python twin of MorphAvatar): a second of speech offscreen to
# PNG frames, a Theora video and the WAV; a second test checks what it wrote.
set(avatar_out "${MORPHNODE_TEST_OUTPUT_DIR}/ExampleMorphAvatarPython")
morphnode_add_python_test(ExampleMorphAvatarPython
  ${PROJECT_SOURCE_DIR}/Examples/Python/morph_avatar.py
  --say "Hello, my friend." --seed 3 --duration 1 --fps 10 --size 240x240 --method adjusted
  --offscreen --frames "${avatar_out}" --video "${avatar_out}/avatar.ogv")
set_tests_properties(ExampleMorphAvatarPython PROPERTIES
  LABELS "python;examples;render;avatar" FIXTURES_SETUP MorphAvatarPythonOutput)
add_test(NAME ExampleMorphAvatarPythonOutput COMMAND "${Python3_EXECUTABLE}" -c
  "import os, sys; d = sys.argv[1]; frames = sorted(f for f in os.listdir(d) if f.startswith('frame_')); \
assert len(frames) == 11, frames; \
assert open(os.path.join(d, 'avatar.ogv'), 'rb').read(4) == b'OggS'; \
assert open(os.path.join(d, 'avatar.wav'), 'rb').read(4) == b'RIFF'; \
sizes = {os.path.getsize(os.path.join(d, f)) for f in frames}; assert len(sizes) > 1, 'all frames alike'; \
print('ok:', len(frames), 'frames, video and audio')"
  "${avatar_out}")
set_tests_properties(ExampleMorphAvatarPythonOutput PROPERTIES
  LABELS "python;examples;avatar" FIXTURES_REQUIRED MorphAvatarPythonOutput)
