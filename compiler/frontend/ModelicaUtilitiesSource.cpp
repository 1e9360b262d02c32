// The C text of ldaec's ModelicaUtilities.h callbacks (MLS 12.9.6), compiled
// into every shared object of the Modelica libraries' C sources
// (ExternalLibraries.h), so no symbol of the ldaec process needs exporting.
// ModelicaError and its formatting variants end the call through the hook
// ldaec sets after loading (`ldae_modelica_error`): they never return.
#include "frontend/ExternalLibraries.h"

namespace ldae::frontend {

const char *modelicaUtilitiesSource() {
  return R"C(
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void (*ldae_modelica_error)(const char *message) = 0;

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
  if (ldae_modelica_error)
    ldae_modelica_error(string);
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
