// SPDX-License-Identifier: BSD-3-Clause
// The avatar prepared for streaming and one session (stream/StreamAvatar.h,
// StreamSession.h) on the default head and the ICT head: the file keeps only driven
// targets and gains the rotation nodes; frames decode; speech opens the mouth and brings
// sound; stop sends a stop and closes the mouth; the optimizer sends fewer targets.
#include "stream/StreamSession.h"

#include "MorphNodeTestSkips.h"
#include "base/Error.h"
#include "budget/DeviceProfile.h"
#include "gltf/GltfScene.h"
#include "speech/Speech.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

using namespace morphnode;
using namespace morphnode::stream;

namespace
{
SpeechOptions Paper6()
{
  SpeechOptions o;
  o.Visemes = VisemeSet::Paper6;
  return o;
}

std::vector<std::string> ChannelsOf(const SpeechOptions& speech)
{
  return LiveBehavior(SelectVisemeMap(speech).GetVisemes()).GetChannelNames();
}

const GltfScene& DefaultHead()
{
  static const GltfScene scene =
    LoadGltfScene(std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb");
  return scene;
}

/// Writes the avatar file into the Khronos validator test's folder when it runs this
/// program (MORPHNODE_GLTF_EXPORT_DIR; GltfValidatorStreamAvatar).
void WriteForValidator(const StreamAvatar& avatar, const std::string& name)
{
  const char* dir = std::getenv("MORPHNODE_GLTF_EXPORT_DIR");
  if (!dir || !*dir)
  {
    return;
  }
  std::filesystem::create_directories(dir);
  std::ofstream out(std::string(dir) + "/" + name, std::ios::binary);
  out.write(reinterpret_cast<const char*>(avatar.GetFile().data()),
    static_cast<std::streamsize>(avatar.GetFile().size()));
}

struct Decoded
{
  std::vector<Frame> Frames;
  std::vector<AudioChunk> Audio;
  std::vector<StopMessage> Stops;
};

Decoded Decode(StreamSession& s, const StreamHeader& h)
{
  Decoded d;
  for (const auto& m : s.TakeMessages())
  {
    const ServerMessage msg = DecodeServerMessage(m.data(), m.size(), &h);
    if (auto* f = std::get_if<Frame>(&msg))
    {
      d.Frames.push_back(*f);
    }
    else if (auto* a = std::get_if<AudioChunk>(&msg))
    {
      d.Audio.push_back(*a);
    }
    else
    {
      d.Stops.push_back(std::get<StopMessage>(msg));
    }
  }
  return d;
}

/// The largest weight (0..255) a frame gives any of `names`.
int Largest(const Frame& f, const StreamHeader& h, const std::set<std::string>& names)
{
  int best = 0;
  for (const auto& [index, weight] : f.Targets)
  {
    if (names.count(h.Targets[index]))
    {
      best = std::max(best, static_cast<int>(weight));
    }
  }
  return best;
}
} // namespace

TEST(StreamAvatar, DefaultHeadFileHasDrivenTargetsAndRotationNodes)
{
  const SpeechOptions speech = Paper6();
  const StreamAvatar avatar(DefaultHead(), ChannelsOf(speech), nullptr, false);
  const StreamAvatar quantized(DefaultHead(), ChannelsOf(speech));
  WriteForValidator(quantized, "stream_default_head.glb");
  // The quantized file: KHR_mesh_quantization, fewer bytes (the deltas are half of them).
  const auto& glb = quantized.GetFile();
  ASSERT_GT(glb.size(), 20u);
  const size_t jsonLength =
    glb[12] | (glb[13] << 8) | (glb[14] << 16) | (static_cast<size_t>(glb[15]) << 24);
  ASSERT_LE(20 + jsonLength, glb.size());
  const std::string json(
    glb.begin() + 20, glb.begin() + 20 + static_cast<std::ptrdiff_t>(jsonLength));
  EXPECT_NE(json.find("KHR_mesh_quantization"), std::string::npos);
  EXPECT_LT(quantized.GetFile().size(), avatar.GetFile().size());
  EXPECT_EQ(quantized.GetTargetNames(), avatar.GetTargetNames());
  const auto& targets = avatar.GetTargetNames();
  EXPECT_GE(targets.size(), 6u);
  EXPECT_NE(std::find(targets.begin(), targets.end(), "A"), targets.end());
  ASSERT_GE(avatar.GetRotationNames().size(), 1u);
  EXPECT_EQ(avatar.GetRotationNames()[0], "HeadRotation");
  // The file loads back with the stream's targets only, and has the rotation nodes.
  const GltfScene back = LoadGltfSceneFromMemory(avatar.GetFile().data(), avatar.GetFile().size());
  std::set<std::string> names;
  for (const auto& part : back.Parts)
  {
    for (const auto& t : part.Targets)
    {
      names.insert(t.Name);
    }
  }
  EXPECT_EQ(names, std::set<std::string>(targets.begin(), targets.end()));
  for (const std::string& rotation : avatar.GetRotationNames())
  {
    EXPECT_TRUE(std::any_of(
      back.Nodes.begin(), back.Nodes.end(), [&](const GltfNode& n) { return n.Name == rotation; }))
      << rotation;
  }
  // A face the channels cannot drive is refused.
  EXPECT_THROW(StreamAvatar(DefaultHead(), { "Nothing", "Else" }), InputError);
}

TEST(StreamAvatar, IctHeadThroughTheRigLeavesUndrivenTargetsOut)
{
  const std::string file = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
  if (!std::filesystem::exists(file))
  {
    GTEST_SKIP() << "ICT-FaceKit data missing: " << file;
  }
  const GltfScene head = LoadGltfScene(file);
  const Rig rig = Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
  const StreamAvatar avatar(head, ChannelsOf(Paper6()), &rig);
  WriteForValidator(avatar, "stream_ict_head.glb");
  EXPECT_EQ(avatar.GetNumberOfFaceTargets(), 53u);
  EXPECT_LT(avatar.GetTargetNames().size(), 53u); // the paper's shapes do not use them all
  const auto& t = avatar.GetTargetNames();
  EXPECT_NE(std::find(t.begin(), t.end(), "jawOpen"), t.end());
  EXPECT_GE(avatar.GetRotationNames().size(), 3u); // head and two eyes
  EXPECT_LT(avatar.GetFile().size(), 40u * 1024 * 1024);
}

TEST(StreamSession, IdleFramesDecodeAndRotationsAreSentWhenTheyChange)
{
  const SpeechOptions speech = Paper6();
  const StreamAvatar avatar(DefaultHead(), ChannelsOf(speech));
  StreamSettings settings;
  StreamSession s(avatar, SelectVisemeMap(speech).GetVisemes(), nullptr, settings);
  const StreamHeader h = ParseHeader(s.Header("x", "/avatar.glb"));
  EXPECT_EQ(h.Targets, avatar.GetTargetNames());
  size_t rotationsSent = 0;
  for (int i = 0; i < 90; ++i)
  {
    s.Tick(i / 30.0);
    const Decoded d = Decode(s, h);
    ASSERT_EQ(d.Frames.size(), 1u);
    EXPECT_EQ(d.Frames[0].Sample, static_cast<uint32_t>(std::lround(i / 30.0 * 24000)));
    if (i == 0)
    {
      EXPECT_EQ(d.Frames[0].Rotations.size(), h.Rotations.size()); // all at first
    }
    rotationsSent += d.Frames[0].Rotations.size();
  }
  EXPECT_LT(rotationsSent, 90 * h.Rotations.size()); // eyes hold still between saccades
  EXPECT_EQ(s.GetNumberOfFrames(), 90u);
}

TEST(StreamSession, SayOpensTheMouthBringsSoundAndStopClosesIt)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  const SpeechOptions speech = Paper6();
  const StreamAvatar avatar(DefaultHead(), ChannelsOf(speech));
  StreamSettings settings;
  StreamSession s(
    avatar, SelectVisemeMap(speech).GetVisemes(),
    [speech](const std::string& text) { return SpeakText(text, speech); }, settings);
  const StreamHeader h = ParseHeader(s.Header("x", "/avatar.glb"));
  const std::set<std::string> mouth = { "A", "E", "O", "S", "F", "L" };
  s.Tick(0.0);
  Decode(s, h);
  dialog::SayCommand say;
  say.Text = "Hello there, how are you doing today? I am fine.";
  const dialog::Schedule when = s.Say(say, 0.1);
  EXPECT_GE(when.Start, 0.1);
  int open = 0;
  size_t audioSamples = 0;
  for (int i = 1; i <= 45; ++i) // 1.5 s
  {
    s.Tick(i / 30.0);
    const Decoded d = Decode(s, h);
    open = std::max(open, Largest(d.Frames.back(), h, mouth));
    for (const auto& a : d.Audio)
    {
      EXPECT_GE(a.Sample, s.SampleOf(0.1) - 1);
      audioSamples += a.Frames;
    }
  }
  EXPECT_GT(open, 100) << "the mouth should open while speaking";
  EXPECT_GT(audioSamples, 24000u / 2) << "half a second of sound at least";
  // Stop: a stop message at its sample, then the mouth closes within the fade.
  s.StopSpeaking(1.5);
  Decoded d = Decode(s, h);
  ASSERT_EQ(d.Stops.size(), 1u);
  EXPECT_EQ(d.Stops[0].Sample, s.SampleOf(1.5));
  int after = 255;
  for (int i = 46; i <= 52; ++i)
  {
    s.Tick(i / 30.0);
    d = Decode(s, h);
    EXPECT_TRUE(d.Audio.empty()) << "no sound after stop";
    after = Largest(d.Frames.back(), h, mouth);
  }
  EXPECT_LT(after, 10) << "the mouth is closed 0.23 s after stop";
}

