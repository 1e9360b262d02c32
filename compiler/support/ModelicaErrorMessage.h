// The message of a ModelicaError raised by external C code (MLS 12.9.6).
// ldaec's ModelicaUtilities (frontend/ModelicaUtilitiesSource.cpp) keeps
// it per thread and makes the wrapper that called the code return NaN
// outputs; whoever reports the failed call (the compiler's evaluator, the
// runtime's failure report) takes it from there. The object is loaded
// RTLD_GLOBAL by ldaec or linked into an emitted program, so the symbol is
// found by name; without it there is no message.
#pragma once

#include <dlfcn.h>

#include <string>

namespace ldae {

/// The message of the last ModelicaError on this thread, once; "" if none.
inline std::string takeModelicaError() {
  using Take = const char *(*)();
  auto take =
      reinterpret_cast<Take>(dlsym(RTLD_DEFAULT, "ldae_modelica_take_error"));
  const char *message = take ? take() : nullptr;
  return message ? message : "";
}

} // namespace ldae
