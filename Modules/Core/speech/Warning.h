// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Warning.h
/// @brief How the speech core reports problems that are not errors (an unknown phoneme, ...):
/// a callback receiving one human-readable message per problem.

#include <functional>
#include <string>
#include <vector>

namespace morphnode
{
/// Receives one warning message. An empty handler drops warnings.
using WarningHandler = std::function<void(const std::string& message)>;

/// A handler that appends every message to `list` (which must outlive the handler).
inline WarningHandler CollectWarnings(std::vector<std::string>& list)
{
  return [&list](const std::string& message) { list.push_back(message); };
}
} // namespace morphnode
