// SPDX-License-Identifier: BSD-3-Clause
// The avatar stream's wire format (stream/StreamProtocol.h): round trips, every truncation
// and bad byte refused, quantization bounds, client messages through the dialog parser.
#include "stream/StreamProtocol.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace morphnode::stream;
namespace dialog = morphnode::dialog;

namespace
{
StreamHeader SmallHeader()
{
  StreamHeader h;
  h.Session = "t";
  h.Targets = { "A", "E", "O", "jawOpen" };
  h.Rotations = { "HeadRotation", "EyeLeftRotation", "EyeRightRotation" };
  h.Avatar = "/avatar.glb";
  return h;
}
} // namespace

TEST(StreamProtocol, HeaderRoundTrip)
{
  StreamHeader h = SmallHeader();
  h.Codec = AudioCodec::Opus;
  h.FrameRate = 25.0;
  const StreamHeader back = ParseHeader(FormatHeader(h));
  EXPECT_EQ(back.Targets, h.Targets);
  EXPECT_EQ(back.Rotations, h.Rotations);
  EXPECT_EQ(back.Codec, AudioCodec::Opus);
  EXPECT_EQ(back.SampleRate, h.SampleRate);
  EXPECT_DOUBLE_EQ(back.FrameRate, 25.0);
  EXPECT_EQ(back.Avatar, "/avatar.glb");
  // Limits and malformed headers.
  StreamHeader many = h;
  many.Targets.assign(MaxTargets + 1, "x");
  EXPECT_THROW(FormatHeader(many), StreamError);
  EXPECT_THROW(ParseHeader("not json"), StreamError);
  EXPECT_THROW(ParseHeader("[1]"), StreamError);
  EXPECT_THROW(
    ParseHeader(
      R"({"type":"header","protocol":2,"fps":30,"sampleRate":24000,"codec":"pcm16","targets":[],"rotations":[]})"),
    StreamError);
  EXPECT_THROW(
    ParseHeader(
      R"({"type":"header","protocol":1,"fps":30,"sampleRate":24000,"codec":"mp3","targets":[],"rotations":[]})"),
    StreamError);
  EXPECT_THROW(
    ParseHeader(
      R"({"type":"header","protocol":1,"fps":"x","sampleRate":24000,"codec":"pcm16","targets":[],"rotations":[]})"),
    StreamError);
}

TEST(StreamProtocol, FrameRoundTripAndSize)
{
  Frame f;
  f.Sample = 0x12345678u;
  f.Targets = { { 0, 255 }, { 3, 17 } };
  f.Rotations = { { 2, { { 1, -2, 3 } } }, { 0, { { -32767, 0, 32767 } } } };
  const auto bytes = EncodeFrame(f);
  EXPECT_EQ(bytes.size(), EncodedFrameSize(2, 2));
  EXPECT_EQ(bytes.size(), 7u + 4u + 12u);
  const StreamHeader h = SmallHeader();
  const auto m = DecodeServerMessage(bytes.data(), bytes.size(), &h);
  ASSERT_TRUE(std::holds_alternative<Frame>(m));
  const Frame& g = std::get<Frame>(m);
  EXPECT_EQ(g.Sample, f.Sample);
  EXPECT_EQ(g.Targets, f.Targets);
  ASSERT_EQ(g.Rotations.size(), 2u); // in index order
  EXPECT_EQ(g.Rotations[0].first, 0);
  EXPECT_EQ(g.Rotations[0].second, (std::array<int16_t, 3>{ { -32767, 0, 32767 } }));
  EXPECT_EQ(g.Rotations[1].first, 2);
  // Every truncation and a trailing byte are refused.
  for (size_t n = 0; n < bytes.size(); ++n)
  {
    EXPECT_THROW(DecodeServerMessage(bytes.data(), n, &h), StreamError) << n;
  }
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_THROW(DecodeServerMessage(longer.data(), longer.size(), &h), StreamError);
  // Indices beyond the header's lists.
  Frame bad;
  bad.Targets = { { 4, 1 } };
  const auto b1 = EncodeFrame(bad);
  EXPECT_THROW(DecodeServerMessage(b1.data(), b1.size(), &h), StreamError);
  EXPECT_NO_THROW(DecodeServerMessage(b1.data(), b1.size(), nullptr));
  Frame badRotation;
  badRotation.Rotations = { { 3, { { 0, 0, 0 } } } };
  const auto b2 = EncodeFrame(badRotation);
  EXPECT_THROW(DecodeServerMessage(b2.data(), b2.size(), &h), StreamError);
  Frame repeated;
  repeated.Rotations = { { 1, { { 0, 0, 0 } } }, { 1, { { 0, 0, 0 } } } };
  EXPECT_THROW(EncodeFrame(repeated), StreamError);
}

