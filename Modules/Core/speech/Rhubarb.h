// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Rhubarb.h
/// @brief Rhubarb Lip Sync's mouth cues (shapes A-F, extended G H X) in its TSV and JSON
/// exports, both ways, and the conversion to and from viseme tracks.
///
/// TSV: one `start<TAB>shape` a line, a cue lasting until the next start.
/// JSON: `{"metadata":{"soundFile":..,"duration":..},"mouthCues":[{"start":..,"end":..,
/// "value":"A"}]}`. The viseme <-> shape table lives in each viseme table (VisemeMap).

#include "speech/Coarticulation.h"
#include "speech/SpeechTypes.h"
#include "speech/VisemeMap.h"
#include "track/WeightTrack.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace morphnode
{
struct MouthCue
{
  double Start = 0.0; ///< seconds
  double End = 0.0;   ///< seconds
  char Shape = 'X';   ///< 'A'..'H' or 'X'
};

/// True for 'A'..'H' and 'X'.
bool IsRhubarbShape(char shape);

/// Reads TSV. Each cue ends where the next starts; the last ends at `endTime` when that is
/// given (>= its start), else it has zero length. InputError "rhubarb tsv line <n>: ..."
/// for a malformed line, an unknown shape or starts that decrease.
std::vector<MouthCue> ReadRhubarbTsv(std::istream& in, double endTime = -1.0);
/// Writes TSV; the end of the last cue is written as a final `X` unless it has zero
/// length or is an X itself (Rhubarb ends with X too). Gaps between cues become X.
void WriteRhubarbTsv(std::ostream& out, const std::vector<MouthCue>& cues);

/// Reads JSON; InputError naming the cue for missing fields, unknown shapes, end < start
/// or starts that decrease.
std::vector<MouthCue> ReadRhubarbJson(std::istream& in);
/// Writes JSON with metadata soundFile (may be empty) and duration (the last end when < 0).
void WriteRhubarbJson(std::ostream& out, const std::vector<MouthCue>& cues,
  const std::string& soundFile = "", double duration = -1.0);

/// Reads XML (`rhubarb --exportFormat xml`): `<rhubarbResult><metadata>..</metadata>
/// <mouthCues><mouthCue start="0.00" end="0.23">X</mouthCue>..</mouthCues></rhubarbResult>`,
/// parsed with expat (Debian's libexpat1-dev). InputError naming the line for malformed XML,
/// a missing or bad start/end, an unknown shape, end < start or starts that decrease.
std::vector<MouthCue> ReadRhubarbXml(std::istream& in);

/// Reads any export: JSON when the first non-blank character is '{', XML when it is '<',
/// else TSV (the last TSV cue then has zero length, as Rhubarb ends with an X). InputError
/// as the readers.
std::vector<MouthCue> ParseRhubarb(const std::string& text);
/// Same from a file; InputError naming the file when it cannot be opened or is malformed.
std::vector<MouthCue> ReadRhubarbFile(const std::string& path);

/// The dominant viseme of each frame as a shape; equal neighbours merge. Cues shorter than
/// `minimumDuration` merge into the previous cue, except closures (A), which Rhubarb too
/// keeps however short they are.
std::vector<MouthCue> VisemeTrackToMouthCues(
  const WeightTrack& visemes, const VisemeMap& map, double minimumDuration = 0.0);

/// Mouth cues as viseme segments (through the table's shape -> viseme entries), to blend
/// with Coarticulate. A-cues are closures. InputError for a shape the table lacks.
std::vector<VisemeSegment> MouthCuesToVisemeSegments(
  const std::vector<MouthCue>& cues, const VisemeMap& map);
} // namespace morphnode
