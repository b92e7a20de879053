// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the rig JSON reader (Rig::LoadString), then binding the rig to exactly the
// targets it names and expanding all shapes at weight 1.
#include "base/Error.h"
#include "rig/Rig.h"

#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    morphnode::Rig rig = morphnode::Rig::LoadString(text, "fuzz");
    if (rig.GetName().empty() || rig.GetShapeNames().size() != rig.GetNumberOfShapes())
    {
      std::abort();
    }
    // Every set names shapes the rig has (the reader promised).
    for (const auto& setName : rig.GetSetNames())
    {
      for (const auto& member : rig.GetSet(setName))
      {
        if (rig.FindShape(member) < 0)
        {
          std::abort();
        }
      }
    }
    // Bind to the targets the rig itself uses: Validate must accept them.
    std::vector<std::string> targets;
    std::set<std::string> seen;
    for (size_t s = 0; s < rig.GetNumberOfShapes(); ++s)
    {
      if (rig.FindShape(rig.GetShapeNames()[s]) != static_cast<int>(s))
      {
        std::abort(); // shape names are unique
      }
      for (const auto& term : rig.GetShapeTerms(s))
      {
        if (seen.insert(term.Target).second)
        {
          targets.push_back(term.Target);
        }
      }
    }
    rig.Bind(targets);
    const std::vector<double> out = rig.Expand(std::vector<double>(rig.GetNumberOfShapes(), 1.0));
    if (out.size() != targets.size())
    {
      std::abort();
    }
    for (double w : out)
    {
      if (!(w >= 0.0 && w <= 1.0))
      {
        std::abort(); // Expand clamps to [0, 1]; NaN must not get through
      }
    }
  }
  catch (const morphnode::InputError&)
  {
    // rejected input is fine
  }
  return 0;
}