TEST(StreamProtocol, AudioAndStop)
{
  AudioChunk a;
  a.Sample = 24000;
  a.Frames = 3;
  a.Payload = { 1, 0, 2, 0, 0xff, 0xff };
  const auto bytes = EncodeAudio(a);
  EXPECT_EQ(bytes.size(), 8u + 6u);
  const auto m = DecodeServerMessage(bytes.data(), bytes.size());
  ASSERT_TRUE(std::holds_alternative<AudioChunk>(m));
  EXPECT_EQ(std::get<AudioChunk>(m).Payload, a.Payload);
  EXPECT_EQ(std::get<AudioChunk>(m).Sample, 24000u);
  a.Frames = 4; // payload no longer matches
  EXPECT_THROW(EncodeAudio(a), StreamError);
  auto odd = bytes;
  odd.pop_back();
  EXPECT_THROW(DecodeServerMessage(odd.data(), odd.size()), StreamError);
  StreamHeader opus = SmallHeader();
  opus.Codec = AudioCodec::Opus;
  EXPECT_THROW(
    DecodeServerMessage(bytes.data(), bytes.size(), &opus), StreamError); // codec differs

  const auto stop = EncodeStop({ 4800 });
  EXPECT_EQ(stop.size(), 5u);
  const auto s = DecodeServerMessage(stop.data(), stop.size());
  ASSERT_TRUE(std::holds_alternative<StopMessage>(s));
  EXPECT_EQ(std::get<StopMessage>(s).Sample, 4800u);
  const uint8_t unknown[] = { 9, 0, 0, 0, 0 };
  EXPECT_THROW(DecodeServerMessage(unknown, sizeof unknown), StreamError);
  EXPECT_THROW(DecodeServerMessage(nullptr, 0), StreamError);
}

TEST(StreamProtocol, Quantization)
{
  EXPECT_EQ(QuantizeWeight(0.0), 0);
  EXPECT_EQ(QuantizeWeight(-0.3), 0);
  EXPECT_EQ(QuantizeWeight(std::nan("")), 0);
  EXPECT_EQ(QuantizeWeight(1.7), 255);
  EXPECT_EQ(QuantizeWeight(0.5), 128);
  for (int i = 0; i <= 100; ++i)
  {
    const double w = i / 100.0;
    EXPECT_LE(std::abs(DequantizeWeight(QuantizeWeight(w)) - w), 0.5 / 255.0 + 1e-12);
  }
  // A rotation and its negative quantize alike (w >= 0); the round trip is close.
  const double a = 0.3;
  const std::array<double, 4> q{ { std::sin(a) * 0.6, std::sin(a) * 0.8, 0.0, std::cos(a) } };
  const std::array<double, 4> minus{ { -q[0], -q[1], -q[2], -q[3] } };
  EXPECT_EQ(QuantizeRotation(q), QuantizeRotation(minus));
  const auto back = DequantizeRotation(QuantizeRotation(q));
  for (int c = 0; c < 4; ++c)
  {
    EXPECT_NEAR(back[c], q[c], 1e-4);
  }
  EXPECT_THROW(QuantizeRotation({ { 0, 0, 0, 0 } }), StreamError);
  EXPECT_THROW(QuantizeRotation({ { std::nan(""), 0, 0, 1 } }), StreamError);
}

TEST(StreamProtocol, ClientMessagesAreDialogCommands)
{
  const auto say = ParseClientMessage(R"({"cmd":"say","text":"Hello","id":"a"})");
  ASSERT_TRUE(say.Ok());
  EXPECT_EQ(std::get<dialog::SayCommand>(say.Cmd.Body).Text, "Hello");
  const auto quit = ParseClientMessage(R"({"cmd":"quit","id":7})");
  ASSERT_FALSE(quit.Ok());
  EXPECT_EQ(quit.Error.Reason, dialog::reason::Rejected);
  EXPECT_EQ(quit.Error.Id, "7");
  EXPECT_EQ(ParseClientMessage("{{{").Error.Reason, dialog::reason::Malformed);
  const std::string huge =
    R"({"cmd":"say","text":")" + std::string(MaxClientMessageBytes, 'a') + "\"}";
  EXPECT_EQ(ParseClientMessage(huge).Error.Reason, dialog::reason::TooLong);
  EXPECT_TRUE(ParseClientMessage(R"({"cmd":"look_at","yaw":10,"pitch":-5})").Ok());
  EXPECT_TRUE(ParseClientMessage(R"({"cmd":"stop"})").Ok());
}
