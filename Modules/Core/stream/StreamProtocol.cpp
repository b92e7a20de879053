// SPDX-License-Identifier: BSD-3-Clause
#include "stream/StreamProtocol.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace stream
{
using json = nlohmann::json;

namespace
{
void Put8(std::vector<uint8_t>& out, uint8_t v)
{
  out.push_back(v);
}
void Put16(std::vector<uint8_t>& out, uint16_t v)
{
  out.push_back(static_cast<uint8_t>(v & 0xff));
  out.push_back(static_cast<uint8_t>(v >> 8));
}
void Put32(std::vector<uint8_t>& out, uint32_t v)
{
  for (int i = 0; i < 4; ++i)
  {
    out.push_back(static_cast<uint8_t>((v >> (8 * i)) & 0xff));
  }
}

/// Reads little-endian values, checking every size first.
class Reader
{
public:
  Reader(const uint8_t* data, size_t size)
    : Data(data)
    , Size(size)
  {
  }
  void Need(size_t n, const char* what) const
  {
    if (this->Size - this->Pos < n)
    {
      throw StreamError(std::string("truncated message: no room for ") + what);
    }
  }
  uint8_t U8(const char* what)
  {
    this->Need(1, what);
    return this->Data[this->Pos++];
  }
  uint16_t U16(const char* what)
  {
    this->Need(2, what);
    const uint16_t v =
      static_cast<uint16_t>(this->Data[this->Pos] | (this->Data[this->Pos + 1] << 8));
    this->Pos += 2;
    return v;
  }
  uint32_t U32(const char* what)
  {
    this->Need(4, what);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
    {
      v |= static_cast<uint32_t>(this->Data[this->Pos + i]) << (8 * i);
    }
    this->Pos += 4;
    return v;
  }
  size_t Left() const { return this->Size - this->Pos; }
  const uint8_t* Here() const { return this->Data + this->Pos; }
  void Skip(size_t n) { this->Pos += n; }
  void End() const
  {
    if (this->Pos != this->Size)
    {
      throw StreamError("trailing bytes after the message");
    }
  }

private:
  const uint8_t* Data;
  size_t Size;
  size_t Pos = 0;
};

void CheckHeader(const StreamHeader& h)
{
  if (!(std::isfinite(h.FrameRate) && h.FrameRate > 0.0 && h.FrameRate <= 1000.0))
  {
    throw StreamError("the frame rate must be in (0, 1000]");
  }
  if (h.SampleRate < 8000 || h.SampleRate > 192000)
  {
    throw StreamError("the sample rate must be in [8000, 192000]");
  }
  if (h.Targets.size() > MaxTargets)
  {
    throw StreamError("more than " + std::to_string(MaxTargets) + " targets");
  }
  if (h.Rotations.size() > MaxRotations)
  {
    throw StreamError("more than " + std::to_string(MaxRotations) + " rotations");
  }
}
} // namespace

const char* AudioCodecName(AudioCodec codec)
{
  return codec == AudioCodec::Opus ? "opus" : "pcm16";
}

AudioCodec ParseAudioCodec(std::string_view name)
{
  if (name == "pcm16")
  {
    return AudioCodec::Pcm16;
  }
  if (name == "opus")
  {
    return AudioCodec::Opus;
  }
  throw StreamError("unknown audio codec (pcm16, opus)");
}

std::string FormatHeader(const StreamHeader& h)
{
  CheckHeader(h);
  json j;
  j["type"] = "header";
  j["protocol"] = h.Protocol;
  j["session"] = h.Session;
  j["fps"] = h.FrameRate;
  j["sampleRate"] = h.SampleRate;
  j["channels"] = 1;
  j["codec"] = AudioCodecName(h.Codec);
  j["targets"] = h.Targets;
  j["rotations"] = h.Rotations;
  j["avatar"] = h.Avatar;
  j["weightScale"] = WeightScale;
  j["rotationScale"] = RotationScale;
  return j.dump();
}

StreamHeader ParseHeader(std::string_view text)
{
  const json j = json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object())
  {
    throw StreamError("the header is not a JSON object");
  }
  auto field = [&](const char* name) -> const json&
  {
    auto it = j.find(name);
    if (it == j.end())
    {
      throw StreamError(std::string("the header has no '") + name + "'");
    }
    return *it;
  };
  if (field("type") != "header")
  {
    throw StreamError("not a header (type)");
  }
  StreamHeader h;
  try
  {
    h.Protocol = field("protocol").get<int>();
    h.Session = j.value("session", std::string());
    h.FrameRate = field("fps").get<double>();
    h.SampleRate = field("sampleRate").get<int>();
    h.Codec = ParseAudioCodec(field("codec").get<std::string>());
    h.Targets = field("targets").get<std::vector<std::string>>();
    h.Rotations = field("rotations").get<std::vector<std::string>>();
    h.Avatar = j.value("avatar", std::string());
  }
  catch (const json::exception& e)
  {
    throw StreamError(std::string("a header field has the wrong type: ") + e.what());
  }
  if (h.Protocol != ProtocolVersion)
  {
    throw StreamError("unsupported protocol version " + std::to_string(h.Protocol));
  }
  CheckHeader(h);
  return h;
}

