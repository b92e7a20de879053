// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file StreamProtocol.h
/// @brief The avatar stream (docs/streaming.md): what a server sends a remote face (a
/// browser page, a game engine, a phone app) and what the face sends back.
///
/// Server to client, over one ordered reliable channel (a WebSocket):
/// - once, a text message: the header (FormatHeader), JSON: the protocol version, the
///   target names (a frame's target index points into them), the frame rate, the audio
///   clock's sample rate and codec, the rotation nodes, where the avatar file is;
/// - binary messages, each one of (EncodeFrame, EncodeAudio, EncodeStop):
///   - a frame: the audio-clock sample it is shown at, only the targets the optimizer
///     kept (index + 8-bit weight; a target not in the frame weighs 0) and the rotations
///     that changed since the last frame (quantized unit quaternions);
///   - an audio chunk: its first sample's index on the same clock, PCM 16-bit or Opus;
///   - a stop: everything queued from its sample on (frames and audio) is void at once;
/// - text messages: the dialog protocol's events (dialog/DialogProtocol.h, FormatEvent).
///
/// Client to server: text messages, each one dialog command (`say`, `gesture`, `mood`,
/// `look_at`, `stop`) as dialog::ParseCommand reads them; a page may not `quit` the server.
///
/// Little-endian throughout. Every decoder checks sizes before reading and throws
/// StreamError for anything malformed; it never reads outside the bytes it is given.

#include "base/Error.h"
#include "dialog/DialogProtocol.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace morphnode
{
namespace stream
{
/// A malformed or unsupported stream message.
class StreamError : public InputError
{
public:
  using InputError::InputError;
};

/// Protocol version (the header's `protocol`).
constexpr int ProtocolVersion = 1;
/// At most this many targets in a stream (a frame's index is one byte).
constexpr size_t MaxTargets = 255;
/// At most this many rotation nodes (a frame's rotation mask is one byte).
constexpr size_t MaxRotations = 8;
/// Longest client message (bytes): a command is a short JSON object.
constexpr size_t MaxClientMessageBytes = 4096;
/// Longest server binary message a client needs to accept (an audio chunk of 1 s of PCM
/// at 48 kHz is 96 kB).
constexpr size_t MaxServerMessageBytes = 128 * 1024;
/// A weight w in [0, 1] travels as round(w * WeightScale) in one byte.
constexpr double WeightScale = 255.0;
/// A quaternion component q in [-1, 1] travels as round(q * RotationScale), int16.
constexpr double RotationScale = 32767.0;

enum class MessageType : uint8_t
{
  Frame = 1,
  Audio = 2,
  Stop = 3
};

enum class AudioCodec : uint8_t
{
  Pcm16 = 0, ///< signed 16-bit little-endian, mono
  Opus = 1   ///< one Opus packet per chunk (RFC 6716), mono
};
/// "pcm16" or "opus".
const char* AudioCodecName(AudioCodec codec);
/// The codec of a name; StreamError for an unknown one.
AudioCodec ParseAudioCodec(std::string_view name);

/// The header: sent once, first, as a JSON text message.
struct StreamHeader
{
  int Protocol = ProtocolVersion;
  std::string Session;     ///< the session's id (for logs)
  double FrameRate = 30.0; ///< frames per second (> 0)
  int SampleRate = 24000;  ///< the audio clock (Hz); frames are stamped on it
  AudioCodec Codec = AudioCodec::Pcm16;
  std::vector<std::string> Targets;   ///< frame target index -> name (the avatar's targets)
  std::vector<std::string> Rotations; ///< rotation index -> node name (e.g. HeadRotation)
  std::string Avatar;                 ///< where the avatar file is (a path on the server)
};
/// {"type":"header","protocol":1,...}. StreamError when the header breaks a limit.
std::string FormatHeader(const StreamHeader& header);
/// The header back (for clients and tests). StreamError for anything malformed.
StreamHeader ParseHeader(std::string_view json);

/// One picture of the face on the audio clock.
struct Frame
{
  uint32_t Sample = 0; ///< the audio-clock sample it is shown at
  /// The kept targets: index into the header's targets, weight in [0, 255] (w * 255).
  std::vector<std::pair<uint8_t, uint8_t>> Targets;
  /// The rotations sent in this frame: index into the header's rotations, and the unit
  /// quaternion's x, y, z * 32767 with w >= 0 (w = sqrt(1 - x^2 - y^2 - z^2)).
  std::vector<std::pair<uint8_t, std::array<int16_t, 3>>> Rotations;
};
/// type, u32 sample, u8 count, count x (u8 index, u8 weight), u8 rotation mask, per set
/// bit (ascending) 3 x i16. StreamError for more than MaxTargets targets, rotation
/// indices >= MaxRotations or repeated.
std::vector<uint8_t> EncodeFrame(const Frame& frame);
/// Bytes of EncodeFrame(frame) without making them.
size_t EncodedFrameSize(size_t targets, size_t rotations);

/// A chunk of the speech's sound.
struct AudioChunk
{
  AudioCodec Codec = AudioCodec::Pcm16;
  uint32_t Sample = 0;          ///< the index of its first sample on the audio clock
  uint16_t Frames = 0;          ///< samples it holds (after decoding, for Opus)
  std::vector<uint8_t> Payload; ///< PCM: 2 * Frames bytes; Opus: one packet
};
/// type, u8 codec, u32 sample, u16 frames, payload.
std::vector<uint8_t> EncodeAudio(const AudioChunk& chunk);

/// Everything from Sample on is void (the speech was stopped).
struct StopMessage
{
  uint32_t Sample = 0;
};
std::vector<uint8_t> EncodeStop(const StopMessage& stop);

using ServerMessage = std::variant<Frame, AudioChunk, StopMessage>;
/// A binary server message back. `header` bounds the target and rotation indices (null:
/// not checked). StreamError for anything malformed (also trailing bytes).
ServerMessage DecodeServerMessage(
  const uint8_t* data, size_t size, const StreamHeader* header = nullptr);

// ---- quantization ------------------------------------------------------------------------
/// round(clamp(w, 0, 1) * 255); NaN gives 0.
uint8_t QuantizeWeight(double w);
double DequantizeWeight(uint8_t q);
/// A unit quaternion (x, y, z, w) to the wire's three components (the sign made w >= 0;
/// normalized first). StreamError for a zero or non-finite quaternion.
std::array<int16_t, 3> QuantizeRotation(const std::array<double, 4>& q);
std::array<double, 4> DequantizeRotation(const std::array<int16_t, 3>& q);

// ---- client messages ---------------------------------------------------------------------
/// One client text message -> a dialog command, or an error event to send back: the dialog
/// protocol's own parser (dialog::ParseCommand, its reasons), with MaxClientMessageBytes as
/// the limit and `quit` refused (reason rejected: a page ends its session by closing).
dialog::ParsedLine ParseClientMessage(std::string_view message);
} // namespace stream
} // namespace morphnode
