// SPDX-License-Identifier: BSD-3-Clause
#include "Framing.h"

#include <algorithm>

namespace morphnode
{
namespace appkit
{
void FramingBox(
  const double head[6], const double all[6], const std::string& framing, double box[6])
{
  const double h = head[3] - head[2];
  const double w = std::max(head[1] - head[0], 0.75 * h);
  const double cx = 0.5 * (head[0] + head[1]);
  if (framing == "body")
  {
    const double height = all[3] - all[2];
    const double b[6] = { all[0], all[1], all[2] - 0.2 * height, all[3] + 0.18 * height, all[4],
      all[5] };
    std::copy(b, b + 6, box);
    return;
  }
  const bool bust = framing == "bust";
  const double below = bust ? 1.5 * h : 0.45 * h;
  const double half = bust ? 1.6 * w : 0.6 * w;
  const double above = bust ? 0.25 * h : 0.15 * h;
  const double b[6] = { cx - half, cx + half, head[2] - below, head[3] + above, head[4], head[5] };
  std::copy(b, b + 6, box);
}
} // namespace appkit
} // namespace morphnode