TEST(StreamSession, TheOptimizerSendsFewerTargets)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  const SpeechOptions speech = Paper6();
  const StreamAvatar avatar(DefaultHead(), ChannelsOf(speech));
  auto count = [&](const OptimizerSettings& optimizer)
  {
    StreamSettings settings;
    settings.Optimizer = optimizer;
    StreamSession s(
      avatar, SelectVisemeMap(speech).GetVisemes(),
      [speech](const std::string& text) { return SpeakText(text, speech); }, settings);
    dialog::SayCommand say;
    say.Text = "One two three four five six seven.";
    s.Say(say, 0.0);
    for (int i = 0; i < 90; ++i)
    {
      s.Tick(i / 30.0);
    }
    return s.GetFrameBytes();
  };
  const uint64_t all = count(OptimizerSettings());
  const uint64_t pruned = count(MakeOptimizerSettings(OptimizerPreset::Adjusted, 0.1, 0.0));
  EXPECT_LT(pruned, all);
}

TEST(StreamSession, OpusWhenAskedIsSmallerThanPcm)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  if (!HasOpus())
  {
    GTEST_SKIP() << "built without libopus (libopus-dev)";
  }
  const SpeechOptions speech = Paper6();
  const StreamAvatar avatar(DefaultHead(), ChannelsOf(speech));
  auto audio = [&](AudioCodec codec, std::vector<AudioChunk>& chunks)
  {
    StreamSettings settings;
    settings.Codec = codec;
    StreamSession s(
      avatar, SelectVisemeMap(speech).GetVisemes(),
      [speech](const std::string& text) { return SpeakText(text, speech); }, settings);
    const StreamHeader h = ParseHeader(s.Header("x", "/avatar.glb"));
    EXPECT_EQ(h.Codec, codec);
    dialog::SayCommand say;
    say.Text = "Hello there.";
    s.Say(say, 0.0);
    s.Tick(0.0);
    uint64_t bytes = 0;
    for (const auto& m : s.TakeMessages())
    {
      const ServerMessage msg = DecodeServerMessage(m.data(), m.size(), &h);
      if (auto* a = std::get_if<AudioChunk>(&msg))
      {
        chunks.push_back(*a);
        bytes += m.size();
      }
    }
    return bytes;
  };
  std::vector<AudioChunk> pcm, opus;
  const uint64_t pcmBytes = audio(AudioCodec::Pcm16, pcm);
  const uint64_t opusBytes = audio(AudioCodec::Opus, opus);
  ASSERT_FALSE(opus.empty());
  for (size_t i = 0; i < opus.size(); ++i)
  {
    EXPECT_EQ(opus[i].Frames, 480u); // 20 ms at 24 kHz
    EXPECT_FALSE(opus[i].Payload.empty());
    if (i > 0)
    {
      EXPECT_EQ(opus[i].Sample, opus[i - 1].Sample + 480u); // contiguous on the clock
    }
  }
  EXPECT_EQ(opus.front().Sample, pcm.front().Sample);
  EXPECT_LT(opusBytes * 5, pcmBytes) << "Opus at 24 kbit/s is far smaller than 384 kbit/s PCM";
  // Opus needs one of its rates.
  StreamSettings odd;
  odd.Codec = AudioCodec::Opus;
  odd.SampleRate = 22050;
  EXPECT_THROW(
    StreamSession(avatar, SelectVisemeMap(speech).GetVisemes(), nullptr, odd), InputError);
}

