// For tests: the message of the InputError a call throws, or "" when it throws none.
#pragma once
#include <functional>
#include <string>

#include "base/errors.h"

namespace hb {

inline std::string inputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace hb
