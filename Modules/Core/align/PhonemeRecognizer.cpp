// SPDX-License-Identifier: BSD-3-Clause
#include "align/PhonemeRecognizer.h"

#include "audio/Resample.h"
#include "base/Error.h"
#include "speech/PhoneSets.h"

#if MORPHNODE_HAVE_POCKETSPHINX
#include <pocketsphinx.h>
#endif

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

namespace morphnode
{
bool IsPhonemeRecognitionAvailable()
{
  return MORPHNODE_HAVE_POCKETSPHINX != 0;
}

PhonemeRecognition RecognizePhonemes(
  const AudioBuffer& recording, const RecognitionOptions& options)
{
  if (recording.IsEmpty() || recording.SampleRate <= 0)
  {
    throw InputError("the recording is empty");
  }
#if MORPHNODE_HAVE_POCKETSPHINX
  namespace fs = std::filesystem;
  const std::string folder = options.ModelDirectory.empty()
    ? std::string(MORPHNODE_POCKETSPHINX_MODEL_DIR)
    : options.ModelDirectory;
  const std::string hmm = (fs::path(folder) / "en-us").string();
  const std::string lm = (fs::path(folder) / "en-us-phone.lm.bin").string();
  std::error_code ignored;
  if (!fs::is_directory(hmm, ignored) || !fs::is_regular_file(lm, ignored))
  {
    throw InputError("phoneme recognition needs the PocketSphinx en-us model: '" + hmm + "' and '" +
      lm + "' (Debian: pocketsphinx-en-us)");
  }
  const std::string weight = std::to_string(options.LanguageWeight);
  cmd_ln_t* config = cmd_ln_init(nullptr, ps_args(), TRUE, "-hmm", hmm.c_str(), "-allphone",
    lm.c_str(), "-backtrace", "yes", "-beam", "1e-20", "-pbeam", "1e-20", "-lw", weight.c_str(),
    "-allphone_ci", "yes", "-logfn", "/dev/null", nullptr);
  if (!config)
  {
    throw InputError("PocketSphinx rejected its configuration");
  }
  std::unique_ptr<cmd_ln_t, int (*)(cmd_ln_t*)> configGuard(config, cmd_ln_free_r);
  ps_decoder_t* decoder = ps_init(config);
  if (!decoder)
  {
    throw InputError("PocketSphinx failed to load its model from '" + folder + "'");
  }
  std::unique_ptr<ps_decoder_t, int (*)(ps_decoder_t*)> decoderGuard(decoder, ps_free);

  const AudioBuffer mono = Resample(MixToMono(recording), 16000, ResampleQuality::Medium);
  const std::vector<int16_t> samples = ToInt16Mono(mono);
  PhonemeRecognition result;
  result.Duration = recording.GetDuration();
  if (ps_start_utt(decoder) < 0)
  {
    throw InputError("PocketSphinx failed to start decoding");
  }
  const size_t block = 16000; // one second at a time, for progress and cancellation
  for (size_t at = 0; at < samples.size(); at += block)
  {
    const size_t n = std::min(block, samples.size() - at);
    if (ps_process_raw(decoder, samples.data() + at, n, FALSE, FALSE) < 0)
    {
      throw InputError("PocketSphinx failed while decoding");
    }
    if (options.Progress && !options.Progress(0.95 * static_cast<double>(at + n) / samples.size()))
    {
      ps_end_utt(decoder);
      throw InputError("recognition cancelled");
    }
  }
  ps_end_utt(decoder);
  const double frameSeconds = 0.01; // PocketSphinx's frame rate is 100 per second
  for (ps_seg_t* seg = ps_seg_iter(decoder); seg; seg = ps_seg_next(seg))
  {
    int first = 0, last = 0;
    ps_seg_frames(seg, &first, &last);
    const char* label = ps_seg_word(seg);
    TimedPhoneme p;
    const std::string name = label ? label : "";
    p.Sampa = (name.empty() || name[0] == '+' || name == "SIL" || name == "<s>" || name == "</s>")
      ? std::string("_")
      : ArpabetToSampa(name);
    p.Start = first * frameSeconds;
    const double end = (last + 1) * frameSeconds;
    if (!(end > p.Start))
    {
      continue;
    }
    p.Duration = end - p.Start;
    if (!result.Phonemes.empty())
    {
      // Keep the tiling exact: start where the previous one ended.
      TimedPhoneme& previous = result.Phonemes.back();
      previous.Duration = std::max(0.0, p.Start - previous.Start);
      if (p.Sampa == "_" && previous.Sampa == "_")
      {
        previous.Duration = end - previous.Start;
        continue;
      }
    }
    result.Phonemes.push_back(std::move(p));
  }
  const bool anySpeech = std::any_of(result.Phonemes.begin(), result.Phonemes.end(),
    [](const TimedPhoneme& p) { return p.Sampa != "_"; });
  if (!anySpeech)
  {
    throw InputError("no speech recognized in the recording (silence or noise only?)");
  }
  if (result.Phonemes.front().Start > 0.0)
  {
    TimedPhoneme pause;
    pause.Sampa = "_";
    pause.Duration = result.Phonemes.front().Start;
    result.Phonemes.insert(result.Phonemes.begin(), pause);
  }
  TimedPhoneme& lastPhoneme = result.Phonemes.back();
  lastPhoneme.Duration = std::max(lastPhoneme.Duration, result.Duration - lastPhoneme.Start);
  if (options.Progress)
  {
    options.Progress(1.0);
  }
  return result;
#else
  (void)options;
  throw InputError("phoneme recognition needs PocketSphinx, and this MorphNode was built without "
                   "it (MORPHNODE_ENABLE_POCKETSPHINX=OFF): give a transcript or a timing file");
#endif
}
} // namespace morphnode
