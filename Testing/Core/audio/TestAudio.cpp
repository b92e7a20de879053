// SPDX-License-Identifier: BSD-3-Clause
// The audio concept: libsndfile reading and writing, mono mixing, resampling, bad files.
#include "audio/AudioBuffer.h"
#include "audio/AudioFile.h"
#include "audio/Resample.h"
#include "base/Error.h"

#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

using namespace morphnode;

namespace
{
const double Pi = 3.14159265358979323846;

std::string OutPath(const std::string& name)
{
  return std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/audio_" + name;
}

AudioBuffer Sine(double hz, int rate, double seconds, int channels = 1)
{
  AudioBuffer a;
  a.SampleRate = rate;
  a.Channels = channels;
  const size_t frames = static_cast<size_t>(seconds * rate);
  for (size_t f = 0; f < frames; ++f)
  {
    for (int c = 0; c < channels; ++c)
    {
      // channel c at (c + 1) times the amplitude 0.2, so mixing can be checked
      a.Samples.push_back(static_cast<float>(0.2 * (c + 1) * std::sin(2 * Pi * hz * f / rate)));
    }
  }
  return a;
}

/// Writes with libsndfile directly in a format the project itself never writes.
void WriteWithSndfile(const std::string& path, const AudioBuffer& a, int format)
{
  SF_INFO info;
  std::memset(&info, 0, sizeof(info));
  info.samplerate = a.SampleRate;
  info.channels = a.Channels;
  info.format = format;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  ASSERT_NE(f, nullptr) << sf_strerror(nullptr);
  sf_writef_float(f, a.Samples.data(), static_cast<sf_count_t>(a.GetFrameCount()));
  sf_close(f);
}

double MaxAbsDifference(
  const std::vector<float>& a, const std::vector<float>& b, size_t from, size_t to)
{
  double m = 0.0;
  for (size_t i = from; i < to && i < a.size() && i < b.size(); ++i)
  {
    m = std::max(m, std::abs(static_cast<double>(a[i]) - b[i]));
  }
  return m;
}
} // namespace

TEST(Audio, Int16WavRoundTripIsExact)
{
  std::vector<int16_t> samples = { 0, 1, -1, 32767, -32768, 1234, -4321 };
  const std::string path = OutPath("int16.wav");
  WriteWavFile(path, samples, 22050);
  const AudioBuffer a = ReadAudioFile(path);
  EXPECT_EQ(a.SampleRate, 22050);
  EXPECT_EQ(a.Channels, 1);
  EXPECT_EQ(ToInt16Mono(a), samples);
  // A plain 44-byte RIFF header: what players and Rhubarb expect.
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_EQ(bytes.str().size(), 44 + 2 * samples.size());
  EXPECT_EQ(bytes.str().substr(0, 4), "RIFF");
}

TEST(Audio, StreamAndFileWritesAgree)
{
  const AudioBuffer a = Sine(440, 16000, 0.1, 2);
  std::ostringstream stream;
  WriteWav(stream, a);
  WriteWavFile(OutPath("stereo.wav"), a);
  std::ifstream in(OutPath("stereo.wav"), std::ios::binary);
  std::stringstream file;
  file << in.rdbuf();
  EXPECT_EQ(stream.str(), file.str());
  const AudioBuffer back = ReadAudioMemory(stream.str());
  EXPECT_EQ(back.Channels, 2);
  EXPECT_EQ(back.GetFrameCount(), a.GetFrameCount());
  EXPECT_LT(MaxAbsDifference(back.Samples, a.Samples, 0, a.Samples.size()), 1.0 / 16000);
}

TEST(Audio, ReadsFlacAndOggAtTheirOwnRateAndChannels)
{
  const AudioBuffer a = Sine(300, 44100, 0.5, 2);
  WriteWithSndfile(OutPath("sine.flac"), a, SF_FORMAT_FLAC | SF_FORMAT_PCM_16);
  WriteWithSndfile(OutPath("sine.ogg"), a, SF_FORMAT_OGG | SF_FORMAT_VORBIS);
  const AudioBuffer flac = ReadAudioFile(OutPath("sine.flac"));
  EXPECT_EQ(flac.SampleRate, 44100);
  EXPECT_EQ(flac.Channels, 2);
  EXPECT_EQ(flac.GetFrameCount(), a.GetFrameCount());
  EXPECT_LT(MaxAbsDifference(flac.Samples, a.Samples, 0, a.Samples.size()), 1e-4); // lossless
  const AudioBuffer ogg = ReadAudioFile(OutPath("sine.ogg"));
  EXPECT_EQ(ogg.SampleRate, 44100);
  EXPECT_EQ(ogg.Channels, 2);
  EXPECT_NEAR(ogg.GetDuration(), 0.5, 0.01);
  // Lossy, but the tone and its level survive.
  EXPECT_NEAR(RootMeanSquare(ogg), RootMeanSquare(a), 0.02);
}

