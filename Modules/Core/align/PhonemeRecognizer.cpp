// SPDX-License-Identifier: BSD-3-Clause
#include "align/PhonemeRecognizer.h"

#include "audio/Resample.h"
#include "base/Error.h"
#include "speech/PhoneSets.h"

#if MORPHNODE_HAVE_POCKETSPHINX
#include <pocketsphinx.h>
#include <sphinxbase/ckd_alloc.h>
#include <sphinxbase/fsg_model.h>
#endif

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace morphnode
{
#if MORPHNODE_HAVE_POCKETSPHINX
namespace
{
/// PocketSphinx's English model files in the options' folder (or the build's default):
/// the acoustic model, the phone language model of the phone loop, the word dictionary.
struct EnglishModel
{
  explicit EnglishModel(const RecognitionOptions& options)
    : Folder(options.ModelDirectory.empty() ? std::string(MORPHNODE_POCKETSPHINX_MODEL_DIR)
                                            : options.ModelDirectory)
    , Hmm((std::filesystem::path(Folder) / "en-us").string())
    , PhoneLm((std::filesystem::path(Folder) / "en-us-phone.lm.bin").string())
    , Dictionary((std::filesystem::path(Folder) / "cmudict-en-us.dict").string())
  {
  }
  /// The acoustic model and the phone language model exist (the phone loop's search).
  bool HasPhoneLoop() const
  {
    std::error_code ignored;
    return std::filesystem::is_directory(this->Hmm, ignored) &&
      std::filesystem::is_regular_file(this->PhoneLm, ignored);
  }
  /// The word dictionary exists (a transcript's words).
  bool HasDictionary() const
  {
    std::error_code ignored;
    return std::filesystem::is_regular_file(this->Dictionary, ignored);
  }

  std::string Folder;
  std::string Hmm;
  std::string PhoneLm;
  std::string Dictionary;
};
} // namespace
#endif

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
  const EnglishModel model(options);
  if (!model.HasPhoneLoop())
  {
    throw InputError("phoneme recognition needs the PocketSphinx en-us model: '" + model.Hmm +
      "' and '" + model.PhoneLm + "' (Debian: pocketsphinx-en-us)");
  }
  const std::string weight = std::to_string(options.LanguageWeight);
  cmd_ln_t* config = cmd_ln_init(nullptr, ps_args(), TRUE, "-hmm", model.Hmm.c_str(), "-allphone",
    model.PhoneLm.c_str(), "-backtrace", "yes", "-beam", "1e-20", "-pbeam", "1e-20", "-lw",
    weight.c_str(), "-allphone_ci", "yes", "-logfn", "/dev/null", nullptr);
  if (!config)
  {
    throw InputError("PocketSphinx rejected its configuration");
  }
  std::unique_ptr<cmd_ln_t, int (*)(cmd_ln_t*)> configGuard(config, cmd_ln_free_r);
  ps_decoder_t* decoder = ps_init(config);
  if (!decoder)
  {
    throw InputError("PocketSphinx failed to load its model from '" + model.Folder + "'");
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

TranscriptFit FitTranscript(
  const AudioBuffer& recording, const std::string& transcript, const RecognitionOptions& options)
{
  if (recording.IsEmpty() || recording.SampleRate <= 0)
  {
    throw InputError("the recording is empty");
  }
  // The transcript's words as the dictionary spells them: lower case, letters and '.
  std::vector<std::string> words(1);
  for (char c : transcript)
  {
    const unsigned char u = static_cast<unsigned char>(c);
    if (std::isalpha(u) || (c == '\'' && !words.back().empty()))
    {
      words.back() += static_cast<char>(std::tolower(u));
    }
    else if (u >= 0x80 || std::isdigit(u))
    {
      throw InputError("the transcript has characters the English dictionary does not spell");
    }
    else if (!words.back().empty())
    {
      words.emplace_back();
    }
  }
  if (words.back().empty())
  {
    words.pop_back();
  }
  if (words.empty())
  {
    throw InputError("the transcript has no words");
  }
#if MORPHNODE_HAVE_POCKETSPHINX
  const EnglishModel model(options);
  if (!model.HasPhoneLoop() || !model.HasDictionary())
  {
    throw InputError("the transcript check needs the PocketSphinx en-us model in '" + model.Folder +
      "' (Debian: pocketsphinx-en-us)");
  }
  // The phone loop is the recognizer's search (RecognizePhonemes); the forced path a
  // grammar of the transcript's words in order (pauses and breath between words are the
  // decoder's own fillers).
  // Loading the model and the dictionary takes about a second: one decoder per model
  // folder is kept for the process (PocketSphinx decoders are not thread-safe: a lock).
  // Beams of 1e-10: the phone loop is the costly search (0.2 s of a core per second of
  // speech at 1e-10, 5x that at 1e-20); 1e-8 already spoils it (a wrong transcript then
  // fits better than the pruned free decode), 1e-10 separates the cards set as 1e-20 does
  // (docs/speech.md).
  struct Decoder
  {
    std::unique_ptr<cmd_ln_t, int (*)(cmd_ln_t*)> Config{ nullptr, cmd_ln_free_r };
    std::unique_ptr<ps_decoder_t, int (*)(ps_decoder_t*)> Ps{ nullptr, ps_free };
    /// The last recording's free decode (the costly part): several transcripts tried on
    /// one recording decode it once.
    std::vector<int16_t> LastSamples;
    long long LastLoop = 0;
    int LastFrames = 0;
  };
  static std::mutex lock;
  static std::map<std::string, Decoder> decoders;
  std::lock_guard<std::mutex> hold(lock);
  Decoder& cached = decoders[model.Folder];
  if (!cached.Ps)
  {
    cached.Config.reset(cmd_ln_init(nullptr, ps_args(), TRUE, "-hmm", model.Hmm.c_str(), "-dict",
      model.Dictionary.c_str(), "-allphone", model.PhoneLm.c_str(), "-backtrace", "yes", "-beam",
      "1e-10", "-pbeam", "1e-10", "-wbeam", "1e-10", "-lw", "2.0", "-remove_noise", "no", "-logfn",
      "/dev/null", nullptr));
    if (!cached.Config)
    {
      throw InputError("PocketSphinx rejected its configuration");
    }
    cached.Ps.reset(ps_init(cached.Config.get()));
    if (!cached.Ps)
    {
      throw InputError("PocketSphinx failed to load its model from '" + model.Folder + "'");
    }
    // Results must not depend on what was decoded before: without noise removal (its
    // estimate carries over from one utterance to the next) only the decoder's first
    // utterance differs from all later ones; a warm-up utterance takes that place.
    std::vector<int16_t> warmUp(8000);
    for (size_t i = 0; i < warmUp.size(); ++i)
    {
      warmUp[i] = static_cast<int16_t>(3000.0 * std::sin(0.07 * static_cast<double>(i)));
    }
    ps_start_utt(cached.Ps.get());
    ps_process_raw(cached.Ps.get(), warmUp.data(), warmUp.size(), FALSE, TRUE);
    ps_end_utt(cached.Ps.get());
  }
  ps_decoder_t* decoder = cached.Ps.get();
  ps_set_search(decoder, "_default"); // the phone loop, -allphone (after an earlier transcript)
  ps_unset_search(decoder, "transcript");
  for (const std::string& w : words)
  {
    char* phones = ps_lookup_word(decoder, w.c_str()); // the caller frees it
    if (!phones)
    {
      throw InputError("'" + w + "' is not in the English dictionary");
    }
    ckd_free(phones);
  }
  const AudioBuffer mono = Resample(MixToMono(recording), 16000, ResampleQuality::Medium);
  const std::vector<int16_t> samples = ToInt16Mono(mono);
  // The acoustic cost of the best path of the active search; false: no path to its end.
  const auto decode = [&](long long& cost, int& frames)
  {
    if (ps_start_utt(decoder) < 0 ||
      ps_process_raw(decoder, samples.data(), samples.size(), FALSE, TRUE) < 0)
    {
      throw InputError("PocketSphinx failed while decoding");
    }
    ps_end_utt(decoder);
    frames = ps_get_n_frames(decoder);
    int32 best = 0;
    if (!ps_get_hyp(decoder, &best))
    {
      return false;
    }
    cost = 0;
    for (ps_seg_t* seg = ps_seg_iter(decoder); seg; seg = ps_seg_next(seg))
    {
      int32 acoustic = 0, language = 0, backoff = 0;
      ps_seg_prob(seg, &acoustic, &language, &backoff);
      cost -= acoustic;
    }
    return true;
  };
  TranscriptFit fit;
  long long loop = 0, forced = 0;
  if (samples == cached.LastSamples)
  {
    loop = cached.LastLoop;
    fit.Frames = cached.LastFrames;
  }
  else
  {
    cached.LastSamples.clear();
    if (!decode(loop, fit.Frames) || loop <= 0)
    {
      throw InputError("no speech recognized in the recording (silence or noise only?)");
    }
    cached.LastSamples = samples;
    cached.LastLoop = loop;
    cached.LastFrames = fit.Frames;
  }
  // The grammar: a chain of the words, state i to i + 1 by word i (the search adds the
  // fillers and alternative pronunciations). Built directly, not parsed from JSGF text:
  // sphinxbase's JSGF parser leaks its tokens.
  const int32 states = static_cast<int32>(words.size()) + 1;
  fsg_model_t* chain = fsg_model_init("transcript", ps_get_logmath(decoder),
    static_cast<float32>(cmd_ln_float32_r(cached.Config.get(), "-lw")), states);
  for (size_t i = 0; i < words.size(); ++i)
  {
    fsg_model_trans_add(chain, static_cast<int32>(i), static_cast<int32>(i + 1), 0,
      fsg_model_word_add(chain, words[i].c_str()));
  }
  chain->start_state = 0;
  chain->final_state = states - 1;
  const int added = ps_set_fsg(decoder, "transcript", chain); // it keeps its own reference
  fsg_model_free(chain);
  if (added < 0 || ps_set_search(decoder, "transcript") < 0)
  {
    throw InputError("PocketSphinx rejected the transcript's grammar");
  }
  fit.Completed = decode(forced, fit.Frames);
  fit.Ratio = fit.Completed ? static_cast<double>(forced) / static_cast<double>(loop) : 0.0;
  return fit;
#else
  (void)options;
  throw InputError("the transcript check needs PocketSphinx, and this MorphNode was built "
                   "without it (MORPHNODE_ENABLE_POCKETSPHINX=OFF)");
#endif
}
} // namespace morphnode