// With the synthesis pool, a say returns at once and the frames go on; the speech starts
// at the first frame after it is ready, with its sound stamped there; a say's voice goes
// through the session's voice synthesizers (refused without them or for a voice they
// lack); started is not announced before the mouth moves (Refresh keeps Start ahead).
TEST(StreamSession, WithAPoolSayNeverBlocksAndASaysVoiceIsUsed)
{
  const SpeechOptions speech = Paper6();
  const StreamAvatar avatar(DefaultHead(), ChannelsOf(speech));
  auto voices = std::make_shared<std::vector<std::string>>();
  auto fake = [](const std::string& voice)
  {
    return [voice](const std::string& text)
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(30)); // synthesis takes a while
      Utterance u;
      u.Visemes = WeightTrack({ "A" }, 100.0);
      for (int f = 0; f <= 100; ++f)
      {
        u.Visemes.AppendFrame(std::vector<double>{ f > 10 && f < 90 ? 1.0 : 0.0 });
      }
      u.Duration = 1.0;
      u.SampleRate = 24000;
      u.Audio.assign(24000, voice == "de" ? 2000 : 1000);
      (void)text;
      return u;
    };
  };
  StreamSettings settings;
  StreamSession s(avatar, SelectVisemeMap(speech).GetVisemes(), fake("en"), settings);
  s.SetSynthesisPool(std::make_shared<SynthesisPool>());
  const StreamHeader h = ParseHeader(s.Header("x", "/avatar.glb"));
  dialog::SayCommand say;
  say.Text = "Hallo.";
  say.Voice = "de";
  EXPECT_THROW(s.Say(say, 0.0), InputError) << "no voice synthesizers: a voice is refused";
  s.SetVoiceSynthesizers(
    [&](const std::string& voice) -> LiveBehavior::Synthesizer
    {
      voices->push_back(voice);
      if (voice != "de")
      {
        throw InputError("unknown voice '" + voice + "'");
      }
      return fake(voice);
    });
  say.Voice = "xx";
  EXPECT_THROW(s.Say(say, 0.0), InputError);
  say.Voice = "de";
  s.Tick(0.0);
  Decode(s, h);
  dialog::Schedule when = s.Say(say, 0.0);
  ASSERT_NE(when.Handle, 0u);
  EXPECT_TRUE(std::isnan(when.Sound)) << "not known until synthesized";
  const std::set<std::string> mouth = { "A" };
  double t = 0.0;
  int frames = 0, open = 0;
  int16_t firstSample = 0;
  uint32_t soundAt = 0;
  bool heard = false;
  while (t < 3.0 && !heard)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    t += 1.0 / 30.0;
    s.Tick(t);
    ++frames;
    dialog::Schedule now = when;
    ASSERT_TRUE(s.Refresh(when.Handle, now));
    const Decoded d = Decode(s, h);
    if (!d.Audio.empty())
    {
      heard = true;
      soundAt = d.Audio[0].Sample;
      firstSample = static_cast<int16_t>(d.Audio[0].Payload[0] | (d.Audio[0].Payload[1] << 8));
      EXPECT_DOUBLE_EQ(now.Start, t) << "speech starts at the frame that picked it up";
      EXPECT_DOUBLE_EQ(now.Sound, t);
    }
    else
    {
      EXPECT_GT(now.Start, t) << "start stays ahead of the frames until ready";
    }
  }
  ASSERT_TRUE(heard);
  EXPECT_EQ(soundAt, s.SampleOf(t));
  EXPECT_EQ(firstSample, 2000) << "the say's voice spoke";
  EXPECT_EQ(*voices, (std::vector<std::string>{ "xx", "de" }));
  for (int i = 0; i < 30; ++i)
  {
    t += 1.0 / 30.0;
    s.Tick(t);
    const Decoded d = Decode(s, h);
    open = std::max(open, Largest(d.Frames.back(), h, mouth));
  }
  EXPECT_GT(open, 100) << "the mouth opens once the speech is ready";
  EXPECT_GT(frames, 1) << "frames went on while synthesizing";
}

