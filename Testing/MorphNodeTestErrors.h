// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The message of the InputError a call throws, for tests that check that bad input gets a
// clear error naming the place.

#include "base/Error.h"

#include <string>
#include <utility>

namespace morphnode_test
{
/// The what() of the morphnode::InputError `f` throws; "(no error)" when it throws none.
template <typename F>
std::string ErrorOf(F&& f)
{
  try
  {
    std::forward<F>(f)();
  }
  catch (const morphnode::InputError& e)
  {
    return e.what();
  }
  return "(no error)";
}
} // namespace morphnode_test