TEST(Audio, MixToMonoAveragesChannels)
{
  const AudioBuffer stereo = Sine(200, 8000, 0.05, 2);
  const AudioBuffer mono = MixToMono(stereo);
  ASSERT_EQ(mono.Channels, 1);
  ASSERT_EQ(mono.GetFrameCount(), stereo.GetFrameCount());
  for (size_t f = 0; f < mono.GetFrameCount(); ++f)
  {
    EXPECT_FLOAT_EQ(mono.Samples[f], 0.5f * (stereo.Samples[2 * f] + stereo.Samples[2 * f + 1]));
  }
  AudioBuffer broken = stereo;
  broken.Samples.pop_back();
  EXPECT_THROW(MixToMono(broken), InputError);
  broken.Channels = 0;
  EXPECT_THROW(MixToMono(broken), InputError);
}

TEST(Audio, ResampleKeepsToneAndLength)
{
  const AudioBuffer a = Sine(440, 22050, 1.0);
  const AudioBuffer b = Resample(a, 16000);
  EXPECT_EQ(b.SampleRate, 16000);
  EXPECT_EQ(b.GetFrameCount(), 16000u);
  // Compare with the tone computed at the new rate, away from the edges.
  const AudioBuffer expected = Sine(440, 16000, 1.0);
  EXPECT_LT(MaxAbsDifference(b.Samples, expected.Samples, 1000, 15000), 0.01);
  // Up-sampling, stereo, every quality.
  for (ResampleQuality q :
    { ResampleQuality::Quick, ResampleQuality::Medium, ResampleQuality::High })
  {
    const AudioBuffer up = Resample(Sine(100, 8000, 0.25, 2), 48000, q);
    EXPECT_EQ(up.Channels, 2);
    EXPECT_EQ(up.GetFrameCount(), 12000u);
    EXPECT_NEAR(RootMeanSquare(up), RootMeanSquare(Sine(100, 8000, 0.25, 2)), 0.01);
  }
  // A tone above the new Nyquist frequency is filtered out, not folded back.
  const AudioBuffer high = Resample(Sine(7000, 22050, 0.5), 8000);
  EXPECT_LT(RootMeanSquare(high), 0.01);
  EXPECT_THROW(Resample(a, 0), InputError);
}

TEST(Audio, BadFilesAreClearErrors)
{
  EXPECT_THROW(ReadAudioFile(OutPath("no-such-file.wav")), InputError);
  {
    std::ofstream(OutPath("empty.wav"), std::ios::binary);
  }
  EXPECT_THROW(ReadAudioFile(OutPath("empty.wav")), InputError);
  {
    std::ofstream(OutPath("text.wav"), std::ios::binary) << "this is not a sound file at all\n";
  }
  try
  {
    ReadAudioFile(OutPath("text.wav"));
    FAIL() << "a text file read as audio";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("text.wav"), std::string::npos) << e.what();
  }
  // A valid WAV header with no frames: an error, not an empty success.
  WriteWavFile(OutPath("zero.wav"), std::vector<int16_t>{}, 16000);
  EXPECT_THROW(ReadAudioFile(OutPath("zero.wav")), InputError);
  // Truncated in the middle of the header.
  std::ostringstream whole;
  WriteWav(whole, std::vector<int16_t>(100, 7), 16000);
  EXPECT_THROW(ReadAudioMemory(whole.str().substr(0, 20)), InputError);
  EXPECT_THROW(ReadAudioMemory(""), InputError);
  // Bad buffers to write.
  AudioBuffer bad;
  bad.SampleRate = 0;
  bad.Channels = 1;
  std::ostringstream sink;
  EXPECT_THROW(WriteWav(sink, bad), InputError);
  EXPECT_THROW(WriteWav(sink, std::vector<int16_t>{ 1 }, -5), InputError);
  EXPECT_THROW(WriteWavFile("/no/such/folder/x.wav", std::vector<int16_t>{ 1 }, 8000), InputError);
}

// Issue 29: a WAV whose header says 1 Hz was resampled 16,000x (3.6 GB) and crashed in
// libsoxr. Rates, channels and lengths are decided before decoding or resampling.
TEST(Audio, LimitsAreDecidedBeforeTheWork)
{
  std::ostringstream oneHertz;
  WriteWav(oneHertz, std::vector<int16_t>(1000, 7), 1);
  try
  {
    ReadAudioMemory(oneHertz.str(), "bomb.wav");
    ADD_FAILURE() << "a 1 Hz file was read";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(
      std::string(e.what()).find("bomb.wav: a sample rate of 1 Hz is outside [4000, 384000] Hz"),
      std::string::npos)
      << e.what();
  }
  std::ostringstream fine;
  WriteWav(fine, std::vector<int16_t>(100, 7), MinSampleRate);
  EXPECT_EQ(ReadAudioMemory(fine.str()).SampleRate, MinSampleRate);
  // A resampling whose result would pass MaxAudioSamples: refused before allocating it.
  AudioBuffer low;
  low.SampleRate = MinSampleRate;
  low.Channels = 1;
  low.Samples.assign(size_t(1) << 22, 0.0f);
  EXPECT_THROW(Resample(low, MaxSampleRate), InputError);
}