// A device's avatar (docs/streaming.md): a phone gets the level-of-detail ladder's level 1
// (when the build has the reduction) with the same targets, and a target that moves less
// than the profile's pixel bound on the face's height is left out (kept on the desktop
// with a smaller bound, and without a bound). The phone's file goes to the Khronos validator.
TEST(StreamAvatar, DevicesGetTheirLevelAndTheirPixelBoundPrunesTargets)
{
  const SpeechOptions speech = Paper6();
  const std::vector<std::string> channels = ChannelsOf(speech);
  const StreamAvatar full(DefaultHead(), channels, nullptr, false);
  StreamAvatarOptions phoneOptions = DeviceAvatarOptions(FindDeviceProfile("phone"));
  EXPECT_EQ(phoneOptions.Level, 1);
  EXPECT_DOUBLE_EQ(phoneOptions.TargetPixelBound, 1.0);
  phoneOptions.QuantizeDeltas = false; // read back below
  const StreamAvatar phone(DefaultHead(), channels, nullptr, phoneOptions);
  EXPECT_EQ(phone.GetTargetNames(), full.GetTargetNames())
    << "every target of the default head shows on a phone";
  EXPECT_TRUE(phone.GetPrunedTargets().empty());
  if (phone.GetLevel() == 0)
  {
    GTEST_SKIP()
      << "this build has no reduction (MORPHNODE_ENABLE_REDUCTION): the phone gets the full mesh";
  }
  EXPECT_EQ(phone.GetLevel(), 1);
  EXPECT_LT(phone.GetNumberOfTriangles(), 0.8 * full.GetNumberOfTriangles());
  EXPECT_GT(phone.GetNumberOfTriangles(), 0.3 * full.GetNumberOfTriangles());
  EXPECT_GT(phone.GetLevelError(), 0.0);
  // The file reads back with the reduced mesh and every target.
  const GltfScene back = LoadGltfSceneFromMemory(phone.GetFile().data(), phone.GetFile().size());
  size_t triangles = 0;
  std::set<std::string> names;
  for (const GltfPart& part : back.Parts)
  {
    triangles += part.Triangles.size() / 3;
    for (const GltfTarget& t : part.Targets)
    {
      names.insert(t.Name);
      EXPECT_EQ(t.PositionDeltas.size(), part.Positions.size());
    }
  }
  EXPECT_EQ(triangles, phone.GetNumberOfTriangles());
  EXPECT_EQ(names.size(), phone.GetTargetNames().size());
  StreamAvatarOptions quantized = DeviceAvatarOptions(FindDeviceProfile("phone"));
  WriteForValidator(
    StreamAvatar(DefaultHead(), channels, nullptr, quantized), "stream_default_head_phone.glb");

  // A target that barely moves: pruned for the phone (1 px), kept without a bound.
  GltfScene face = DefaultHead();
  const std::string tiny = full.GetTargetNames().back();
  for (GltfPart& part : face.Parts)
  {
    for (GltfTarget& t : part.Targets)
    {
      if (t.Name == tiny)
      {
        for (float& d : t.PositionDeltas)
        {
          d *= 1e-5f;
        }
      }
    }
  }
  StreamAvatarOptions bound;
  bound.TargetPixelBound = 1.0;
  bound.QuantizeDeltas = false;
  const StreamAvatar pruned(face, channels, nullptr, bound);
  EXPECT_EQ(pruned.GetPrunedTargets(), std::vector<std::string>{ tiny });
  EXPECT_EQ(std::count(pruned.GetTargetNames().begin(), pruned.GetTargetNames().end(), tiny), 0);
  EXPECT_EQ(pruned.GetTargetNames().size() + 1, full.GetTargetNames().size());
  const StreamAvatar kept(face, channels, nullptr, false);
  EXPECT_EQ(kept.GetTargetNames().size(), full.GetTargetNames().size());
  bound.TargetPixelBound = -1.0;
  EXPECT_THROW(StreamAvatar(face, channels, nullptr, bound), InputError);
}

