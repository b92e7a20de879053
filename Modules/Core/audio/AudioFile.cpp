// SPDX-License-Identifier: BSD-3-Clause
#include "audio/AudioFile.h"

#include "base/Error.h"
#include "base/File.h"
#include "base/Text.h"

#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <ostream>

namespace morphnode
{
namespace
{
/// libsndfile's virtual I/O over a byte string (reading) or a growing one (writing).
struct MemoryFile
{
  std::string* Bytes = nullptr;
  sf_count_t Position = 0;
};

sf_count_t MemoryLength(void* user)
{
  return static_cast<sf_count_t>(static_cast<MemoryFile*>(user)->Bytes->size());
}

sf_count_t MemorySeek(sf_count_t offset, int whence, void* user)
{
  auto* file = static_cast<MemoryFile*>(user);
  const sf_count_t size = static_cast<sf_count_t>(file->Bytes->size());
  sf_count_t base = 0;
  switch (whence)
  {
    case SEEK_SET:
      base = 0;
      break;
    case SEEK_CUR:
      base = file->Position;
      break;
    case SEEK_END:
      base = size;
      break;
    default:
      return -1;
  }
  if ((offset > 0 && base > std::numeric_limits<sf_count_t>::max() - offset) || base + offset < 0)
  {
    return -1;
  }
  file->Position = base + offset;
  return file->Position;
}

sf_count_t MemoryRead(void* destination, sf_count_t count, void* user)
{
  auto* file = static_cast<MemoryFile*>(user);
  const sf_count_t size = static_cast<sf_count_t>(file->Bytes->size());
  if (count <= 0 || file->Position >= size)
  {
    return 0;
  }
  const sf_count_t n = std::min(count, size - file->Position);
  std::memcpy(destination, file->Bytes->data() + file->Position, static_cast<size_t>(n));
  file->Position += n;
  return n;
}

sf_count_t MemoryWrite(const void* source, sf_count_t count, void* user)
{
  auto* file = static_cast<MemoryFile*>(user);
  if (count <= 0)
  {
    return 0;
  }
  const size_t end = static_cast<size_t>(file->Position) + static_cast<size_t>(count);
  if (end > file->Bytes->size())
  {
    file->Bytes->resize(end);
  }
  std::memcpy(file->Bytes->data() + file->Position, source, static_cast<size_t>(count));
  file->Position += count;
  return count;
}

sf_count_t MemoryTell(void* user)
{
  return static_cast<MemoryFile*>(user)->Position;
}

SF_VIRTUAL_IO MemoryIo()
{
  SF_VIRTUAL_IO io;
  io.get_filelen = MemoryLength;
  io.seek = MemorySeek;
  io.read = MemoryRead;
  io.write = MemoryWrite;
  io.tell = MemoryTell;
  return io;
}

struct SndFileCloser
{
  void operator()(SNDFILE* f) const { sf_close(f); }
};

/// Decodes an open file in blocks (the frame count in a header may lie; never trust it for
/// one big allocation).
AudioBuffer Decode(SNDFILE* file, const SF_INFO& info, const std::string& origin)
{
  if (info.channels <= 0 || info.samplerate <= 0)
  {
    throw InputError(origin + ": not a usable sound file (" + std::to_string(info.channels) +
      " channels at " + std::to_string(info.samplerate) + " Hz)");
  }
  // Decided from the header, before any decoding (docs/limits.md).
  if (info.samplerate < MinSampleRate || info.samplerate > MaxSampleRate)
  {
    throw InputError(origin + ": a sample rate of " + std::to_string(info.samplerate) +
      " Hz is outside [" + std::to_string(MinSampleRate) + ", " + std::to_string(MaxSampleRate) +
      "] Hz");
  }
  if (info.channels > MaxAudioChannels)
  {
    throw InputError(origin + ": " + std::to_string(info.channels) + " channels (at most " +
      std::to_string(MaxAudioChannels) + ")");
  }
  const size_t maximumSamples = std::min<size_t>(MaxAudioSamples,
    static_cast<size_t>(MaxAudioSeconds * info.samplerate) * static_cast<size_t>(info.channels));
  const std::string tooLong = origin + ": too long (more than " +
    text::FormatNumber(MaxAudioSeconds / 3600.0) + " h or " + std::to_string(MaxAudioSamples) +
    " samples; docs/limits.md)";
  if (info.frames > 0 && info.frames < (sf_count_t(1) << 50) &&
    static_cast<size_t>(info.frames) * static_cast<size_t>(info.channels) > maximumSamples)
  {
    throw InputError(tooLong); // the header says so; a lying header is caught while decoding
  }
  AudioBuffer audio;
  audio.SampleRate = info.samplerate;
  audio.Channels = info.channels;
  // Integer files are scaled to [-1, 1]; float files are read as they are.
  sf_command(file, SFC_SET_NORM_FLOAT, nullptr, SF_TRUE);
  constexpr sf_count_t blockFrames = 1 << 14;
  std::vector<float> block(static_cast<size_t>(blockFrames) * static_cast<size_t>(info.channels));
  for (;;)
  {
    const sf_count_t got = sf_readf_float(file, block.data(), blockFrames);
    if (got <= 0)
    {
      break;
    }
    const size_t n = static_cast<size_t>(got) * static_cast<size_t>(info.channels);
    if (audio.Samples.size() + n > maximumSamples)
    {
      throw InputError(tooLong);
    }
    audio.Samples.insert(
      audio.Samples.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(n));
  }
  if (sf_error(file) != SF_ERR_NO_ERROR)
  {
    throw InputError(origin + ": decoding failed: " + sf_strerror(file));
  }
  if (audio.Samples.empty())
  {
    throw InputError(origin + ": holds no audio (0 frames)");
  }
  for (float& s : audio.Samples)
  {
    if (!std::isfinite(s))
    {
      s = 0.0f; // a float file may hold NaN or infinities; they would poison every sum
    }
  }
  return audio;
}

void CheckWritable(const AudioBuffer& audio)
{
  if (audio.SampleRate <= 0)
  {
    throw InputError("a WAV file needs a sample rate > 0");
  }
  if (audio.Channels <= 0 || audio.Samples.size() % static_cast<size_t>(audio.Channels) != 0)
  {
    throw InputError("a WAV file needs at least one channel and whole frames");
  }
  // RIFF sizes are 32 bit: the data chunk plus the header must fit.
  if (audio.Samples.size() > (0xffffffffull - 44) / 2)
  {
    throw InputError("too many samples for a WAV file");
  }
}

} // namespace

AudioBuffer ReadAudioFile(const std::string& path)
{
  SF_INFO info;
  std::memset(&info, 0, sizeof(info));
  // A regular file (not a FIFO or device libsndfile would wait on or read for ever).
  file::CheckInputFile(path, "audio file", uint64_t(4) << 30);
  std::unique_ptr<SNDFILE, SndFileCloser> file(sf_open(path.c_str(), SFM_READ, &info));
  if (!file)
  {
    throw InputError("audio file '" + path + "' cannot be read: " + sf_strerror(nullptr));
  }
  return Decode(file.get(), info, "audio file '" + path + "'");
}

AudioBuffer ReadAudioMemory(const std::string& bytes, const std::string& origin)
{
  std::string copy = bytes; // libsndfile's virtual I/O wants a mutable user pointer
  MemoryFile memory{ &copy, 0 };
  SF_VIRTUAL_IO io = MemoryIo();
  SF_INFO info;
  std::memset(&info, 0, sizeof(info));
  std::unique_ptr<SNDFILE, SndFileCloser> file(sf_open_virtual(&io, SFM_READ, &info, &memory));
  if (!file)
  {
    throw InputError(origin + " cannot be read: " + sf_strerror(nullptr));
  }
  return Decode(file.get(), info, origin);
}

namespace
{
/// Opens `path` (or, when empty, a memory file appended to `out`) for 16-bit WAV output and
/// hands it to `write`.
template <typename Writer>
void WriteWavWith(
  const std::string& path, std::ostream* out, int sampleRate, int channels, Writer&& write)
{
  SF_INFO info;
  std::memset(&info, 0, sizeof(info));
  info.samplerate = sampleRate;
  info.channels = channels;
  info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
  if (out == nullptr)
  {
    // Beside the target, renamed onto it when complete (base/File.h).
    file::SafeOutput target(path, "WAV file");
    std::unique_ptr<SNDFILE, SndFileCloser> file(
      sf_open(target.GetTemporaryPath().c_str(), SFM_WRITE, &info));
    if (!file)
    {
      throw InputError("cannot write WAV file '" + path + "': " + sf_strerror(nullptr));
    }
    write(file.get(), "WAV file '" + path + "'");
    if (sf_close(file.release()) != 0) // the header's sizes are written on close
    {
      throw InputError("cannot write WAV file '" + path + "' (the disk is full?)");
    }
    target.Commit();
    return;
  }
  std::string bytes;
  {
    MemoryFile memory{ &bytes, 0 };
    SF_VIRTUAL_IO io = MemoryIo();
    std::unique_ptr<SNDFILE, SndFileCloser> file(sf_open_virtual(&io, SFM_WRITE, &info, &memory));
    if (!file)
    {
      throw InputError(std::string("cannot write WAV data: ") + sf_strerror(nullptr));
    }
    write(file.get(), "WAV data");
  } // closing writes the final header sizes
  out->write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!*out)
  {
    throw InputError("error while writing WAV data to a stream");
  }
}

void WriteFloat(const AudioBuffer& audio, const std::string& path, std::ostream* out)
{
  CheckWritable(audio);
  WriteWavWith(path, out, audio.SampleRate, audio.Channels,
    [&audio](SNDFILE* file, const std::string& origin)
    {
      sf_command(file, SFC_SET_CLIPPING, nullptr, SF_TRUE);
      const sf_count_t frames = static_cast<sf_count_t>(audio.GetFrameCount());
      if (frames > 0 && sf_writef_float(file, audio.Samples.data(), frames) != frames)
      {
        throw InputError("error while writing " + origin + ": " + sf_strerror(file));
      }
    });
}

void WriteShort(
  const std::vector<int16_t>& samples, int sampleRate, const std::string& path, std::ostream* out)
{
  if (sampleRate <= 0)
  {
    throw InputError("a WAV file needs a sample rate > 0");
  }
  if (samples.size() > (0xffffffffull - 44) / 2)
  {
    throw InputError("too many samples for a WAV file");
  }
  WriteWavWith(path, out, sampleRate, 1,
    [&samples](SNDFILE* file, const std::string& origin)
    {
      const sf_count_t frames = static_cast<sf_count_t>(samples.size());
      if (frames > 0 && sf_writef_short(file, samples.data(), frames) != frames)
      {
        throw InputError("error while writing " + origin + ": " + sf_strerror(file));
      }
    });
}
} // namespace

void WriteWavFile(const std::string& path, const AudioBuffer& audio)
{
  WriteFloat(audio, path, nullptr);
}

void WriteWav(std::ostream& out, const AudioBuffer& audio)
{
  WriteFloat(audio, std::string(), &out);
}

void WriteWavFile(const std::string& path, const std::vector<int16_t>& samples, int sampleRate)
{
  WriteShort(samples, sampleRate, path, nullptr);
}

void WriteWav(std::ostream& out, const std::vector<int16_t>& samples, int sampleRate)
{
  WriteShort(samples, sampleRate, std::string(), &out);
}
} // namespace morphnode