size_t EncodedFrameSize(size_t targets, size_t rotations)
{
  return 1 + 4 + 1 + 2 * targets + 1 + 6 * rotations;
}

std::vector<uint8_t> EncodeFrame(const Frame& frame)
{
  if (frame.Targets.size() > MaxTargets)
  {
    throw StreamError("a frame holds at most " + std::to_string(MaxTargets) + " targets");
  }
  std::array<const std::array<int16_t, 3>*, MaxRotations> byIndex{};
  uint8_t mask = 0;
  for (const auto& [index, q] : frame.Rotations)
  {
    if (index >= MaxRotations || (mask & (1u << index)))
    {
      throw StreamError("a frame's rotation index is out of range or repeated");
    }
    mask = static_cast<uint8_t>(mask | (1u << index));
    byIndex[index] = &q;
  }
  std::vector<uint8_t> out;
  out.reserve(EncodedFrameSize(frame.Targets.size(), frame.Rotations.size()));
  Put8(out, static_cast<uint8_t>(MessageType::Frame));
  Put32(out, frame.Sample);
  Put8(out, static_cast<uint8_t>(frame.Targets.size()));
  for (const auto& [index, weight] : frame.Targets)
  {
    Put8(out, index);
    Put8(out, weight);
  }
  Put8(out, mask);
  for (size_t r = 0; r < MaxRotations; ++r)
  {
    if (byIndex[r])
    {
      for (int16_t c : *byIndex[r])
      {
        Put16(out, static_cast<uint16_t>(c));
      }
    }
  }
  return out;
}

std::vector<uint8_t> EncodeAudio(const AudioChunk& chunk)
{
  if (chunk.Codec == AudioCodec::Pcm16 && chunk.Payload.size() != 2u * chunk.Frames)
  {
    throw StreamError("a PCM chunk's payload must hold 2 bytes per frame");
  }
  if (chunk.Payload.size() + 8 > MaxServerMessageBytes)
  {
    throw StreamError("an audio chunk is larger than a message may be");
  }
  std::vector<uint8_t> out;
  out.reserve(8 + chunk.Payload.size());
  Put8(out, static_cast<uint8_t>(MessageType::Audio));
  Put8(out, static_cast<uint8_t>(chunk.Codec));
  Put32(out, chunk.Sample);
  Put16(out, chunk.Frames);
  out.insert(out.end(), chunk.Payload.begin(), chunk.Payload.end());
  return out;
}

std::vector<uint8_t> EncodeStop(const StopMessage& stop)
{
  std::vector<uint8_t> out;
  Put8(out, static_cast<uint8_t>(MessageType::Stop));
  Put32(out, stop.Sample);
  return out;
}