// The frames a timer sends: the one due, every one missed by a late timer back to the
// catch-up bound (a page still shows them), none older (counted as skipped).
TEST(StreamSession, ALateTimerSendsTheFramesAPageCanStillShow)
{
  const double frame = 1.0 / 30.0;
  DueFrames d = FramesDue(10, 10 * frame + 0.001, frame, 0.1);
  EXPECT_EQ(d.First, 10u);
  EXPECT_EQ(d.Last, 10u);
  EXPECT_FALSE(d.Late);
  d = FramesDue(10, 10 * frame - 1e-12, frame, 0.1); // a hair early: still that frame
  EXPECT_EQ(d.First, 10u);
  EXPECT_EQ(d.Last, 10u);
  d = FramesDue(10, 12 * frame + 0.01, frame, 0.1); // two frames late: 10, 11, 12
  EXPECT_TRUE(d.Late);
  EXPECT_EQ(d.First, 10u);
  EXPECT_EQ(d.Last, 12u);
  EXPECT_EQ(d.Skipped, 0u);
  d = FramesDue(10, 20 * frame + 0.01, frame, 0.1); // ten late: only the last 0.1 s
  EXPECT_TRUE(d.Late);
  EXPECT_EQ(d.Last, 20u);
  EXPECT_EQ(d.First, 17u);
  EXPECT_EQ(d.Skipped, 7u);
  d = FramesDue(10, 20 * frame + 0.01, frame, 0.0); // no catch-up: the frame due only
  EXPECT_EQ(d.First, 20u);
  EXPECT_EQ(d.Skipped, 10u);
}

