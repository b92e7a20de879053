// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: external speech inline in a dialog command (docs/dialog.md), as the avatar
// takes it: `say` with `audio_base64` and `timings_inline` parsed (dialog::ParseCommand), the
// recording decoded from memory (ReadAudioMemory, libsndfile's virtual I/O) and, with inline
// timings, the utterance built from both (SpeakRecording's timing route). Also the base64
// decoder on the raw input: what it accepts re-encodes to the same bytes and decodes the same
// with Boost.Archive's decoder (an implementation we did not write).
#include "align/RecordingSpeech.h"
#include "audio/AudioFile.h"
#include "base/Base64.h"
#include "base/Error.h"
#include "dialog/DialogProtocol.h"

#include <boost/archive/iterators/binary_from_base64.hpp>
#include <boost/archive/iterators/transform_width.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>

namespace
{
using namespace morphnode;

std::string BoostDecode(const std::string& text) // no padding, no whitespace
{
  using namespace boost::archive::iterators;
  using Iterator = transform_width<binary_from_base64<std::string::const_iterator>, 8, 6>;
  std::string out(Iterator(text.cbegin()), Iterator(text.cend()));
  out.resize(text.size() * 6 / 8);
  return out;
}

void CheckBase64(std::string_view input)
{
  std::string bytes;
  try
  {
    bytes = base64::Decode(input, "fuzz input");
  }
  catch (const InputError&)
  {
    return;
  }
  std::string alphabet; // the input without whitespace and padding
  for (char c : input)
  {
    if (c != ' ' && c != '\t' && c != '\r' && c != '\n' && c != '=')
    {
      alphabet += c;
    }
  }
  if (alphabet.size() * 6 / 8 != bytes.size() || BoostDecode(alphabet) != bytes ||
    base64::Decode(base64::Encode(bytes)) != bytes)
  {
    std::abort();
  }
}

void CheckCommand(std::string_view line)
{
  const dialog::ParsedLine p = dialog::ParseCommand(line);
  if (!p.Ok() || !std::holds_alternative<dialog::SayCommand>(p.Cmd.Body))
  {
    return;
  }
  const dialog::SayCommand& say = std::get<dialog::SayCommand>(p.Cmd.Body);
  if (!say.HasRecording() && (!say.TimingsData.empty() || !say.Timings.empty()))
  {
    std::abort(); // timings only with a recording
  }
  if (say.AudioData.empty())
  {
    return;
  }
  if (!say.Audio.empty())
  {
    std::abort(); // a recording by name or inline, never both
  }
  try
  {
    const AudioBuffer audio = ReadAudioMemory(say.AudioData, "'audio_base64'");
    if (audio.IsEmpty() || audio.Channels <= 0 || audio.SampleRate <= 0)
    {
      std::abort();
    }
    if (say.TimingsData.empty())
    {
      return; // (the transcript and recognition routes are not the parser's business)
    }
    RecordingOptions options;
    options.Route = RecordingRoute::TimingFile;
    options.TimingData = say.TimingsData;
    if (!say.TimingsFormat.empty())
    {
      options.Timing.Format = ParseTimingFormat(say.TimingsFormat);
    }
    const Utterance u = SpeakRecording(audio, SpeechOptions(), options);
    if (u.Audio.empty() || u.SampleRate <= 0 || !std::isfinite(u.Duration))
    {
      std::abort();
    }
  }
  catch (const InputError&)
  {
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  CheckBase64(input);
  CheckCommand(input);
  return 0;
}
