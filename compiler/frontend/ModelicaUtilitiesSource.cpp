// The C text of ldaec's ModelicaUtilities.h callbacks (MLS 12.9.6), compiled
// into every shared object of the Modelica libraries' C sources
// (ExternalLibraries.h), so no symbol of the ldaec process needs exporting.
// ModelicaError and its formatting variants never return: they keep the
// message (per thread) and jump back to the wrapper that made the call
// (`ldae_modelica_guard`, set by every wrapper ExternalFunctions.cpp
// generates), which returns NaN outputs, so the call is a domain error of
// its equation and the run ends located, with its rows, or the compiler
// reports the call. `ldae_modelica_take_error` hands the message to whoever
// reports it (ir/External.h, the runtime's failure report).
#include "frontend/ExternalLibraries.h"

namespace ldae::frontend {

const char *modelicaUtilitiesSource() {
  return R"C(
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

__thread jmp_buf *ldae_modelica_guard = 0;
static __thread char ldae_modelica_text[2048];
static __thread int ldae_modelica_pending = 0;

/* The message of the last ModelicaError on this thread, once; 0 if none. */
const char *ldae_modelica_take_error(void) {
  if (!ldae_modelica_pending)
    return 0;
  ldae_modelica_pending = 0;
  return ldae_modelica_text;
}

static void ldae_report(const char *kind, const char *text) {
  fprintf(stderr, "%s%s\n", kind, text);
}

void ModelicaMessage(const char *string) { ldae_report("", string); }
void ModelicaVFormatMessage(const char *format, va_list args) {
  vfprintf(stderr, format, args);
}
void ModelicaFormatMessage(const char *format, ...) {
  va_list args;
  va_start(args, format);
  ModelicaVFormatMessage(format, args);
  va_end(args);
}
void ModelicaWarning(const char *string) {
  ldae_report("ldaec: warning: ", string);
}
void ModelicaVFormatWarning(const char *format, va_list args) {
  char text[2048];
  vsnprintf(text, sizeof text, format, args);
  ModelicaWarning(text);
}
void ModelicaFormatWarning(const char *format, ...) {
  va_list args;
  va_start(args, format);
  ModelicaVFormatWarning(format, args);
  va_end(args);
}
void ModelicaError(const char *string) {
  snprintf(ldae_modelica_text, sizeof ldae_modelica_text, "%s", string);
  ldae_modelica_pending = 1;
  if (ldae_modelica_guard)
    longjmp(*ldae_modelica_guard, 1);
  /* Not under a wrapper: nothing to return to. */
  ldae_report("ldaec: error: ", string);
  exit(3);
}
void ModelicaVFormatError(const char *format, va_list args) {
  char text[2048];
  vsnprintf(text, sizeof text, format, args);
  ModelicaError(text);
}
void ModelicaFormatError(const char *format, ...) {
  va_list args;
  va_start(args, format);
  ModelicaVFormatError(format, args);
  va_end(args);
}
char *ModelicaAllocateStringWithErrorReturn(size_t len) {
  /* Strings live until the process ends: a call's results are read
     after it returns, and there is no per-call arena to free them with. */
  char *s = (char *)malloc(len + 1);
  if (s)
    s[len] = '\0';
  return s;
}
char *ModelicaAllocateString(size_t len) {
  char *s = ModelicaAllocateStringWithErrorReturn(len);
  if (!s)
    ModelicaError("out of memory allocating a string");
  return s;
}
char *ModelicaDuplicateStringWithErrorReturn(const char *str) {
  size_t len = strlen(str);
  char *s = ModelicaAllocateStringWithErrorReturn(len);
  if (s)
    memcpy(s, str, len);
  return s;
}
char *ModelicaDuplicateString(const char *str) {
  char *s = ModelicaDuplicateStringWithErrorReturn(str);
  if (!s)
    ModelicaError("out of memory allocating a string");
  return s;
}
)C";
}

} // namespace ldae::frontend