ServerMessage DecodeServerMessage(const uint8_t* data, size_t size, const StreamHeader* header)
{
  if (!data || size == 0)
  {
    throw StreamError("an empty message");
  }
  if (size > MaxServerMessageBytes)
  {
    throw StreamError("a message larger than " + std::to_string(MaxServerMessageBytes) + " bytes");
  }
  Reader r(data, size);
  const uint8_t type = r.U8("the type");
  if (type == static_cast<uint8_t>(MessageType::Frame))
  {
    Frame f;
    f.Sample = r.U32("the sample");
    const uint8_t n = r.U8("the target count");
    r.Need(2u * n, "the targets");
    f.Targets.reserve(n);
    for (uint8_t i = 0; i < n; ++i)
    {
      const uint8_t index = r.U8("a target index");
      const uint8_t weight = r.U8("a weight");
      if (header && index >= header->Targets.size())
      {
        throw StreamError("a target index beyond the header's targets");
      }
      f.Targets.emplace_back(index, weight);
    }
    const uint8_t mask = r.U8("the rotation mask");
    for (uint8_t b = 0; b < MaxRotations; ++b)
    {
      if (!(mask & (1u << b)))
      {
        continue;
      }
      if (header && b >= header->Rotations.size())
      {
        throw StreamError("a rotation index beyond the header's rotations");
      }
      std::array<int16_t, 3> q{};
      for (int c = 0; c < 3; ++c)
      {
        q[c] = static_cast<int16_t>(r.U16("a rotation"));
      }
      f.Rotations.emplace_back(b, q);
    }
    r.End();
    return f;
  }
  if (type == static_cast<uint8_t>(MessageType::Audio))
  {
    AudioChunk a;
    const uint8_t codec = r.U8("the codec");
    if (codec > static_cast<uint8_t>(AudioCodec::Opus))
    {
      throw StreamError("an unknown audio codec");
    }
    a.Codec = static_cast<AudioCodec>(codec);
    if (header && header->Codec != a.Codec)
    {
      throw StreamError("an audio chunk in another codec than the header's");
    }
    a.Sample = r.U32("the sample");
    a.Frames = r.U16("the frame count");
    if (a.Codec == AudioCodec::Pcm16 && r.Left() != 2u * a.Frames)
    {
      throw StreamError("a PCM chunk's payload does not hold 2 bytes per frame");
    }
    if (a.Codec == AudioCodec::Opus && r.Left() == 0)
    {
      throw StreamError("an Opus chunk without a packet");
    }
    a.Payload.assign(r.Here(), r.Here() + r.Left());
    r.Skip(r.Left());
    r.End();
    return a;
  }
  if (type == static_cast<uint8_t>(MessageType::Stop))
  {
    StopMessage s;
    s.Sample = r.U32("the sample");
    r.End();
    return s;
  }
  throw StreamError("an unknown message type " + std::to_string(type));
}

uint8_t QuantizeWeight(double w)
{
  if (!(w > 0.0)) // NaN and w <= 0
  {
    return 0;
  }
  return static_cast<uint8_t>(std::lround(std::min(w, 1.0) * WeightScale));
}

double DequantizeWeight(uint8_t q)
{
  return q / WeightScale;
}

std::array<int16_t, 3> QuantizeRotation(const std::array<double, 4>& q)
{
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(n) || n < 1e-12)
  {
    throw StreamError("a rotation that is not a quaternion");
  }
  const double sign = q[3] < 0.0 ? -1.0 : 1.0;
  std::array<int16_t, 3> out{};
  for (int c = 0; c < 3; ++c)
  {
    const double v = std::clamp(sign * q[c] / n, -1.0, 1.0);
    out[c] = static_cast<int16_t>(std::lround(v * RotationScale));
  }
  return out;
}

std::array<double, 4> DequantizeRotation(const std::array<int16_t, 3>& q)
{
  std::array<double, 4> r{ q[0] / RotationScale, q[1] / RotationScale, q[2] / RotationScale, 0.0 };
  const double s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
  if (s > 1.0)
  {
    const double n = std::sqrt(s);
    r[0] /= n;
    r[1] /= n;
    r[2] /= n;
  }
  else
  {
    r[3] = std::sqrt(1.0 - s);
  }
  return r;
}

dialog::ParsedLine ParseClientMessage(std::string_view message)
{
  dialog::ParsedLine p = dialog::ParseCommand(message, MaxClientMessageBytes);
  if (p.Ok() && std::holds_alternative<dialog::QuitCommand>(p.Cmd.Body))
  {
    dialog::ParsedLine refused;
    refused.Error = dialog::MakeError(dialog::reason::Rejected,
      "a stream client cannot quit the server; close the connection to end the session", p.Cmd.Id,
      "quit");
    return refused;
  }
  if (p.Ok() && !p.Cmd.Session.empty())
  {
    dialog::ParsedLine refused;
    refused.Error = dialog::MakeError(dialog::reason::UnknownField,
      "a stream client commands its own session only (no 'session' field)", p.Cmd.Id,
      dialog::CommandName(p.Cmd.Body));
    return refused;
  }
  return p;
}
} // namespace stream
} // namespace morphnode