// Speech the pool finished between two frames starts when it is picked up (PickUp), not at
// the next frame: its sound is stamped at the pick-up's time and leaves at once, the
// session is told (SynthesizedCallback) when the job is final, and the next frame already
// shows the mouth moving.
TEST(StreamSession, SpeechPickedUpBetweenFramesStartsThere)
{
  const SpeechOptions speech = Paper6();
  const StreamAvatar avatar(DefaultHead(), ChannelsOf(speech));
  auto synthesize = [](const std::string&)
  {
    Utterance u;
    u.Visemes = WeightTrack({ "A" }, 100.0);
    for (int f = 0; f <= 100; ++f)
    {
      u.Visemes.AppendFrame(std::vector<double>{ f < 90 ? 1.0 : 0.0 });
    }
    u.Duration = 1.0;
    u.SampleRate = 24000;
    u.Audio.assign(24000, 1000);
    return u;
  };
  StreamSession s(avatar, SelectVisemeMap(speech).GetVisemes(), synthesize, StreamSettings());
  s.SetSynthesisPool(std::make_shared<SynthesisPool>());
  std::atomic<int> told{ 0 };
  s.SetSynthesizedCallback([&]() { ++told; });
  const StreamHeader h = ParseHeader(s.Header("x", "/avatar.glb"));
  const double frame = 1.0 / 30.0;
  s.Tick(3 * frame);
  Decode(s, h);
  EXPECT_FALSE(s.PickUp(3 * frame)) << "nothing waits";
  dialog::SayCommand say;
  say.Text = "Hello.";
  s.Say(say, 3 * frame);
  EXPECT_TRUE(s.IsSynthesizing());
  for (int i = 0; i < 2000 && told == 0; ++i)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(told, 1) << "the session is told when the pool finished";
  const double between = 3 * frame + 0.01;
  ASSERT_TRUE(s.PickUp(between));
  EXPECT_FALSE(s.IsSynthesizing());
  const std::vector<std::vector<uint8_t>> messages = s.TakeMessages();
  ASSERT_GE(messages.size(), 2u);
  EXPECT_EQ(messages[0][0], 1) << "the pick-up's frame comes first";
  EXPECT_EQ(std::get<Frame>(DecodeServerMessage(messages[0].data(), messages[0].size(), &h)).Sample,
    s.SampleOf(between));
  const ServerMessage first = DecodeServerMessage(messages[1].data(), messages[1].size(), &h);
  ASSERT_TRUE(std::holds_alternative<AudioChunk>(first)) << "then the sound, leaving at once";
  EXPECT_EQ(std::get<AudioChunk>(first).Sample, s.SampleOf(between)) << "starting there";
  s.Tick(4 * frame);
  const Decoded next = Decode(s, h);
  ASSERT_EQ(next.Frames.size(), 1u);
  EXPECT_GT(Largest(next.Frames[0], h, { "A" }), 0) << "the next frame shows the speech under way";
}
