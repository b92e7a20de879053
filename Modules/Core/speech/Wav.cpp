// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Wav.h"

#include "base/Error.h"

#include <fstream>
#include <ostream>

namespace morphnode
{
namespace
{
void Put16(std::ostream& out, uint16_t v)
{
  const char bytes[2] = { static_cast<char>(v & 0xff), static_cast<char>(v >> 8) };
  out.write(bytes, 2);
}

void Put32(std::ostream& out, uint32_t v)
{
  const char bytes[4] = { static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
    static_cast<char>((v >> 16) & 0xff), static_cast<char>(v >> 24) };
  out.write(bytes, 4);
}
} // namespace

void WriteWav(std::ostream& out, const std::vector<int16_t>& samples, int sampleRate)
{
  if (sampleRate <= 0)
  {
    throw InputError("a WAV file needs a sample rate > 0");
  }
  // RIFF sizes are 32 bit: the data chunk plus 36 header bytes must fit.
  if (samples.size() > (0xffffffffull - 36) / 2)
  {
    throw InputError("too many samples for a WAV file");
  }
  const uint32_t dataBytes = static_cast<uint32_t>(samples.size() * 2);
  out.write("RIFF", 4);
  Put32(out, 36 + dataBytes);
  out.write("WAVE", 4);
  out.write("fmt ", 4);
  Put32(out, 16);                                    // PCM format chunk size
  Put16(out, 1);                                     // PCM
  Put16(out, 1);                                     // mono
  Put32(out, static_cast<uint32_t>(sampleRate));
  Put32(out, static_cast<uint32_t>(sampleRate) * 2); // bytes per second
  Put16(out, 2);                                     // block align
  Put16(out, 16);                                    // bits per sample
  out.write("data", 4);
  Put32(out, dataBytes);
  for (int16_t s : samples)
  {
    Put16(out, static_cast<uint16_t>(s));
  }
}

void WriteWavFile(const std::string& path, const std::vector<int16_t>& samples, int sampleRate)
{
  std::ofstream out(path, std::ios::binary);
  if (!out)
  {
    throw InputError("cannot write WAV file '" + path + "'");
  }
  WriteWav(out, samples, sampleRate);
  if (!out)
  {
    throw InputError("error while writing WAV file '" + path + "'");
  }
}
} // namespace morphnode
