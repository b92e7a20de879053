// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The viseme tables of speech/data compiled into the library (BuiltinVisemeTables.cpp).

namespace morphnode
{
namespace speech_detail
{
/// The JSON text of speech/data/visemes_<key>.json (key e.g. "oculus15_en"); nullptr if none.
const char* BuiltinVisemeTableJson(const char* key);
} // namespace speech_detail
} // namespace morphnode
