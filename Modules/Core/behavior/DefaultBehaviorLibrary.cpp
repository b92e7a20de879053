// SPDX-License-Identifier: BSD-3-Clause
// The built-in behaviour library: behavior/data/behavior.json, a raw string literal made by
// morphnode_embed_json (Modules/Core/CMakeLists.txt).
namespace morphnode
{
namespace behavior_detail
{
const char* DefaultBehaviorLibraryJson()
{
  return
#include "behavior.json.inc"
    ;
}
} // namespace behavior_detail
} // namespace morphnode
